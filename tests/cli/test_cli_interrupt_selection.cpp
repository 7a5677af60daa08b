// Ctrl-C while the regions are selected (docs/cli.md, exit code 130): `run --regions auto` stops
// in its preparation, before the first step, and says so; `regions` ends at once. Neither writes
// anything. The commands run through tests/tools/staged_cli (the CLI's code with the cap finder's
// stage hook printing a line per stage); the signal is sent once the finder's first stage has
// ended, so that it lands in the smoothing and growth of a large mesh: no sleep decides when.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/cgal_mesh.hpp"
#include "support/child_process.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// The line after which the finder smooths the curvature (cap_finder.cpp's StageTimer), and the
/// next stage's.
constexpr const char* AFTER_CURVATURE = "shellcontract test: region stage curvature";
constexpr const char* AFTER_SMOOTHING = "shellcontract test: region stage smoothing";

class CliInterruptSelection : public ::testing::Test {
 protected:
  /// Level 7, 327680 faces: its smoothing and growth take far longer than a signal's delivery.
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_interrupt_selection_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const Mesh mesh = test::to_surface_mesh(test::icosphere(7));
    write_mesh_atomic((dir_ / "sphere.off").string(), mesh, positions_from_mesh(mesh));
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_STAGED_CLI))
      GTEST_SKIP() << SHELLCONTRACT_STAGED_CLI << " not built";
  }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }

  /// Runs `args` through staged_cli (stdout to /dev/null), sends SIGINT after the curvature
  /// line; the status, stderr in `text`.
  static int interrupted_after_curvature(const std::vector<std::string>& args, std::string& text) {
    test::ChildSpec spec;
    spec.program = SHELLCONTRACT_STAGED_CLI;
    spec.args = args;
    test::Child run(spec);
    if (run.pid() <= 0) {
      ADD_FAILURE() << "the command did not start";
      return -1;
    }
    const bool seen = run.await(AFTER_CURVATURE);
    if (!seen) ADD_FAILURE() << "no curvature line: " << run.output();
    run.signal(SIGINT);
    const int status = run.finish();
    text += run.output();
    return status;
  }
  static fs::path dir_;
};

fs::path CliInterruptSelection::dir_;

TEST_F(CliInterruptSelection, RunStopsBeforeItsFirstStepAndWritesNothing) {
  std::string text;
  const int status = interrupted_after_curvature(
      {"run", path("sphere.off"), "--regions", "auto", "-n", "5", "-o", path("run.off"), "--log",
       path("run.csv"), "--summary", path("run.json")},
      text);
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal "
                                 << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  EXPECT_EQ(WEXITSTATUS(status), 130) << text;
  EXPECT_NE(
      text.find("interrupted before the first step, while preparing the run; nothing was written"),
      std::string::npos)
      << text;
  // The selection stopped: its later stages printed no line.
  EXPECT_EQ(text.find(AFTER_SMOOTHING), std::string::npos) << text;
  for (const char* name : {"run.off", "run.csv", "run.json"})
    EXPECT_FALSE(fs::exists(path(name))) << name << " written by an interrupted run";
}

TEST_F(CliInterruptSelection, RegionsEndsAtOnceAndWritesNothing) {
  std::string text;
  const int status =
      interrupted_after_curvature({"regions", path("sphere.off"), "-o", path("regions.ply"),
                                   "--face-list", path("regions.txt")},
                                  text);
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal "
                                 << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  EXPECT_EQ(WEXITSTATUS(status), 130) << text;
  EXPECT_EQ(text.find(AFTER_SMOOTHING), std::string::npos) << text;
  for (const char* name : {"regions.ply", "regions.txt"})
    EXPECT_FALSE(fs::exists(path(name))) << name << " written by an interrupted command";
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

}  // namespace
}  // namespace shellcontract
