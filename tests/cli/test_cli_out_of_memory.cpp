// `shellcontract run` when memory runs out (README "Exit codes": 3): a message and, once a frame
// has run, the last good state; never an abort. The memory is limited with the shell's
// `ulimit -v` (the address space, RLIMIT_AS), so that allocations fail with std::bad_alloc as
// on a machine without the memory. Where the run fails depends on the limit, and the limit a run
// needs depends on the machine, so the test finds it first and then steps below it: every run
// must end in one of the documented ways, and the steps must reach both a failure during the
// frames (the collision step's candidate pairs grow as the shell contracts) and one before them.
// Memory running out while the input is read is exit code 3 as well, with the reader's message
// naming the file: memory is short, not the file unusable (exit code 2 told a script to fix a
// file that was fine).
#include <gtest/gtest.h>
#include <stdlib.h>  // setenv: the runs' malloc arenas
#include <unistd.h>  // getpid: temporary files of this process's own

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "shellcontract/mesh_io.hpp"
#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

constexpr long FLOOR_KIB = 8 * 1024;            ///< too little to start a process
constexpr long CEILING_KIB = 8L * 1024 * 1024;  ///< more than the tests' runs need

/// Whether `output` is the reader's own out-of-memory message about `file`.
bool reading_ran_out(const std::string& output, const std::string& file) {
  return output.find(file + ": out of memory: reading it needs more memory than there is (") !=
         std::string::npos;
}

/// The least address space (KiB, to within `step`) under which the CLI with `args` succeeds;
/// -1 if not even CEILING_KIB is enough. `before` runs before each try (removes what the last
/// one wrote, where a rerun would be refused).
long least_address_space(
    const std::vector<std::string>& args, long step, const std::function<void()>& before = [] {}) {
  long lo = FLOOR_KIB, hi = CEILING_KIB;
  before();
  if (test::run_cli_limited(hi, args).exit_code != 0) return -1;
  while (hi - lo > step) {
    const long mid = lo + (hi - lo) / 2;
    before();
    (test::run_cli_limited(mid, args).exit_code == 0 ? hi : lo) = mid;
  }
  return hi;
}

std::string file_bytes(const fs::path& p) {
  std::ostringstream s;
  s << std::ifstream(p, std::ios::binary).rdbuf();
  return s.str();
}

class CliOutOfMemory : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    bear_ = std::string(test::PAPER_MESH_DIR) + "/bear.off";
    if (!fs::exists(bear_)) GTEST_SKIP() << bear_ << " absent (scripts/fetch_paper_meshes.sh)";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_oom_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  /// Sixteen threads whatever the cores: starting them (TBB's pthread_create) is also refused
  /// when the address space runs out.
  std::vector<std::string> run_args(const fs::path& out, int frames) const {
    return {"run",       bear_, "-o", out.string(), "--frames", std::to_string(frames),
            "--threads", "16",  "-q"};
  }
  std::string bear_;
  fs::path dir_;
};

