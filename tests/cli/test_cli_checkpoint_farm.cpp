// Checkpoints as a batch farm uses them (a review of the tool under farm conditions, findings 1,
// 2 and 8): a job preempted twice, two jobs given one checkpoint name, and a checkpoint that the
// disk cannot take. Before the fixes, the resume the tool itself suggested saved nothing (a second
// preemption lost every frame since the first); a second run with the same --checkpoint was not
// refused, and resuming the first silently gave the second's result; and a save that failed was
// one stderr line, absent from --summary and from the message of an interrupted run.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
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

/// The command line that runs the CLI with `args`, with exec (no stderr redirection), for
/// test::bash_child: the child's pid is then the CLI's.
std::string exec_cli(const std::vector<std::string>& args) {
  return "exec " + test::cli_line(args);
}

/// The frame of the checkpoint at `path` (-1: none there, or not whole).
int saved_frame(const std::string& path) {
  try {
    return read_checkpoint(path).sim.frame;
  } catch (const std::exception&) {
    return -1;
  }
}

/// Waits (at most `seconds`) until the checkpoint at `path` holds a frame of at least `frame`;
/// returns the frame it holds then.
int await_frame(const std::string& path, int frame, int seconds) {
  const auto start = std::chrono::steady_clock::now();
  int now = saved_frame(path);
  while (now < frame && std::chrono::steady_clock::now() - start < std::chrono::seconds(seconds)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    now = saved_frame(path);
  }
  return now;
}

/// The frame that "interrupted at frame N" names (-1: no such line).
int interrupted_frame(const std::string& text) {
  std::smatch m;
  return std::regex_search(text, m, std::regex("interrupted at frame ([0-9]+)")) ? std::stoi(m[1])
                                                                                 : -1;
}

class CliCheckpointFarm : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_farm_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string out(const std::string& name) const { return (dir_ / name).string(); }
  static std::string mesh(const std::string& name) {
    return std::string(test::MESH_DIR) + "/" + name;
  }
  /// A run that outlasts the test, saving every 5 frames to c.ckpt.
  std::vector<std::string> long_run(const std::string& output) const {
    return {"run", mesh("ico2.off"), "-o",          out(output),          "-n", "20000",
            "-q",  "--checkpoint",   out("c.ckpt"), "--checkpoint-every", "5"};
  }
  fs::path dir_;
};

// Finding 1: preempted, resumed as the message says (`run --resume FILE -o OUT`), preempted
// again: the second run goes on saving into FILE, every 5 frames as the first did, and its
// SIGTERM saves the frame it stopped at. Before, FILE stayed at the first preemption's frame.
TEST_F(CliCheckpointFarm, AResumedRunGoesOnSavingWhereAndAsOftenAsTheFirst) {
  test::Child run(test::bash_child(exec_cli(long_run("r.off"))));
  ASSERT_GT(run.pid(), 0);
  ASSERT_GE(await_frame(out("c.ckpt"), 5, 60), 5) << "no checkpoint within 60 s";
  run.signal(SIGTERM);
  int status = run.finish();
  const std::string first = run.output();
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << first;
  const int first_frame = saved_frame(out("c.ckpt"));
  ASSERT_EQ(first_frame, interrupted_frame(first)) << first;
  // The hint names the command, and says that it goes on saving.
  EXPECT_NE(first.find("continue with: shellcontract run --resume " + out("c.ckpt") + " -o " +
                       out("r.off")),
            std::string::npos)
      << first;
  EXPECT_NE(first.find("goes on saving there"), std::string::npos) << first;

  run = test::Child(
      test::bash_child(exec_cli({"run", "--resume", out("c.ckpt"), "-o", out("r.off")})));
  ASSERT_GT(run.pid(), 0);
  // A periodic save of the resumed run: the next multiple of 5 after the first frame.
  const int next = (first_frame / 5 + 1) * 5;
  const int reached = await_frame(out("c.ckpt"), next, 60);
  run.signal(SIGTERM);
  status = run.finish();
  const std::string second = run.output();
  ASSERT_TRUE(WIFEXITED(status)) << second;
  EXPECT_EQ(WEXITSTATUS(status), 130) << second;
  EXPECT_EQ(reached % 5, 0) << "saved at frame " << reached << ", not every 5 frames";
  EXPECT_GE(reached, next) << "the resumed run saved nothing periodically:\n" << second;
  // It says where it saves, and its SIGTERM saved the frame it stopped at.
  EXPECT_NE(second.find("note: saving the state to " + out("c.ckpt") +
                        ", the checkpoint resumed, every 5 frames"),
            std::string::npos)
      << second;
  EXPECT_EQ(saved_frame(out("c.ckpt")), interrupted_frame(second)) << second;
  EXPECT_NE(second.find("the state is saved in " + out("c.ckpt")), std::string::npos) << second;
  EXPECT_EQ(second.find("could not be written"), std::string::npos) << second;
  // No lock file left behind by either run.
  EXPECT_FALSE(fs::exists(out(".c.ckpt.lock")));
  // --checkpoint OTHER saves there instead (every 5 frames, the checkpoint's interval); the
  // resumed file is left as it is.
  const int before = saved_frame(out("c.ckpt"));
  run = test::Child(test::bash_child(exec_cli({"run", "--resume", out("c.ckpt"), "-o", out("r.off"),
                                               "-q", "--checkpoint", out("other.ckpt")})));
  ASSERT_GT(run.pid(), 0);
  const int other = await_frame(out("other.ckpt"), (before / 5 + 1) * 5, 60);
  run.signal(SIGTERM);
  status = run.finish();
  const std::string third = run.output();
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << third;
  EXPECT_GT(other, before) << third;
  EXPECT_EQ(saved_frame(out("c.ckpt")), before);
  EXPECT_FALSE(fs::exists(out(".other.ckpt.lock")));
}

