// `run --resume` on a checkpoint edited by hand and resealed (tests/support/forged_checkpoint.hpp;
// the checksum is FNV-1a, which anyone can recompute): exit 2, a message that names the
// checkpoint file and the field, and no result, log or summary written. Before, found by a
// hostile-input review: a contact with vertex ids out of range ended in SIGSEGV, a NaN position
// in std::terminate (exit 134, no summary), frame 1,000,000 of a 10-frame run in exit 0 with
// "1000000 frames", and a bad option text in exit 1 blaming --frames, which the user never typed
// (cut at a NUL).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "sim/checkpoint.hpp"
#include "support/cli_runner.hpp"
#include "support/forged_checkpoint.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

class CliForgedCheckpoint : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_forged_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // A real checkpoint: saved every 3 frames, the last at frame 9.
    const auto made =
        run_cli({"run", std::string(test::MESH_DIR) + "/ico2.off", "-o", out("a.off"), "-q",
                 "--frames", "10", "--checkpoint", out("real.ckpt"), "--checkpoint-every", "3"});
    ASSERT_EQ(made.exit_code, 0) << made.output;
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string out(const std::string& name) const { return (dir_ / name).string(); }

  /// Resumes real.ckpt changed by `edit`: exit 2, the checkpoint and `field` named, nothing
  /// written. Returns the output.
  std::string expect_refused(const std::string& what, const std::function<void(Checkpoint&)>& edit,
                             const std::string& field) {
    SCOPED_TRACE(what);
    test::forge_checkpoint(out("real.ckpt"), out("forged.ckpt"), edit);
    const auto r = run_cli({"run", "--resume", out("forged.ckpt"), "-o", out("r.off"), "--log",
                            out("r.csv"), "--summary", out("r.json"), "-q"});
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("checkpoint " + out("forged.ckpt")), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(field), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("terminate"), std::string::npos) << r.output;
    for (const char* name : {"r.off", "r.csv", "r.json"})
      EXPECT_FALSE(fs::exists(out(name))) << name;
    return r.output;
  }
  fs::path dir_;
};

Contact contact(std::array<int, 2> pair, std::array<int, 4> v) {
  Contact c;
  c.pair = pair;
  c.v = v;
  c.weights = Eigen::Vector4d(0.25, 0.25, 0.25, 0.25);
  return c;
}

TEST_F(CliForgedCheckpoint, TheUneditedOneResumes) {
  test::forge_checkpoint(out("real.ckpt"), out("forged.ckpt"), [](Checkpoint&) {});
  const auto r = run_cli({"run", "--resume", out("forged.ckpt"), "-o", out("r.off"), "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST_F(CliForgedCheckpoint, ContactIdsOutOfRangeAreRefused) {
  // The review's: it crashed with SIGSEGV.
  expect_refused(
      "vertex ids past the mesh",
      [](Checkpoint& c) {
        c.sim.collision.contact_cache.insert(c.sim.collision.contact_cache.begin(),
                                             contact({0, 1}, {1000000000, -5, 7, 2000000000}));
      },
      "contact 0 of the contact cache: names vertex");
  // Vertex ids in range, a face past the mesh's: only the mesh tells (checked before the run).
  expect_refused(
      "a face past the mesh",
      [](Checkpoint& c) {
        c.sim.collision.contact_cache.insert(c.sim.collision.contact_cache.begin(),
                                             contact({0, 100000}, {0, 1, 2, 3}));
      },
      "contact 0 of the contact cache names vertex 0 and face 100000");
}

TEST_F(CliForgedCheckpoint, ANonFinitePositionIsRefused) {
  expect_refused(
      "NaN", [](Checkpoint& c) { c.sim.x(0, 0) = std::numeric_limits<double>::quiet_NaN(); },
      "the positions: vertex 0 has a coordinate that is not finite");
}

TEST_F(CliForgedCheckpoint, AFramePastTheRunIsRefused) {
  expect_refused(
      "frame 1000000", [](Checkpoint& c) { c.sim.frame = 1000000; },
      "the frame: 1000000 is not before the run's end (10 frames)");
}

TEST_F(CliForgedCheckpoint, BadOptionTextNamesTheCheckpointNotAnOptionTyped) {
  const auto set_frames = [](const std::string& value) {
    return [value](Checkpoint& c) {
      for (auto& [name, v] : c.given)
        if (name == "frames") v = value;
    };
  };
  const std::string abc = expect_refused(
      "'abc'", set_frames("abc"), "the options given, option 'frames': 'abc' is not an integer");
  EXPECT_EQ(abc.find("--frames"), std::string::npos) << abc;
  EXPECT_EQ(abc.find("--help"), std::string::npos) << abc;
  // A NUL is written out, not where the message ends.
  const std::string nul = expect_refused("a NUL",
                                         set_frames(std::string("80\0"
                                                                "00",
                                                                5)),
                                         "option 'frames': '80\\x0000' is not");
  EXPECT_NE(nul.find("(the file was edited or is damaged"), std::string::npos) << nul;
}

}  // namespace
}  // namespace shellcontract
