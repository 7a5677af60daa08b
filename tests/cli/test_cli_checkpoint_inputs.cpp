// `run --resume` as a user meets it when something besides the mesh has changed or is odd: a
// face-list or weights file edited since the checkpoint (refused, exit 2, naming the file), a
// folder given as the checkpoint (exit 2, "it is a folder"), and a checkpoint that Python wrote
// from arrays, resumed without INPUT (exit 1, saying to give INPUT). Each failed before its fix
// as its comment says.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "sim/checkpoint.hpp"
#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

class CliResumeInputs : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_resume_inputs_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string out(const std::string& name) { return (dir_ / name).string(); }
  static std::string mesh(const std::string& name) { return std::string(test::MESH_DIR) + "/" + name; }
  static void write(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  }
  static std::string read(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  /// A finished run of ico2 with `extra`, saving every 4 frames: its checkpoint is at frame 8.
  void checkpointed_run(const std::vector<std::string>& extra) {
    std::vector<std::string> args{"run", mesh("ico2.off"), "-o", out("whole.off"), "-q", "--frames", "10",
                                  "--pressure", "0", "--checkpoint", out("c.ckpt"), "--checkpoint-every", "4"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    ASSERT_TRUE(fs::exists(out("c.ckpt")));
  }
  fs::path dir_;
};

// Before: exit 0, the resumed frames run with the new regions (a result that matched neither run).
TEST_F(CliResumeInputs, AFaceListEditedSinceTheCheckpointIsRefusedNamingIt) {
  write(out("reg.txt"), "0 1 2 3 4\n");
  checkpointed_run({"--regions", out("reg.txt")});
  write(out("reg.txt"), "40 41 42 43 44\n");
  const auto r = run_cli({"run", "--resume", out("c.ckpt"), "-o", out("r.off")});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("another input: --regions " + out("reg.txt") + " has changed"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(out("r.off")));
  // Put back, the run resumes to the uninterrupted run's bytes.
  write(out("reg.txt"), "0 1 2 3 4\n");
  const auto back = run_cli({"run", "--resume", out("c.ckpt"), "-o", out("r.off"), "-q"});
  ASSERT_EQ(back.exit_code, 0) << back.output;
  EXPECT_EQ(read(out("r.off")), read(out("whole.off")));
}

// Before: exit 0, as for the face list.
TEST_F(CliResumeInputs, AWeightsFileEditedSinceTheCheckpointIsRefusedNamingIt) {
  std::string weights;
  for (int v = 0; v < 162; ++v) weights += v < 5 ? "1\n" : "0\n";  // ico2: 162 vertices
  write(out("w.txt"), weights);
  checkpointed_run({"--region-weights", out("w.txt")});
  write(out("w.txt"), "0.25\n" + weights.substr(2));
  const auto r = run_cli({"run", mesh("ico2.off"), "--resume", out("c.ckpt"), "-o", out("r.off")});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--region-weights " + out("w.txt") + " has changed"), std::string::npos) << r.output;
}

// Before: exit 3 ("simulation failed"), "basic_filebuf::underflow error reading the file: Is a
// directory".
TEST_F(CliResumeInputs, AFolderAsTheCheckpointIsBadInputNamedAsAFolder) {
  const auto r = run_cli({"run", "--resume", dir_.string(), "-o", out("x.off")});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("checkpoint " + dir_.string() + ": cannot open file: it is a folder"), std::string::npos)
      << r.output;
}

// Before: "<arrays>: cannot open file: no such file" (exit 2), as if "<arrays>" were a file name.
TEST_F(CliResumeInputs, ACheckpointOfArraysWithoutInputSaysToGiveInput) {
  checkpointed_run({});
  Checkpoint c = read_checkpoint(out("c.ckpt"));
  c.input = "<arrays>";  // what Python's contract(V, F, checkpoint=...) records
  write_checkpoint(out("py.ckpt"), c);
  const auto r = run_cli({"run", "--resume", out("py.ckpt"), "-o", out("x.off")});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("given as arrays (Python)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("shellcontract run INPUT --resume " + out("py.ckpt") + " -o OUTPUT"), std::string::npos)
      << r.output;
  // With INPUT it resumes.
  const auto with_input = run_cli({"run", mesh("ico2.off"), "--resume", out("py.ckpt"), "-o", out("x.off"), "-q"});
  EXPECT_EQ(with_input.exit_code, 0) << with_input.output;
  EXPECT_EQ(read(out("x.off")), read(out("whole.off")));
}

// Before: exit 0, and the checkpoint was the log's CSV (or the summary's JSON): resuming it again
// failed with "not a shellcontract checkpoint", the run's saved state lost.
TEST_F(CliResumeInputs, NoOutputButCheckpointMayBeTheResumedCheckpoint) {
  checkpointed_run({});
  const std::string saved = read(out("c.ckpt"));
  fs::create_symlink(out("c.ckpt"), out("link.ckpt"));
  for (const char* option : {"--log", "--summary"})
    for (const std::string& target : {out("c.ckpt"), out("link.ckpt")}) {
      const auto r = run_cli({"run", "--resume", out("c.ckpt"), "-o", out("r.off"), option, target, "-q"});
      EXPECT_EQ(r.exit_code, 1) << option << " " << target << ": " << r.output;
      EXPECT_NE(r.output.find(option), std::string::npos) << r.output;
      EXPECT_NE(r.output.find("--resume"), std::string::npos) << r.output;
      EXPECT_FALSE(fs::exists(out("r.off")));
      EXPECT_EQ(read(out("c.ckpt")), saved) << option << " " << target;
    }
  // --checkpoint on the resumed file goes on saving there, as before.
  const auto same = run_cli({"run", "--resume", out("c.ckpt"), "-o", out("r.off"), "--checkpoint",
                             out("link.ckpt"), "-q"});
  EXPECT_EQ(same.exit_code, 0) << same.output;
  EXPECT_EQ(read(out("r.off")), read(out("whole.off")));
}

}  // namespace
}  // namespace shellcontract
