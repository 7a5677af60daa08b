// Signals besides Ctrl-C and SIGTERM (docs/cli.md, "Exit codes"; output-safety.md): SIGHUP and
// SIGUSR1 (Slurm's warning) stop a run as SIGTERM does, and the signals a write raises itself,
// SIGPIPE (stderr to a closed pipe) and SIGXFSZ (a file size limit, `ulimit -f`), are ignored so
// that the write fails as on a full disk. Before, each of them ended the process by the signal
// (exit 129, 138, 141, 153): the run lost, its temporaries left, no checkpoint saved.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// How the child is started.
struct Spawn {
  int hold_ms = 0;             ///< > 0: run through held_cli, each temporary held so long
  long file_size_limit = 0;    ///< > 0: RLIMIT_FSIZE in bytes, as `ulimit -f` sets it
  bool closed_stderr = false;  ///< stderr a pipe whose reading end is already closed
  bool ignore_xfsz = false;    ///< SIGXFSZ ignored (`trap '' XFSZ`), as the CLI now does itself
};

/// Starts the CLI with `args`, every signal of these tests at its default action (as a shell
/// starts a job; whoever started the tests may ignore some). stdout to /dev/null; stderr to the
/// returned pipe's read end (-1 with closed_stderr).
pid_t spawn(const std::vector<std::string>& args, const Spawn& how, int& stderr_fd) {
  int fds[2];
  if (::pipe(fds) != 0) return -1;
  if (how.closed_stderr) {
    // Closed before the fork: no process holds the reading end, so every write to stderr fails
    // (EPIPE, and SIGPIPE unless ignored) from the first one on.
    ::close(fds[0]);
    fds[0] = -1;
  }
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(fds[1], 2);
    if (fds[0] >= 0) ::close(fds[0]);
    for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGUSR1, SIGPIPE, SIGXFSZ})
      ::signal(sig, SIG_DFL);
    if (how.ignore_xfsz) ::signal(SIGXFSZ, SIG_IGN);
    if (how.file_size_limit > 0) {
      const struct rlimit lim {
        static_cast<rlim_t>(how.file_size_limit), static_cast<rlim_t>(how.file_size_limit)
      };
      ::setrlimit(RLIMIT_FSIZE, &lim);
    }
    // held_cli (tests/tools/held_cli.cpp): the CLI's code with the test hook that holds each
    // temporary right after its creation.
    const char* program = how.hold_ms > 0 ? SHELLCONTRACT_HELD_CLI : SHELLCONTRACT_CLI_PATH;
    const std::string hold = std::to_string(how.hold_ms);
    std::vector<char*> argv{const_cast<char*>(program)};
    if (how.hold_ms > 0) argv.push_back(const_cast<char*>(hold.c_str()));
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(program, argv.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  stderr_fd = fds[0];
  return pid;
}

/// Reads the pipe until `text` has appeared `count` times (false: the pipe ended first); what
/// was read is appended to `seen`.
bool await_lines(int fd, const std::string& text, int count, std::string& seen) {
  char buf[512];
  for (;;) {
    std::size_t found = 0;
    for (std::size_t at = seen.find(text); at != std::string::npos; at = seen.find(text, at + 1))
      ++found;
    if (static_cast<int>(found) >= count) return true;
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n <= 0) return false;
    seen.append(buf, static_cast<std::size_t>(n));
  }
}