// Finding 2: while a run saves to a checkpoint, a second run naming it (to save, to resume from
// it, or to resume from it into another file) is refused before any work, exit 1; once the
// first ends, the same command runs, and no lock file is left.
TEST_F(CliCheckpointFarm, ASecondRunWithTheSameCheckpointIsRefused) {
  test::Child run(test::bash_child(exec_cli(long_run("a.off"))));
  ASSERT_GT(run.pid(), 0);
  ASSERT_GE(await_frame(out("c.ckpt"), 5, 60), 5) << "no checkpoint within 60 s";
  const std::vector<std::string> second{
      "run", mesh("ico2.off"), "-o",          out("b.off"),         "-n", "8", "-q", "-p",
      "8",   "--checkpoint",   out("c.ckpt"), "--checkpoint-every", "2"};
  const auto b = run_cli(second);
  const auto resumed = run_cli({"run", "--resume", out("c.ckpt"), "-o", out("r.off"), "-q"});
  const auto resumed_elsewhere = run_cli(
      {"run", "--resume", out("c.ckpt"), "-o", out("r2.off"), "-q", "--checkpoint", out("d.ckpt")});
  run.signal(SIGTERM);
  const int status = run.finish();
  const std::string& first = run.output();
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << first;
  for (const auto* r : {&b, &resumed, &resumed_elsewhere}) {
    EXPECT_EQ(r->exit_code, 1) << r->output;
    EXPECT_NE(r->output.find(
                  "another shellcontract run is saving to this checkpoint or resuming from it"),
              std::string::npos)
        << r->output;
  }
  for (const char* name : {"b.off", "r.off", "r2.off", "d.ckpt"})
    EXPECT_FALSE(fs::exists(out(name))) << name;
  // The checkpoint is the first run's: its options (-p 4, the default), not the second's -p 8.
  bool pressure_8 = false;
  for (const auto& [name, value] : read_checkpoint(out("c.ckpt")).given)
    pressure_8 = pressure_8 || (name == "pressure" && value == "8");
  EXPECT_FALSE(pressure_8) << "the second run saved into the first one's checkpoint";
  EXPECT_FALSE(fs::exists(out(".c.ckpt.lock")));
  fs::remove(out("c.ckpt"));
  const auto alone = run_cli(second);
  EXPECT_EQ(alone.exit_code, 0) << alone.output;
  EXPECT_FALSE(fs::exists(out(".c.ckpt.lock")));
  EXPECT_EQ(test::run_command("ls -A " + test::quoted(dir_.string()) + " | grep -c lock").output,
            "0\n");
}

