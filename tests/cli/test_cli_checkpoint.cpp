// `run --checkpoint` and `run --resume` as a user meets them: a run killed with SIGKILL at a
// random frame and resumed from its checkpoint writes the same mesh, byte for byte, the same log
// rows and the same summary (timings apart) as the run never killed; SIGTERM saves and stops
// with exit code 130 and no other output; a checkpoint of another input or other options is
// refused, saying which.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "sim/checkpoint.hpp"
#include "support/child_process.hpp"
#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

/// Starts the CLI with `args` (output to /dev/null).
test::Child spawn_cli(const std::vector<std::string>& args) {
  test::ChildSpec spec = test::cli_child(args);
  spec.err = test::ChildErr::DevNull;
  return test::Child(spec);
}

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The log without its timing columns (step_ms, solve_ms, ccd_ms: the 8th to 10th).
std::string log_without_times(const std::string& csv) {
  std::istringstream in(csv);
  std::string line, out;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    for (std::size_t c = 0; c < cells.size(); ++c)
      if (c < 7 || c > 9) out += cells[c] + ",";
    out += "\n";
  }
  return out;
}

/// The summary without the lines that are times, memory, file names or the thread count.
std::string summary_without_times(const std::string& json) {
  std::istringstream in(json);
  std::string line, out;
  while (std::getline(in, line))
    if (line.find("seconds") == std::string::npos && line.find("_ms") == std::string::npos &&
        line.find("_s\"") == std::string::npos && line.find("memory") == std::string::npos &&
        line.find("\"output\"") == std::string::npos &&
        line.find("\"input\"") == std::string::npos &&
        line.find("\"path\"") == std::string::npos &&  // input_file's: its bytes are compared
        line.find("\"threads") == std::string::npos)  // the option and the count the run had
      out += line + "\n";
  return out;
}

class CliCheckpoint : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_checkpoint_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string out(const std::string& name) { return (dir_ / name).string(); }
  std::string mesh(const std::string& name) { return std::string(test::MESH_DIR) + "/" + name; }
  // Deep enough that the shell meets itself: contacts and the warm start's cache at the kill.
  std::vector<std::string> options() {
    return {"--target-volume", "0.25", "--target-ramp", "40", "--frames", "120", "--threads", "2"};
  }
  std::vector<std::string> whole_run() {
    std::vector<std::string> a{"run", mesh("ico3.off"), "-o", out("whole.off"), "--log",
                               out("whole.csv"), "--summary", out("whole.json"), "-q"};
    for (const std::string& o : options()) a.push_back(o);
    return a;
  }
  void expect_equals_whole(const std::string& name) {
    EXPECT_EQ(read(out(name + ".off")), read(out("whole.off"))) << "the meshes differ";
    EXPECT_EQ(log_without_times(read(out(name + ".csv"))), log_without_times(read(out("whole.csv"))));
    EXPECT_EQ(summary_without_times(read(out(name + ".json"))),
              summary_without_times(read(out("whole.json"))));
  }
  fs::path dir_;
};