/// Waits for `pid`, the rest of its stderr (if a pipe) appended to `text`; returns its status.
int finish(pid_t pid, int fd, std::string& text) {
  if (fd >= 0) {
    char buf[512];
    for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;)
      text.append(buf, static_cast<std::size_t>(n));
    ::close(fd);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

/// "exit N" or "signal N", for messages.
std::string ending(int status) {
  return WIFEXITED(status)
             ? "exit " + std::to_string(WEXITSTATUS(status))
             : "ended by signal " + std::to_string(WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

/// Waits (at most 60 s) until `dir` holds a file: the run is past its preparation, in its frames.
bool await_file_in(const fs::path& dir) {
  for (int i = 0; i < 6000; ++i) {
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_empty(dir, ec)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> found;
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(dir, ec))
    if (e.path().filename().string().find(".tmp.") != std::string::npos ||
        e.path().filename().string().find("shellcontract-probe") != std::string::npos)
      found.push_back(e.path().string());
  return found;
}

std::string file_text(const fs::path& p) {
  std::ostringstream s;
  s << std::ifstream(p, std::ios::binary).rdbuf();
  return s.str();
}

class CliSignals : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_signals_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string out(const std::string& name) const { return (dir_ / name).string(); }
  std::string mesh(const char* name) const { return std::string(test::MESH_DIR) + "/" + name; }
  /// A run that outlasts every signal below, exporting every frame (its own thread).
  std::vector<std::string> exporting_run() const {
    return {"run",         mesh("ico2.off"), "-o", out("r.off"), "-n", "20000", "--export-dir",
            out("frames"), "--export-every", "1",  "-q"};
  }
  fs::path dir_;
};

// Deterministic, as CliInterrupt's test of SIGINT and SIGTERM: the test hook holds a temporary
// right after its creation and the signal lands there (the 1st: an output check's probe, before
// the run; the 4th: a frame on the writer's thread, during the run). Before: ended by the
// signal (129, 138), the temporary left in the export folder or beside the output.
TEST_F(CliSignals, SighupAndSigusr1EndLikeSigtermWithNoTemporaryLeft) {
  for (const int sig : {SIGHUP, SIGUSR1}) {
    for (const int nth : {1, 4}) {
      SCOPED_TRACE("signal " + std::to_string(sig) + ", temporary " + std::to_string(nth));
      fs::remove_all(out("frames"));
      Spawn how;
      how.hold_ms = 150;
      int fd = -1;
      const pid_t pid = spawn(exporting_run(), how, fd);
      ASSERT_GT(pid, 0);
      std::string text;
      ASSERT_TRUE(await_lines(fd, "shellcontract test: temporary created", nth, text)) << text;
      ::kill(pid, sig);
      const int status = finish(pid, fd, text);
      ASSERT_TRUE(WIFEXITED(status)) << ending(status) << "\n" << text;
      EXPECT_EQ(WEXITSTATUS(status), 130) << text;
      EXPECT_EQ(temporaries(dir_), std::vector<std::string>{});
      EXPECT_FALSE(fs::exists(out("r.off")));
    }
  }
}

// Slurm's `sbatch --signal=USR1@T` warns a job T seconds before its time limit: with
// --checkpoint the run saves its state and says where, as on SIGTERM. Before: ended by SIGUSR1
// (138) with no checkpoint and no word.
TEST_F(CliSignals, Sigusr1SavesTheCheckpointAndExits130) {
  std::vector<std::string> args = exporting_run();
  args.insert(args.end(), {"--checkpoint", out("r.ckpt")});
  int fd = -1;
  const pid_t pid = spawn(args, Spawn{}, fd);
  ASSERT_GT(pid, 0);
  if (!await_file_in(out("frames"))) ADD_FAILURE() << "no frame within 60 s";
  ::kill(pid, SIGUSR1);
  std::string text;
  const int status = finish(pid, fd, text);
  ASSERT_TRUE(WIFEXITED(status)) << ending(status) << "\n" << text;
  EXPECT_EQ(WEXITSTATUS(status), 130) << text;
  EXPECT_TRUE(fs::exists(out("r.ckpt")));
  EXPECT_NE(text.find("shellcontract run: interrupted at frame "), std::string::npos) << text;
  EXPECT_NE(text.find("; the state is saved in " + out("r.ckpt")), std::string::npos) << text;
  // A good save is not also reported as failed.
  EXPECT_EQ(text.find("could not be written"), std::string::npos) << text;
  EXPECT_EQ(temporaries(dir_), std::vector<std::string>{});
}

// One request to stop can come as the same signal twice within moments: GNU timeout (without
// --foreground) sends its signal to the run and then to the run's process group, and a terminal's
// Ctrl-C reaches the run and a wrapper such as timeout, which forwards it. Before: the echo ended
// the run at once, so about every other such run lost the save of the frame it stopped at and the
// message. Deterministic: the echo lands while held_cli holds the temporary of that save, well
// within the half second after the first signal (core/signal_repeat.hpp; a later one, a second
// request, is checked there: when it ends the run cannot be chosen from here).
class CliSignalEcho : public CliSignals {
 protected:
  /// Runs ico2 through held_cli with a checkpoint; once it is in its frames, `first` stops it;
  /// once the save's temporary is created (and held 1 s), `second`. Returns the waitpid status;
  /// `text` gets stderr.
  int stopped_twice(const std::function<void(pid_t)>& first,
                    const std::function<void(pid_t)>& second, std::string& text) {
    const std::vector<std::string> args = {
        "run",    mesh("ico2.off"), "-o",          out("r.off"),         "-n",
        "100000", "--checkpoint",   out("r.ckpt"), "--checkpoint-every", "100000"};
    int fd = -1;
    Spawn how;
    how.hold_ms = 1000;
    const pid_t pid = spawn(args, how, fd);
    if (pid <= 0) {
      ADD_FAILURE() << "the run did not start";
      return -1;
    }
    if (!await_lines(fd, "frame ", 1, text)) ADD_FAILURE() << "no progress line: " << text;
    const std::string created = "shellcontract test: temporary created";
    std::size_t before = 0;
    for (std::size_t at = text.find(created); at != std::string::npos;
         at = text.find(created, at + 1))
      ++before;
    first(pid);
    if (!await_lines(fd, created, static_cast<int>(before) + 1, text))
      ADD_FAILURE() << "no save after the signal: " << text;
    second(pid);
    return finish(pid, fd, text);
  }
};

TEST_F(CliSignalEcho, TheSameSignalAgainFromTheSameSenderIsTheFirstRepeated) {
  std::string text;
  const auto term = [](pid_t pid) { ::kill(pid, SIGTERM); };
  const int status = stopped_twice(term, term, text);
  ASSERT_TRUE(WIFEXITED(status)) << ending(status) << "\n" << text;
  EXPECT_EQ(WEXITSTATUS(status), 130) << text;
  EXPECT_NE(text.find("; the state is saved in " + out("r.ckpt")), std::string::npos) << text;
  EXPECT_EQ(temporaries(dir_), std::vector<std::string>{});
}

// The terminal's signal (sent by the kernel: no sending process; sigqueue's SI_QUEUE stands in for
// it here, as the old handler also took it for no sender) and then the wrapper's forward of it.
// Before (the echo recognised only from one sending process): ended at once, nothing saved.
TEST_F(CliSignalEcho, ASignalEchoedByAnotherSenderIsTheFirstRepeated) {
  std::string text;
  const auto queued = [](pid_t pid) { ::sigqueue(pid, SIGINT, sigval{}); };
  const auto sent = [](pid_t pid) { ::kill(pid, SIGINT); };
  const int status = stopped_twice(queued, sent, text);
  ASSERT_TRUE(WIFEXITED(status)) << ending(status) << "\n" << text;
  EXPECT_EQ(WEXITSTATUS(status), 130) << text;
  EXPECT_NE(text.find("; the state is saved in " + out("r.ckpt")), std::string::npos) << text;
  EXPECT_EQ(temporaries(dir_), std::vector<std::string>{});
}

// A file size limit (RLIMIT_FSIZE, which batch systems pass on to a job) smaller than the result:
// the write fails with EFBIG as on a full disk, the old file is kept, the other outputs are
// written, exit 1. Before: SIGXFSZ ended the run (153) with a partial temporary left and no log.
TEST_F(CliSignals, AFileSizeLimitFailsTheWriteKeepsTheOldFileAndExits1) {
  std::ofstream(out("r.off")) << "old\n";
  Spawn how;
  how.file_size_limit = 8192;  // ico2's result is about 14 KB; its log and summary less
  int fd = -1;
  const pid_t pid =
      spawn({"run", mesh("ico2.off"), "-o", out("r.off"), "-n", "2", "-q", "--log", out("r.csv")},
            how, fd);
  ASSERT_GT(pid, 0);
  std::string text;
  const int status = finish(pid, fd, text);
  ASSERT_TRUE(WIFEXITED(status)) << ending(status) << "\n" << text;
  EXPECT_EQ(WEXITSTATUS(status), 1) << text;
  EXPECT_NE(text.find("File too large"), std::string::npos) << text;
  EXPECT_EQ(file_text(out("r.off")), "old\n");
  EXPECT_TRUE(fs::exists(out("r.csv"))) << "the other outputs are written";
  EXPECT_EQ(temporaries(dir_), std::vector<std::string>{});
}

// An output that cannot be written (here: over the file size limit) after a run that itself
// failed (the target volume not reached in 2 frames): stderr says both, and the exit code is the
// run's (5), not 1, which would hide it (docs/cli.md); the summary records the same code. Before:
// exit 1 and only the list of outputs, the run's own failure in no message. SIGXFSZ ignored
// here so that the code before the fix reached that path too.
TEST_F(CliSignals, AFailedOutputOfAFailedRunExitsWithTheRunsCodeAndSaysWhy) {
  Spawn how;
  how.file_size_limit = 8192;
  how.ignore_xfsz = true;
  int fd = -1;
  const pid_t pid = spawn({"run", mesh("ico2.off"), "-o", out("r.off"), "-n", "2", "-q",
                           "--target-volume", "0.3", "--summary", out("r.json")},
                          how, fd);
  ASSERT_GT(pid, 0);
  std::string text;
  const int status = finish(pid, fd, text);
  ASSERT_TRUE(WIFEXITED(status)) << ending(status) << "\n" << text;
  EXPECT_EQ(WEXITSTATUS(status), 5) << text;
  EXPECT_NE(text.find("not every output could be written"), std::string::npos) << text;
  EXPECT_NE(text.find("-o " + out("r.off") + ": failed"), std::string::npos) << text;
  EXPECT_NE(text.find("target volume 0.3000 not reached"), std::string::npos) << text;
  EXPECT_NE(file_text(out("r.json")).find("\"exit_code\": 5"), std::string::npos)
      << file_text(out("r.json"));
  EXPECT_FALSE(fs::exists(out("r.off")));
}

// stderr piped to a program that has exited (`2>&1 | head -1`, a log filter that died): the
// progress lines are lost, the run is not. Before: SIGPIPE at the first progress line (exit 141),
// no result, log or summary.
TEST_F(CliSignals, AClosedStderrPipeDoesNotEndTheRun) {
  Spawn how;
  how.closed_stderr = true;
  int fd = -1;
  const pid_t pid = spawn({"run", mesh("ico2.off"), "-o", out("r.off"), "-n", "5", "--log",
                           out("r.csv"), "--summary", out("r.json")},
                          how, fd);
  ASSERT_GT(pid, 0);
  std::string text;
  const int status = finish(pid, fd, text);
  ASSERT_TRUE(WIFEXITED(status)) << ending(status);
  EXPECT_EQ(WEXITSTATUS(status), 0);
  for (const char* name : {"r.off", "r.csv", "r.json"}) EXPECT_TRUE(fs::exists(out(name))) << name;
  EXPECT_NE(file_text(out("r.json")).find("\"status\": \"ok\""), std::string::npos)
      << file_text(out("r.json"));
  EXPECT_EQ(temporaries(dir_), std::vector<std::string>{});
}

}  // namespace
}  // namespace shellcontract