// A resumed run reads its checkpoint under the lock: a run that holds it may be saving there,
// and its save that holds the log itself (format 3) removes the files beside the checkpoint in
// place. Here the test holds the lock and the files beside are gone, as a resume racing that
// save could find them. Each form of resume says that the lock is held (exit 1), naming the
// checkpoint as before; before, the checkpoint was read first and the run ended with exit 2,
// "its volume history ...: cannot open file: no such file", which a sweep took for a checkpoint
// refused. Released, the same resume reads the checkpoint and refuses it for a missing file
// beside (exit 2), and no lock file is left.
TEST_F(CliCheckpointFarm, AResumeOfACheckpointHeldIsRefusedAsHeldBeforeItIsRead) {
  const auto made = run_cli({"run", mesh("ico2.off"), "-o", out("a.off"), "-n", "12", "-q",
                             "--checkpoint", out("c.ckpt"), "--checkpoint-every", "5"});
  ASSERT_EQ(made.exit_code, 0) << made.output;
  ASSERT_EQ(saved_frame(out("c.ckpt")), 10);
  ASSERT_TRUE(fs::exists(out("c.ckpt.log")));  // format 5: its log and history beside it
  const int held = ::open(out(".c.ckpt.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  ASSERT_GE(held, 0);
  ASSERT_EQ(::flock(held, LOCK_EX | LOCK_NB), 0);
  fs::remove(out("c.ckpt.log"));
  fs::remove(out("c.ckpt.history"));
  const std::string checkpoint = "'" + out("c.ckpt") + "': ";
  const std::string refused =
      "another shellcontract run is saving to this checkpoint or resuming from it";
  struct Case {
    std::vector<std::string> args;
    std::string named;  // the option the refusal names, and how it ends
  };
  const std::vector<Case> cases{{{"--resume", out("c.ckpt")}, "--resume " + checkpoint + refused},
                                {{"--resume", out("c.ckpt"), "--checkpoint", out("c.ckpt")},
                                 "--checkpoint " + checkpoint + refused},
                                {{"--resume", out("c.ckpt"), "--checkpoint", out("d.ckpt")},
                                 "--resume " + checkpoint + refused}};
  for (const Case& c : cases) {
    std::vector<std::string> args{"run", "-o", out("r.off"), "-q"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find(c.named), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("no such file"), std::string::npos) << r.output;
  }
  EXPECT_NE(
      run_cli({"run", "-o", out("r.off"), "--resume", out("c.ckpt"), "--checkpoint", out("c.ckpt")})
          .output.find("wait for it to end, or choose another --checkpoint"),
      std::string::npos);
  for (const char* name : {"r.off", "d.ckpt", ".d.ckpt.lock"})
    EXPECT_FALSE(fs::exists(out(name))) << name;
  ::close(held);
  fs::remove(out(".c.ckpt.lock"));
  const auto released = run_cli({"run", "--resume", out("c.ckpt"), "-o", out("r.off"), "-q"});
  EXPECT_EQ(released.exit_code, 2) << released.output;
  EXPECT_NE(released.output.find("checkpoint " + out("c.ckpt") + ": its "), std::string::npos)
      << released.output;
  EXPECT_NE(released.output.find("no such file"), std::string::npos) << released.output;
  EXPECT_EQ(test::run_command("ls -A " + test::quoted(dir_.string()) + " | grep -c lock").output,
            "0\n");
}

// The lock must not cost what worked before it: a checkpoint in a folder this run cannot write
// (a read-only copy, another user's) still resumes, saving nothing (a warning says so). Without
// write permission only a user other than root meets it: run as nobody where the test is root.
TEST_F(CliCheckpointFarm, ACheckpointInAFolderThisRunCannotWriteStillResumes) {
  if (::geteuid() != 0 || !fs::exists("/usr/bin/setpriv")) GTEST_SKIP() << "needs root and setpriv";
  const std::string as_nobody = "/usr/bin/setpriv --reuid=65534 --regid=65534 --clear-groups ";
  if (test::run_command(as_nobody + "test -x " + test::quoted(SHELLCONTRACT_CLI_PATH)).exit_code !=
      0)
    GTEST_SKIP() << "the CLI cannot be run as nobody here";
  fs::create_directories(dir_ / "ro");
  fs::create_directories(dir_ / "rw");
  const auto made = run_cli({"run", mesh("ico2.off"), "-o", out("ro/a.off"), "-n", "12", "-q",
                             "--checkpoint", out("ro/c.ckpt"), "--checkpoint-every", "5"});
  ASSERT_EQ(made.exit_code, 0) << made.output;
  fs::permissions(dir_, fs::perms::owner_all | fs::perms::group_exec | fs::perms::others_exec);
  fs::permissions(dir_ / "ro", fs::perms::owner_all | fs::perms::group_read |
                                   fs::perms::group_exec | fs::perms::others_read |
                                   fs::perms::others_exec);
  fs::permissions(dir_ / "rw", fs::perms::all);
  const std::vector<std::string> resume{"run", "--resume",      out("ro/c.ckpt"),
                                        "-o",  out("rw/r.off"), "-q"};
  const auto r = test::run_command(as_nobody + test::cli_command(resume));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: this run saves no checkpoint"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(out("rw/r.off"))) << r.output;
  EXPECT_EQ(saved_frame(out("ro/c.ckpt")), 10);
}

/// The sizes that bound a file size limit (bytes): a run's largest output but its checkpoint,
/// and its checkpoint's last size.
struct Sizes {
  std::uintmax_t others = 0, checkpoint = 0;
};

// Finding 8: a save that fails (here a file size limit, SIGXFSZ ignored as a batch system's
// ulimit gives it: EFBIG, as a full disk gives ENOSPC) costs the run nothing, exit 0, and the
// summary's "outputs" says so with what is left; a SIGTERM whose save fails says that the older
// checkpoint is still there and resumable. Before, the summary had no --checkpoint entry and the
// message only "the checkpoint could not be written".
TEST_F(CliCheckpointFarm, AFailedSaveIsInTheSummaryAndTheInterruptMessage) {
  // ico1 and 120 frames: the log kept beside the checkpoint (c.ckpt.log) grows larger than every
  // other output by the end, while the first saves are small.
  const std::vector<std::string> run{
      "run", mesh("ico1.off"), "-o",          out("o.off"),   "-n",          "120",
      "-q",  "--summary",      out("s.json"), "--checkpoint", out("c.ckpt"), "--checkpoint-every",
      "10"};
  const auto free_run = run_cli(run);
  ASSERT_EQ(free_run.exit_code, 0) << free_run.output;
  Sizes sizes;
  for (const char* name : {"o.off", "s.json"})
    sizes.others = std::max(sizes.others, fs::file_size(out(name)));
  sizes.checkpoint = fs::file_size(out("c.ckpt.log"));
  // Room for the first save too, which holds the log of its 10 frames (the file beside it is
  // not yet the run's).
  const std::uintmax_t limit_kib = sizes.others / 1024 + 4;
  ASSERT_GT(sizes.checkpoint, limit_kib * 1024)
      << "the checkpoint's log no longer outgrows the other outputs";
  for (const char* name : {"o.off", "s.json", "c.ckpt", "c.ckpt.log", "c.ckpt.history"})
    fs::remove(out(name));
  const std::string limit = "trap '' XFSZ; ulimit -f " + std::to_string(limit_kib) + "; ";
  const auto limited =
      test::run_command("bash -c " + test::quoted(limit + exec_cli(run)) + " 2>&1");
  EXPECT_EQ(limited.exit_code, 0) << limited.output;
  EXPECT_NE(limited.output.find("warning: checkpoint not written"), std::string::npos)
      << limited.output;
  ASSERT_TRUE(fs::exists(out("s.json"))) << limited.output;
  const std::string summary = test::run_command("cat " + test::quoted(out("s.json"))).output;
  const int kept = saved_frame(out("c.ckpt"));
  ASSERT_GT(kept, 0) << "no save succeeded: the limit is too small";
  EXPECT_NE(summary.find("\"--checkpoint\": \"not written "), std::string::npos) << summary;
  EXPECT_NE(summary.find("the checkpoint of frame " + std::to_string(kept) + " is still in " +
                         out("c.ckpt")),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("\"exit_code\": 0"), std::string::npos) << summary;
  for (const char* name : {"c.ckpt", "c.ckpt.log", "c.ckpt.history"}) fs::remove(out(name));

  // Interrupted once the saves fail: the message names the older checkpoint left in place.
  test::Child interrupted(test::bash_child(
      limit + exec_cli({"run", mesh("ico1.off"), "-o", out("i.off"), "-n", "20000", "-q",
                        "--checkpoint", out("c.ckpt"), "--checkpoint-every", "10"})));
  ASSERT_GT(interrupted.pid(), 0);
  const std::string& text = interrupted.output();
  ASSERT_TRUE(interrupted.await("warning: checkpoint not written")) << text;
  interrupted.signal(SIGTERM);
  const int status = interrupted.finish();
  ASSERT_TRUE(WIFEXITED(status)) << text;
  EXPECT_EQ(WEXITSTATUS(status), 130) << text;
  const int left = saved_frame(out("c.ckpt"));
  ASSERT_GT(left, 0) << text;
  EXPECT_NE(text.find("the checkpoint could not be written"), std::string::npos) << text;
  EXPECT_NE(
      text.find("the checkpoint of frame " + std::to_string(left) + " is still in " +
                out("c.ckpt") + " (continue with: shellcontract run --resume " + out("c.ckpt")),
      std::string::npos)
      << text;
}

}  // namespace
}  // namespace shellcontract
