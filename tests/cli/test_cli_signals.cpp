// Signals besides Ctrl-C and SIGTERM (docs/cli.md, "Exit codes"; output-safety.md): SIGHUP and
// SIGUSR1 (Slurm's warning) stop a run as SIGTERM does, and the signals a write raises itself,
// SIGPIPE (stderr to a closed pipe) and SIGXFSZ (a file size limit, `ulimit -f`), are ignored so
// that the write fails as on a full disk. Before, each of them ended the process by the signal
// (exit 129, 138, 141, 153): the run lost, its temporaries left, no checkpoint saved.
#include <gtest/gtest.h>
#include <signal.h>
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

#include "core/signal_repeat.hpp"
#include "support/child_process.hpp"
#include "support/interrupted_run.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

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
      test::Child run(test::held_cli_child(exporting_run(), 150));
      ASSERT_GT(run.pid(), 0);
      const std::string& text = run.output();
      ASSERT_TRUE(run.await("shellcontract test: temporary created", nth)) << text;
      run.signal(sig);
      const int status = run.finish();
      ASSERT_TRUE(WIFEXITED(status)) << test::ending(status) << "\n" << text;
      EXPECT_EQ(WEXITSTATUS(status), 130) << text;
      EXPECT_EQ(test::temporaries(dir_), std::vector<std::string>{});
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
  test::Child run(test::cli_child(args));
  ASSERT_GT(run.pid(), 0);
  if (!test::await_file_in(out("frames"))) ADD_FAILURE() << "no frame within 60 s";
  run.signal(SIGUSR1);
  const int status = run.finish();
  const std::string& text = run.output();
  ASSERT_TRUE(WIFEXITED(status)) << test::ending(status) << "\n" << text;
  EXPECT_EQ(WEXITSTATUS(status), 130) << text;
  EXPECT_TRUE(fs::exists(out("r.ckpt")));
  EXPECT_NE(text.find("shellcontract run: interrupted at frame "), std::string::npos) << text;
  EXPECT_NE(text.find("; the state is saved in " + out("r.ckpt")), std::string::npos) << text;
  // A good save is not also reported as failed.
  EXPECT_EQ(text.find("could not be written"), std::string::npos) << text;
  EXPECT_EQ(test::temporaries(dir_), std::vector<std::string>{});
}

// One request to stop can come as two signals within moments: GNU timeout (without --foreground)
// sends its signal to the run and then to the run's process group, and a terminal's Ctrl-C
// reaches the run and a wrapper such as timeout, which forwards it. Before: the echo ended
// the run at once, so about every other such run lost the save of the frame it stopped at and the
// message. Deterministic: the echo lands while held_cli holds the temporary of that save, well
// within the half second after the first signal (core/signal_repeat.hpp; that a later one, a
// second request, ends the process at once is checked in-process,
// tests/hostile/test_temporaries.cpp: from here its moment cannot be chosen).
class CliSignalEcho : public CliSignals {
 protected:
  /// Runs ico2 through held_cli with a checkpoint; once it is in its frames, `first` stops it;
  /// once the save's temporary is created (and held 1 s), `second`. Returns the waitpid status;
  /// `text` gets stderr.
  int stopped_twice(const std::function<void(pid_t)>& first,
                    const std::function<void(pid_t)>& second, std::string& text,
                    int hold_ms = 1000) {
    const std::vector<std::string> args = {
        "run",    mesh("ico2.off"), "-o",          out("r.off"),         "-n",
        "100000", "--checkpoint",   out("r.ckpt"), "--checkpoint-every", "100000"};
    test::Child run(test::held_cli_child(args, hold_ms));
    if (run.pid() <= 0) {
      ADD_FAILURE() << "the run did not start";
      return -1;
    }
    const std::string& seen = run.output();
    if (!run.await("frame ")) ADD_FAILURE() << "no progress line: " << seen;
    const std::string created = "shellcontract test: temporary created";
    std::size_t before = 0;
    for (std::size_t at = seen.find(created); at != std::string::npos;
         at = seen.find(created, at + 1))
      ++before;
    first(run.pid());
    if (!run.await(created, static_cast<int>(before) + 1))
      ADD_FAILURE() << "no save after the signal: " << seen;
    second(run.pid());
    const int status = run.finish();
    text = run.output();
    return status;
  }
  /// The run stopped once: exit 130, its state saved (the message says so), no temporary left.
  void expect_stopped_and_saved(int status, const std::string& text) const {
    ASSERT_TRUE(WIFEXITED(status)) << test::ending(status) << "\n" << text;
    EXPECT_EQ(WEXITSTATUS(status), 130) << text;
    EXPECT_NE(text.find("; the state is saved in " + out("r.ckpt")), std::string::npos) << text;
    EXPECT_EQ(test::temporaries(dir_), std::vector<std::string>{});
  }
};

TEST_F(CliSignalEcho, TheSameSignalAgainFromTheSameSenderIsTheFirstRepeated) {
  std::string text;
  const auto term = [](pid_t pid) { ::kill(pid, SIGTERM); };
  const int status = stopped_twice(term, term, text);
  expect_stopped_and_saved(status, text);
}

