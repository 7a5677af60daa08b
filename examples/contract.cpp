// Contracts a mesh through the library's entry point and prints each frame's V/V0.
//   contract INPUT OUTPUT [FRAMES]
// The options are set as text through the option table, exactly as `shellcontract run` does, and
// the exit codes are the CLI's (README, "Exit codes"): 1 bad usage, 2 an unusable input, 3-5 the
// run's own.
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/output_files.hpp"
#include "shellcontract/run.hpp"

namespace sc = shellcontract;

/// Prints one progress line per frame.
class Progress final : public sc::RunObserver {
 public:
  void warning(const std::string& text) override {
    std::printf("warning: %s\n", sc::spell_options(text, sc::OptionSpelling::Cli).c_str());
  }
  void frame(const sc::FrameView&, const sc::FrameMetrics& m) override {
    std::printf("frame %d  V/V0 %.6f  step %.2f ms\n", m.frame, m.volume_ratio, 1e3 * m.step_seconds);
  }
};

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s INPUT OUTPUT [FRAMES]\n", argv[0]);
    return 1;
  }
  sc::RunOptions options;
  try {
    sc::set_run_option(options, "frames", argc > 3 ? argv[3] : "20");
    sc::set_run_option(options, "target-volume", "0.8");
    sc::set_run_option(options, "target-ramp", "10");
    // Before any work: an output that cannot be written (or would replace the input) is found
    // now, not after the run.
    sc::check_output_files({{"OUTPUT", argv[2]}}, {{"INPUT", argv[1]}});
  } catch (const sc::UsageError& e) {  // the message names the option (`frames`) or the file
    std::fprintf(stderr, "contract: %s\n",
                 sc::spell_options(e.what(), sc::OptionSpelling::Cli).c_str());
    return 1;
  }
  try {
    const sc::Mesh mesh = sc::read_input_mesh(argv[1]);
    Progress progress;
    const sc::RunResult result = sc::run_contraction(mesh, options, &progress);
    sc::write_mesh_atomic(argv[2], mesh, result.positions);
    std::printf("%d frames, V/V0 = %.6f, exit code %d\n", result.frames_run, result.final_volume_ratio,
                result.exit_code());
    return result.exit_code();
  } catch (const sc::InputError& e) {  // the message says what and where (file, line, face)
    std::fprintf(stderr, "contract: %s\n", e.what());
    return 2;
  } catch (const sc::UsageError& e) {  // a write that failed after the check
    std::fprintf(stderr, "contract: %s\n",
                 sc::spell_options(e.what(), sc::OptionSpelling::Cli).c_str());
    return 1;
  } catch (const std::bad_alloc& e) {  // memory ran out (an input larger than memory too)
    std::fprintf(stderr, "contract: out of memory (%s)\n", e.what());
    return 3;
  } catch (const std::exception& e) {  // a resource the system refused: a thread, an open file
    std::fprintf(stderr, "contract: %s\n", e.what());
    return 3;
  }
}