TEST_F(CliCheckpoint, KilledAtARandomFrameAndResumedEqualsTheWholeRun) {
  // The whole run's duration bounds the random wait below, so that the kill lands inside the run
  // on a fast machine as on a loaded one.
  const auto whole_start = std::chrono::steady_clock::now();
  const auto whole = run_cli(whole_run());
  const auto whole_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                            std::chrono::steady_clock::now() - whole_start)
                            .count();
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  std::vector<std::string> args{"run", mesh("ico3.off"), "-o", out("killed.off"), "-q",
                                "--checkpoint", out("c.ckpt"), "--checkpoint-every", "1"};
  for (const std::string& o : options()) args.push_back(o);
  std::random_device seed;
  std::mt19937 random(seed());
  test::Child run = spawn_cli(args);
  // The first checkpoint marks the first frame; then a random share of the run's time.
  const auto start = std::chrono::steady_clock::now();
  while (!fs::exists(out("c.ckpt")) && std::chrono::steady_clock::now() - start < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  const int max_wait_ms = static_cast<int>(std::min<long long>(600, whole_ms / 3));
  std::this_thread::sleep_for(
      std::chrono::milliseconds(std::uniform_int_distribution<int>(0, max_wait_ms)(random)));
  run.signal(SIGKILL);
  const int status = run.finish();
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before the kill; make it longer";
  EXPECT_FALSE(fs::exists(out("killed.off")));
  const int frame = read_checkpoint(out("c.ckpt")).sim.frame;
  std::cout << "killed after frame " << frame << " was saved\n";
  ASSERT_GT(frame, 0);
  ASSERT_LT(frame, 120);
  // Resumed at another thread count, the options taken from the checkpoint.
  const auto resumed = run_cli({"run", "--resume", out("c.ckpt"), "-o", out("resumed.off"), "--log",
                                out("resumed.csv"), "--summary", out("resumed.json"), "-q",
                                "--threads", "1"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  expect_equals_whole("resumed");
}

// The paper's sequential order turns the speculative broad phase on, whose pairs came in the
// order of the grid kept from the last step; a resumed run builds its grid afresh, so its pairs
// came in another order and it wrote other bytes (bumpy_sphere, target 0.1: every vertex, up to
// 1.9 % of the diagonal). Checkpoints at fixed frames, so that the test is the same every time.
TEST_F(CliCheckpoint, ResumedInTheSequentialOrderEqualsTheWholeRun) {
  const std::vector<std::string> common{
      "--target-volume", "0.1",        "--target-ramp", "15", "-n", "30",
      "--order",         "sequential", "--threads",     "1",  "-q"};
  std::vector<std::string> whole{"run", mesh("bumpy_sphere.off"), "-o", out("whole.off")};
  whole.insert(whole.end(), common.begin(), common.end());
  ASSERT_EQ(run_cli(whole).exit_code, 0);
  for (const char* every : {"7", "13"}) {
    SCOPED_TRACE(std::string("--checkpoint-every ") + every);
    std::vector<std::string> saved{
        "run",         mesh("bumpy_sphere.off"), "-o", out("saved.off"), "--checkpoint",
        out("c.ckpt"), "--checkpoint-every",     every};
    saved.insert(saved.end(), common.begin(), common.end());
    ASSERT_EQ(run_cli(saved).exit_code, 0);
    // The last checkpoint (frame 28 or 26) resumed at another thread count.
    const auto resumed = run_cli(
        {"run", "--resume", out("c.ckpt"), "-o", out("resumed.off"), "-q", "--threads", "2"});
    ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
    EXPECT_EQ(read(out("resumed.off")), read(out("whole.off"))) << "the meshes differ";
    fs::remove(out("c.ckpt"));
    fs::remove(out("saved.off"));
    fs::remove(out("resumed.off"));
  }
}

TEST_F(CliCheckpoint, SigtermSavesStopsWith130AndWritesNothingElse) {
  ASSERT_EQ(run_cli(whole_run()).exit_code, 0);
  std::vector<std::string> args{"run", mesh("ico3.off"), "-o", out("t.off"), "--log", out("t.csv"),
                                "--summary", out("t.json"), "-q", "--checkpoint", out("t.ckpt"),
                                "--checkpoint-every", "1"};
  for (const std::string& o : options()) args.push_back(o);
  test::Child run = spawn_cli(args);
  // The first checkpoint (after frame 1) shows the time loop is running; the signal then lands
  // inside it, however fast the machine.
  const auto start = std::chrono::steady_clock::now();
  while (!fs::exists(out("t.ckpt")) && std::chrono::steady_clock::now() - start < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  run.signal(SIGTERM);
  const int status = run.finish();
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 130) << "finished before the signal? make the run longer";
  EXPECT_FALSE(fs::exists(out("t.off")));
  EXPECT_FALSE(fs::exists(out("t.csv")));
  EXPECT_FALSE(fs::exists(out("t.json")));
  ASSERT_TRUE(fs::exists(out("t.ckpt")));
  // The options again (as a sweep gives them), another input path to the same mesh.
  fs::copy_file(mesh("ico3.off"), out("same.off"));
  std::vector<std::string> resume{"run", out("same.off"), "--resume", out("t.ckpt"), "-o",
                                  out("r.off"), "--log", out("r.csv"), "--summary", out("r.json"), "-q"};
  for (const std::string& o : options()) resume.push_back(o);
  const auto r = run_cli(resume);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_equals_whole("r");
}

// The checkpoint keeps the input path as the run was given it; resumed from another folder,
// the message says where the path came from and that INPUT can be given.
TEST_F(CliCheckpoint, ResumedElsewhereNamesTheRecordedInputPath) {
  fs::copy_file(mesh("ico2.off"), out("rel.off"));
  const auto made = test::run_command("cd " + test::quoted(dir_.string()) + " && " +
                                      test::cli_command({"run", "rel.off", "-o", "a.off", "-q", "--frames", "4",
                                                         "--checkpoint", "a.ckpt", "--checkpoint-every", "2"}));
  ASSERT_EQ(made.exit_code, 0) << made.output;
  const auto r = test::run_command("cd / && " + test::cli_command({"run", "--resume", out("a.ckpt"), "-o", out("b.off")}));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("'rel.off' recorded in checkpoint " + out("a.ckpt")), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("give the mesh as INPUT"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out("b.off")));
}

TEST_F(CliCheckpoint, RefusesAnotherInputOrOtherOptionsSayingWhich) {
  std::vector<std::string> args{"run", mesh("ico2.off"), "-o", out("a.off"), "-q", "--frames", "10",
                                "--checkpoint", out("a.ckpt"), "--checkpoint-every", "3"};
  ASSERT_EQ(run_cli(args).exit_code, 0);
  const auto other_mesh = run_cli({"run", mesh("ico1.off"), "--resume", out("a.ckpt"), "-o", out("b.off")});
  EXPECT_EQ(other_mesh.exit_code, 2) << other_mesh.output;
  EXPECT_NE(other_mesh.output.find("another input"), std::string::npos) << other_mesh.output;
  EXPECT_FALSE(fs::exists(out("b.off")));
  const auto other_options =
      run_cli({"run", "--resume", out("a.ckpt"), "-o", out("b.off"), "--frames", "20"});
  EXPECT_EQ(other_options.exit_code, 1) << other_options.output;
  EXPECT_NE(other_options.output.find("--frames 20"), std::string::npos) << other_options.output;
  const auto not_one = run_cli({"run", "--resume", mesh("ico2.off"), "-o", out("b.off")});
  EXPECT_EQ(not_one.exit_code, 2) << not_one.output;
  EXPECT_NE(not_one.output.find("not a shellcontract checkpoint"), std::string::npos);
}

}  // namespace
}  // namespace shellcontract