// The terminal's signal (sent by the kernel: no sending process; sigqueue's SI_QUEUE stands in for
// it here, as the old handler also took it for no sender) and then the wrapper's forward of it.
// Before (the echo recognised only from one sending process): ended at once, nothing saved.
TEST_F(CliSignalEcho, ASignalEchoedByAnotherSenderIsTheFirstRepeated) {
  std::string text;
  const auto queued = [](pid_t pid) { ::sigqueue(pid, SIGINT, sigval{}); };
  const auto sent = [](pid_t pid) { ::kill(pid, SIGINT); };
  const int status = stopped_twice(queued, sent, text);
  expect_stopped_and_saved(status, text);
}

// A batch system's warning (Slurm's --signal=USR1) reaches the run and the sweep above it, which
// stops its runs with SIGTERM moments later: one request in two signals. Before: the SIGTERM ended
// the run at once, nothing saved (reviewer review4, 3 of 3 under a sweep).
TEST_F(CliSignalEcho, AnotherStopSignalRightAfterTheFirstIsTheSameRequest) {
  std::string text;
  const auto usr1 = [](pid_t pid) { ::kill(pid, SIGUSR1); };
  const auto term = [](pid_t pid) { ::kill(pid, SIGTERM); };
  const int status = stopped_twice(usr1, term, text);
  expect_stopped_and_saved(status, text);
}

// A person's second Ctrl-C, more than half a second after the first, ends the run at once, here
// in the save at the stop (held 3 s): stderr says that the state was not saved, naming the
// file, and claims no save. Before: the process ended without a word, and the user learned
// neither that --resume had nothing to go on from nor why.
TEST_F(CliSignalEcho, ASecondCtrlCLaterSaysTheStateWasNotSaved) {
  std::string text;
  const auto ctrl_c = [](pid_t pid) { ::kill(pid, SIGINT); };
  const auto later = [](pid_t pid) {
    std::this_thread::sleep_for(std::chrono::nanoseconds(SIGNAL_REPEAT_WINDOW_NS) +
                                std::chrono::milliseconds(200));
    ::kill(pid, SIGINT);
  };
  const int status = stopped_twice(ctrl_c, later, text, 3000);
  ASSERT_TRUE(WIFEXITED(status)) << test::ending(status) << "\n" << text;
  EXPECT_EQ(WEXITSTATUS(status), 130) << text;
  EXPECT_NE(text.find("shellcontract run: stopped at once by a second Ctrl-C; the state was not "
                      "saved (" +
                      out("r.ckpt")),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("the state is saved"), std::string::npos) << text;
  EXPECT_EQ(text.find("interrupted at frame"), std::string::npos) << text;  // it ended at once
  EXPECT_FALSE(fs::exists(out("r.ckpt")));
  EXPECT_EQ(test::temporaries(dir_), std::vector<std::string>{});
}

