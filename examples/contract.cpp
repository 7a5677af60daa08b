// Contracts a mesh through the library's entry point and prints each frame's V/V0.
//   contract INPUT OUTPUT [FRAMES]
// The options are set as text through the option table, exactly as `shellcontract run` does.
#include <cstdio>
#include <exception>
#include <string>

#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"

namespace sc = shellcontract;

/// Prints one progress line per frame.
class Progress final : public sc::RunObserver {
 public:
  void warning(const std::string& text) override { std::printf("warning: %s\n", text.c_str()); }
  void frame(const sc::FrameView&, const sc::FrameMetrics& m) override {
    std::printf("frame %d  V/V0 %.6f  step %.2f ms\n", m.frame, m.volume_ratio, 1e3 * m.step_seconds);
  }
};

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s INPUT OUTPUT [FRAMES]\n", argv[0]);
    return 1;
  }
  try {
    const sc::Mesh mesh = sc::read_input_mesh(argv[1]);
    sc::RunOptions options;
    sc::set_run_option(options, "frames", argc > 3 ? argv[3] : "20");
    sc::set_run_option(options, "target-volume", "0.8");
    sc::set_run_option(options, "target-ramp", "10");
    Progress progress;
    const sc::RunResult result = sc::run_contraction(mesh, options, &progress);
    sc::write_mesh_atomic(argv[2], mesh, result.positions);
    std::printf("%d frames, V/V0 = %.6f, exit code %d\n", result.frames_run, result.final_volume_ratio,
                result.exit_code());
    return result.exit_code();
  } catch (const std::exception& e) {  // InputError, UsageError: the message says what and where
    std::fprintf(stderr, "contract: %s\n", e.what());
    return 2;
  }
}