TEST_F(CliOutOfMemory, RunEndsWithAMessageAndTheLastGoodStateNeverAnAbort) {
  constexpr int FRAMES = 20;
  const fs::path out = dir_ / "o.off";
  const long hi = least_address_space(run_args(out, FRAMES), 1024);
  if (hi < 0)
    GTEST_SKIP() << "the run needs more than 8 GiB of address space here (a sanitizer build "
                    "reserves terabytes of it)";
  std::printf("the run needs %ld KiB of address space\n", hi);
  // Memory, or a thread the system cannot start without it (TBB: "pthread_create has failed:
  // Resource temporarily unavailable").
  const std::regex refused("out of memory|Resource temporarily unavailable");
  const std::regex at_step("at step ([0-9]+)");
  const std::regex after_step(
      "out of memory (checking step|after step|after the last step|validating the result)");
  int in_frames = 0, before_frames = 0, checked_state = 0, threads_refused = 0;
  bool reading_failed = false;
  // Below it, 2 MiB at a time down to where reading the file fails.
  for (long kb = hi - 1024; kb > FLOOR_KIB && !reading_failed; kb -= 2048) {
    fs::remove(out);
    const test::RunResult r = test::run_cli_limited(kb, run_args(out, FRAMES));
    SCOPED_TRACE("ulimit -v " + std::to_string(kb) + ": " + r.output);
    if (r.exit_code == 0) continue;  // the need is not strictly monotone in the limit
    ASSERT_TRUE(std::regex_search(r.output, refused));
    threads_refused += r.output.find("pthread_create") != std::string::npos;
    if (reading_ran_out(r.output, bear_)) {  // the file needs more than there is
      EXPECT_EQ(r.exit_code, 3) << "memory ran out, not a bad input's 2";
      EXPECT_NE(r.output.find("nothing was written"), std::string::npos);
      EXPECT_FALSE(fs::exists(out));
      reading_failed = true;
      continue;
    }
    ASSERT_EQ(r.exit_code, 3) << "the documented exit code, not an abort";
    std::smatch m;
    if (std::regex_search(r.output, m, at_step)) {
      ++in_frames;
      const int good = std::stoi(m[1].str()) - 1;
      ASSERT_NE(r.output.find("the last good state (frame " + std::to_string(good) + ")"),
                std::string::npos);
      ASSERT_TRUE(fs::exists(out));
      InputReport report;
      const Mesh written = read_input_mesh(out.string(), &report);
      EXPECT_EQ(written.number_of_faces(), 27648u);
      if (checked_state++ == 0) {  // the same bytes as a run asked for that many frames
        const fs::path ref = dir_ / "ref.off";
        ASSERT_EQ(test::run_cli(run_args(ref, good)).exit_code, 0);
        EXPECT_EQ(file_bytes(out), file_bytes(ref));
        fs::remove(ref);
      }
    } else if (r.output.find("nothing was written") != std::string::npos) {
      EXPECT_FALSE(fs::exists(out));
      before_frames += r.output.find("preparing the run") != std::string::npos;
    } else {
      // After a whole step (its checks, the end's validation, an observer): the message says
      // so, and the state is written.
      EXPECT_TRUE(std::regex_search(r.output, after_step)) << r.output;
      EXPECT_TRUE(fs::exists(out));
    }
    // No temporary file of an atomic write is left behind.
    for (const auto& e : fs::directory_iterator(dir_))
      EXPECT_EQ(e.path().filename(), "o.off") << "left behind: " << e.path();
  }
  std::printf("failed during the frames %d times, before them %d (a thread refused %d times)\n",
              in_frames, before_frames, threads_refused);
  EXPECT_GT(in_frames, 0) << "no limit ran out of memory during the frames";
  EXPECT_GT(before_frames, 0) << "no limit ran out of memory before the first frame";
}

// The same run with every frame exported (--export-dir, --gltf), one thread, stepped down from
// the least limit it needs: wherever memory runs out, (a) frame files left behind are named with
// "remove them to rerun" (a rerun is refused while they are there), never "nothing was written"
// alone; (b) a run that itself failed says why on stderr ("simulation failed: out of memory ...")
// and exits 3 even when an output failed too; (c) the glTF is written from consistent frames or
// fails for memory, never for lists of different lengths. Before: "nothing was written" beside a
// frame file, exit 1 with the run's failure in no message, and "--gltf: failed: ... frame field
// 'mean_curvature' has 3 frames, the animation 4" (or "2 frame numbers for 1 frames").
TEST_F(CliOutOfMemory, ExportingRunSaysWhatItLeftAndWhyItFailed) {
  const fs::path frames = dir_ / "frames";
  std::vector<std::string> args = run_args(dir_ / "o.off", 3);
  args[7] = "1";  // --threads: one, so that where memory runs out depends on the limit only
  args.insert(args.end(), {"--export-dir", frames.string(), "--export-every", "1", "--gltf",
                           (dir_ / "o.glb").string()});
  const auto clean = [&] {
    fs::remove_all(frames);
    fs::remove(dir_ / "o.off");
    fs::remove(dir_ / "o.glb");
  };
  // One malloc arena: a thread's own arena (the frame writer's) reserves 64 MiB of address space
  // when it happens to be made, so without this the need varies from run to run by more than the
  // steps below, and the steps may miss the band where the frames fail.
  ::setenv("MALLOC_ARENA_MAX", "1", 1);
  struct Unset {
    ~Unset() { ::unsetenv("MALLOC_ARENA_MAX"); }
  } unset;
  const long hi = least_address_space(args, 512, clean);
  if (hi < 0) GTEST_SKIP() << "needs more than 8 GiB of address space here";
  std::printf("the exporting run needs %ld KiB of address space\n", hi);
  int failed = 0, frames_left = 0, run_failed = 0;
  for (long kb = hi - 512; kb > FLOOR_KIB && kb > hi - 24 * 1024; kb -= 1024) {
    clean();
    const test::RunResult r = test::run_cli_limited(kb, args);
    SCOPED_TRACE("ulimit -v " + std::to_string(kb) + ": " + r.output);
    if (r.exit_code == 0) continue;
    if (reading_ran_out(r.output, bear_)) {  // the file needs more than there is
      EXPECT_EQ(r.exit_code, 3);
      break;
    }
    ++failed;
    ASSERT_TRUE(r.exit_code == 1 || r.exit_code == 3) << "the documented exit codes, not an abort";
    std::size_t left = 0;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(frames, ec)) left += e.path().extension() == ".off";
    // Ended outside the frames (its outputs not written, or only some): what it left.
    const bool ended_early = r.output.find("nothing was written") != std::string::npos ||
                             std::regex_search(r.output, std::regex("; wrote .* only"));
    if (left > 0 && ended_early) {
      ++frames_left;
      EXPECT_NE(r.output.find(" in " + frames.string() + " (remove"), std::string::npos)
          << left << " frame files left and not named";
    }
    EXPECT_EQ(r.output.find("frame field"), std::string::npos);
    EXPECT_EQ(r.output.find("frame numbers for"), std::string::npos);
    if (r.output.find("(the run itself ended: failed") != std::string::npos) {
      ++run_failed;
      EXPECT_NE(r.output.find("shellcontract run: simulation failed: "), std::string::npos);
      EXPECT_EQ(r.exit_code, 3);
    }
  }
  std::printf(
      "%d runs failed, %d left frame files, %d failed in the frames with an output failed\n",
      failed, frames_left, run_failed);
  EXPECT_GT(failed, 0);
}