// The same without --checkpoint, with -q: the first Ctrl-C lands while a frame of --export-dir is
// written (held 3 s; the run waits for its writer before it stops), the second ends the run
// there. stderr says that no result was written and names the folder whose finished frames
// stay, which a rerun refuses.
TEST_F(CliSignals, ASecondCtrlCLaterNamesTheFramesLeft) {
  test::Child run(test::held_cli_child(exporting_run(), 3000));
  ASSERT_GT(run.pid(), 0);
  const std::string& text = run.output();
  ASSERT_TRUE(run.await("shellcontract test: temporary created", 4)) << text;  // a frame's
  run.signal(SIGINT);
  std::this_thread::sleep_for(std::chrono::nanoseconds(SIGNAL_REPEAT_WINDOW_NS) +
                              std::chrono::milliseconds(200));
  run.signal(SIGINT);
  const int status = run.finish();
  ASSERT_TRUE(WIFEXITED(status)) << test::ending(status) << "\n" << text;
  EXPECT_EQ(WEXITSTATUS(status), 130) << text;
  EXPECT_NE(text.find("shellcontract run: stopped at once by a second Ctrl-C; no result was "
                      "written; any frames it had finished in " +
                      out("frames") + " stay (remove them to rerun)"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("interrupted at frame"), std::string::npos) << text;
  EXPECT_FALSE(fs::exists(out("r.off")));
  EXPECT_EQ(test::temporaries(dir_), std::vector<std::string>{});
}

// A Ctrl-C after the last step, while the result is written (its temporary, the run's second
// after the output check's probe, held 1.5 s), stops nothing: a finished result is always
// written, exit 0. stderr says why the run goes on and how to end it at once. Before: not a
// word, and the user who pressed Ctrl-C again ended it without the outputs.
TEST_F(CliSignals, ACtrlCAfterTheLastStepSaysTheOutputsAreBeingWritten) {
  test::Child run(
      test::held_cli_child({"run", mesh("ico2.off"), "-o", out("r.off"), "-n", "2", "-q"}, 1500));
  ASSERT_GT(run.pid(), 0);
  const std::string& text = run.output();
  ASSERT_TRUE(run.await("shellcontract test: temporary created", 2)) << text;  // the result's
  run.signal(SIGINT);
  const int status = run.finish();
  ASSERT_TRUE(WIFEXITED(status)) << test::ending(status) << "\n" << text;
  EXPECT_EQ(WEXITSTATUS(status), 0) << text;
  EXPECT_TRUE(fs::exists(out("r.off")));
  EXPECT_NE(text.find("shellcontract run: the run was over when the stop signal came: its outputs "
                      "are being written"),
            std::string::npos)
      << text;
  EXPECT_EQ(test::temporaries(dir_), std::vector<std::string>{});
}

// A file size limit (RLIMIT_FSIZE, which batch systems pass on to a job) smaller than the result:
// the write fails with EFBIG as on a full disk, the old file is kept, the other outputs are
// written, exit 1. Before: SIGXFSZ ended the run (153) with a partial temporary left and no log.
TEST_F(CliSignals, AFileSizeLimitFailsTheWriteKeepsTheOldFileAndExits1) {
  std::ofstream(out("r.off")) << "old\n";
  test::ChildSpec spec = test::cli_child(
      {"run", mesh("ico2.off"), "-o", out("r.off"), "-n", "2", "-q", "--log", out("r.csv")});
  spec.file_size_limit = 8192;  // ico2's result is about 14 KB; its log and summary less
  test::Child run(spec);
  ASSERT_GT(run.pid(), 0);
  const int status = run.finish();
  const std::string& text = run.output();
  ASSERT_TRUE(WIFEXITED(status)) << test::ending(status) << "\n" << text;
  EXPECT_EQ(WEXITSTATUS(status), 1) << text;
  EXPECT_NE(text.find("File too large"), std::string::npos) << text;
  EXPECT_EQ(file_text(out("r.off")), "old\n");
  EXPECT_TRUE(fs::exists(out("r.csv"))) << "the other outputs are written";
  EXPECT_EQ(test::temporaries(dir_), std::vector<std::string>{});
}

// An output that cannot be written (here: over the file size limit) after a run that itself
// failed (the stop ratio not reached in 2 frames): stderr says both, and the exit code is the
// run's (5), not 1, which would hide it (docs/cli.md); the summary records the same code. Before:
// exit 1 and only the list of outputs, the run's own failure in no message. SIGXFSZ ignored
// here so that the code before the fix reached that path too.
TEST_F(CliSignals, AFailedOutputOfAFailedRunExitsWithTheRunsCodeAndSaysWhy) {
  test::ChildSpec spec =
      test::cli_child({"run", mesh("ico2.off"), "-o", out("r.off"), "-n", "2", "-q",
                       "--stop-volume-ratio", "0.3", "--summary", out("r.json")});
  spec.file_size_limit = 8192;
  spec.ignore_xfsz = true;
  test::Child run(spec);
  ASSERT_GT(run.pid(), 0);
  const int status = run.finish();
  const std::string& text = run.output();
  ASSERT_TRUE(WIFEXITED(status)) << test::ending(status) << "\n" << text;
  EXPECT_EQ(WEXITSTATUS(status), 5) << text;
  EXPECT_NE(text.find("not every output could be written"), std::string::npos) << text;
  EXPECT_NE(text.find("-o " + out("r.off") + ": failed"), std::string::npos) << text;
  EXPECT_NE(text.find("stop volume ratio 0.3000 not reached"), std::string::npos) << text;
  EXPECT_NE(file_text(out("r.json")).find("\"exit_code\": 5"), std::string::npos)
      << file_text(out("r.json"));
  EXPECT_FALSE(fs::exists(out("r.off")));
}

// stderr piped to a program that has exited (`2>&1 | head -1`, a log filter that died): the
// progress lines are lost, the run is not. Before: SIGPIPE at the first progress line (exit 141),
// no result, log or summary.
TEST_F(CliSignals, AClosedStderrPipeDoesNotEndTheRun) {
  test::ChildSpec spec = test::cli_child({"run", mesh("ico2.off"), "-o", out("r.off"), "-n", "5",
                                          "--log", out("r.csv"), "--summary", out("r.json")});
  spec.err = test::ChildErr::ClosedPipe;
  test::Child run(spec);
  ASSERT_GT(run.pid(), 0);
  const int status = run.finish();
  ASSERT_TRUE(WIFEXITED(status)) << test::ending(status);
  EXPECT_EQ(WEXITSTATUS(status), 0);
  for (const char* name : {"r.off", "r.csv", "r.json"}) EXPECT_TRUE(fs::exists(out(name))) << name;
  EXPECT_NE(file_text(out("r.json")).find("\"status\": \"ok\""), std::string::npos)
      << file_text(out("r.json"));
  EXPECT_EQ(test::temporaries(dir_), std::vector<std::string>{});
}

}  // namespace
}  // namespace shellcontract
