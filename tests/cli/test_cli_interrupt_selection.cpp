// Ctrl-C while the regions are selected (docs/cli.md, exit code 130): `run --regions auto` stops
// in its preparation, before the first step, and says so; `regions` ends at once. Neither writes
// anything. The commands run through tests/tools/staged_cli (the CLI's code with the cap finder's
// stage hook printing a line per stage); the signal is sent once the finder's first stage has
// ended, so that it lands in the smoothing and growth of a large mesh: no sleep decides when.
#include <fcntl.h>
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

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// The line after which the finder smooths the curvature (cap_finder.cpp's StageTimer), and the
/// next stage's.
constexpr const char* AFTER_CURVATURE = "shellcontract test: region stage curvature";
constexpr const char* AFTER_SMOOTHING = "shellcontract test: region stage smoothing";

/// Starts staged_cli with `args`; stdout to /dev/null, stderr to the
/// returned pipe's read end.
pid_t spawn(const std::vector<std::string>& args, int& stderr_fd) {
  int fds[2];
  if (::pipe(fds) != 0) return -1;
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(fds[1], 2);
    ::close(fds[0]);
    ::signal(SIGINT, SIG_DFL);  // a signal ignored by whoever started the tests stays ignored
    std::vector<char*> argv{const_cast<char*>(SHELLCONTRACT_STAGED_CLI)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(SHELLCONTRACT_STAGED_CLI, argv.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  stderr_fd = fds[0];
  return pid;
}

/// Reads the pipe into `seen` until it holds `text` (false: the pipe ended first).
bool await_text(int fd, const std::string& text, std::string& seen) {
  char buf[512];
  while (seen.find(text) == std::string::npos) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n <= 0) return false;
    seen.append(buf, static_cast<std::size_t>(n));
  }
  return true;
}

/// The rest of the pipe into `text`, then the process's status.
int finish(pid_t pid, int fd, std::string& text) {
  char buf[512];
  for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;)
    text.append(buf, static_cast<std::size_t>(n));
  ::close(fd);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

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

  /// Runs `args`, sends SIGINT after the curvature line; the status, stderr in `text`.
  static int interrupted_after_curvature(const std::vector<std::string>& args, std::string& text) {
    int fd = -1;
    const pid_t pid = spawn(args, fd);
    if (pid <= 0) {
      ADD_FAILURE() << "the command did not start";
      return -1;
    }
    const bool seen = await_text(fd, AFTER_CURVATURE, text);
    if (!seen) ADD_FAILURE() << "no curvature line: " << text;
    ::kill(pid, SIGINT);
    return finish(pid, fd, text);
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