TEST_F(CliOutOfMemory, OtherCommandsEndWithAMessageNeverAnAbort) {
  // `check` and `regions`: an input the reader cannot hold is exit code 3 as anything later (its
  // "out of memory" message names the file); an output is written whole or not at all.
  const fs::path out = dir_ / "r.ply";
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"check", bear_},
        std::vector<std::string>{"regions", bear_, "-o", out.string()}}) {
    SCOPED_TRACE(args[0]);
    const std::regex refused("out of memory|Resource temporarily unavailable");
    const long hi = least_address_space(args, 512);
    if (hi < 0) GTEST_SKIP() << "needs more than 8 GiB of address space here";
    int failed = 0, after_reading = 0;
    // From a little above the least limit found: the need is not monotone (fewer TBB threads
    // start under a lower limit), and the binary search can land on a lower island of success
    // below a band that fails after reading.
    for (long kb = hi + 4096; kb > FLOOR_KIB && failed < 6; kb -= 512) {
      fs::remove(out);
      const test::RunResult r = test::run_cli_limited(kb, args);
      SCOPED_TRACE("ulimit -v " + std::to_string(kb) + ": " + r.output);
      if (r.exit_code == 0) continue;
      ++failed;
      ASSERT_EQ(r.exit_code, 3) << "memory ran out (reading the input too), never a bad input's 2";
      EXPECT_TRUE(std::regex_search(r.output, refused));
      if (reading_ran_out(r.output, bear_)) {
        EXPECT_NE(r.output.find("shellcontract " + args[0] + ": " + bear_ + ": out of memory"),
                  std::string::npos);
      } else {
        ++after_reading;
      }
      if (fs::exists(out)) {
        InputReport report;
        EXPECT_EQ(read_input_mesh(out.string(), &report).number_of_faces(), 27648u);
      }
    }
    EXPECT_GT(failed, 0);
    if (args[0] == "regions") {
      EXPECT_GT(after_reading, 0) << "no run failed after reading";
    }
  }
}

// Reading the input is where a command first needs memory in proportion to the mesh: stepped
// down from the least limit `check` needs until the reader runs out. Before: exit code 2, a bad
// input's, for a file that was fine.
TEST_F(CliOutOfMemory, ReadingTheInputRunsOutOfMemoryWithExitCode3) {
  const std::vector<std::string> args{"check", bear_};
  const long hi = least_address_space(args, 512);
  if (hi < 0) GTEST_SKIP() << "needs more than 8 GiB of address space here";
  bool reading_failed = false;
  for (long kb = hi - 1024; kb > FLOOR_KIB && !reading_failed; kb -= 1024) {
    const test::RunResult r = test::run_cli_limited(kb, args);
    SCOPED_TRACE("ulimit -v " + std::to_string(kb) + ": " + r.output);
    if (!reading_ran_out(r.output, bear_)) continue;
    reading_failed = true;
    EXPECT_EQ(r.exit_code, 3);
    EXPECT_NE(r.output.find("shellcontract check: " + bear_ + ": out of memory: "),
              std::string::npos);
  }
  EXPECT_TRUE(reading_failed) << "no limit ran out while the file was read";
}

}  // namespace
}  // namespace shellcontract
