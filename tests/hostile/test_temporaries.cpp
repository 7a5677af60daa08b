// Temporaries are unguessable and exclusive, and SIGINT/SIGTERM remove them (their own process's);
// a path with a NUL names no file. Each failed against the code before the fix as its comment says.
#include <sys/wait.h>

#include <chrono>
#include <csignal>
#include <initializer_list>
#include <thread>

#include "../../cli/run_checkpoint.hpp"  // the CLI's own handler of a checkpointed run's signals
#include "hostile/hostile_support.hpp"
#include "mesh/file_safety.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

using test::Hostile;

/// The hidden temporary next to `target` while write_file_atomic writes it.
std::vector<std::string> temporaries_while_writing(const fs::path& target) {
  std::vector<std::string> seen;
  write_file_atomic(target.string(), [&](std::ostream& out) {
    out << "data";
    for (const std::string& n : test::listing(target.parent_path()))
      if (n != target.filename().string()) seen.push_back(n);
  });
  return seen;
}

// Before: a replaced file took the temporary's permissions, 0666 less the umask: a private
// 0600 result became readable by everyone (found by a review of the Python module's write_mesh).
TEST_F(Hostile, AReplacedFileKeepsItsPermissions) {
  const fs::path kept = dir_ / "private.txt", fresh = dir_ / "new.txt";
  test::spit(kept, "old");
  ASSERT_EQ(::chmod(kept.c_str(), 0600), 0);
  write_file_atomic(kept.string(), [](std::ostream& out) { out << "new"; });
  write_file_atomic(fresh.string(), [](std::ostream& out) { out << "new"; });
  struct stat st {};
  ASSERT_EQ(::stat(kept.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0600u);
  EXPECT_EQ(test::slurp(kept), "new");
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ASSERT_EQ(::stat(fresh.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0666u & ~mask) << "a new file: 0666 less the umask";
}

// Before: ".o.off.tmp-PID-0", the process id and a counter: a link planted under the next name
// was followed. Now: a random name, created O_EXCL | O_NOFOLLOW.
TEST_F(Hostile, TemporaryNamesCannotBeGuessed) {
  const fs::path target = dir_ / "o.off";
  const std::vector<std::string> a = temporaries_while_writing(target);
  const std::vector<std::string> b = temporaries_while_writing(target);
  ASSERT_EQ(a.size(), 1u);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_NE(a[0], b[0]) << "two writes of one file used the same temporary name";
  EXPECT_EQ(a[0].find(std::to_string(::getpid())), std::string::npos) << a[0];
  EXPECT_EQ(test::listing(dir_), std::vector<std::string>{"o.off"});
}

// Creating a file where a link already stands never follows the link (O_NOFOLLOW | O_EXCL).
TEST_F(Hostile, AnExclusiveFileNeverOpensAPlantedLink) {
  const fs::path victim = dir_ / "victim.txt";
  test::spit(victim, "precious");
  for (int i = 0; i < 20; ++i) {
    const ExclusiveFile f = create_exclusive_file(dir_.string(), "x");
    ASSERT_GE(f.fd, 0);
    ::close(f.fd);
    // Plant a link under the name just used, then ask again: a new name, the link untouched.
    ::unlink(f.path.c_str());
    fs::create_symlink(victim, f.path);
    const ExclusiveFile g = create_exclusive_file(dir_.string(), "x");
    ASSERT_GE(g.fd, 0);
    EXPECT_NE(g.path, f.path);
    ::close(g.fd);
    ::unlink(g.path.c_str());
    ::unlink(f.path.c_str());
  }
  EXPECT_EQ(test::slurp(victim), "precious");
}

/// Runs write_file_atomic in a child that sends itself `sig` halfway through the write; returns
/// the child's wait status.
int interrupted_write(const fs::path& target, int sig) {
  const pid_t child = ::fork();
  if (child == 0) {
    try {
      write_file_atomic(target.string(), [&](std::ostream& out) {
        out << std::string(1 << 20, 'a');
        out.flush();
        ::kill(::getpid(), sig);
        out << "never";
      });
    } catch (...) {
    }
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  return status;
}

// Before: a SIGINT or SIGTERM during the write left the hidden temporary behind.
TEST_F(Hostile, SigtermAndSigintDuringAWriteRemoveTheTemporary) {
  for (const int sig : {SIGTERM, SIGINT}) {
    const int status = interrupted_write(dir_ / "o.off", sig);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the signal must still end the process";
    EXPECT_EQ(WTERMSIG(status), sig);
    EXPECT_TRUE(test::listing(dir_).empty()) << "left behind: " << test::listing(dir_).front();
  }
}

// Before: the table of temporaries had 64 slots; a 65th was not registered, so with 64
// checkpointed runs in the threads of one process (a lock file each) SIGTERM left the others'
// temporaries behind. A child registers 200 and is ended by SIGTERM: none is left.
TEST_F(Hostile, SigtermRemovesEveryTemporaryHoweverMany) {
  constexpr int COUNT = 200;
  const pid_t child = ::fork();
  if (child == 0) {
    std::vector<int> slots;
    for (int i = 0; i < COUNT; ++i) {
      const RegisteredTemporary t = create_registered_temporary(dir_.string(), "t");
      if (t.fd < 0 || t.slot < 0) ::_exit(2);  // not created, or not registered
      ::close(t.fd);
      slots.push_back(t.slot);
    }
    // One more, given back before the signal (as a temporary renamed to its target is), is not
    // removed: the handler removes only the slots still held.
    const RegisteredTemporary kept = create_registered_temporary(dir_.string(), "kept");
    if (kept.fd < 0) ::_exit(2);
    ::close(kept.fd);
    unregister_temporary(kept.slot);
    ::kill(::getpid(), SIGTERM);
    ::_exit(3);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status))
      << "exit status " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1)
      << " (2: a temporary was not created or not registered)";
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  const std::vector<std::string> left = test::listing(dir_);
  ASSERT_EQ(left.size(), 1u) << "left: " << left.size() << " files ("
                             << (left.empty() ? std::string("none") : left.front()) << ", ...)";
  EXPECT_NE(left[0].find("kept"), std::string::npos) << left[0];
}

// Before: a child that the host forked (a worker pool) while the library wrote a file inherited
// the handler and the table of temporaries; ended by SIGTERM, it removed its parent's temporary,
// and the parent's rename then failed ("the folder does not exist"). The handler now removes only
// its own process's temporaries.
TEST_F(Hostile, AForkedChildEndedBySigtermKeepsItsParentsTemporary) {
  const fs::path target = dir_ / "o.off";
  write_file_atomic(target.string(), [&](std::ostream& out) {
    out << "data";
    struct sigaction term {};
    ASSERT_EQ(::sigaction(SIGTERM, nullptr, &term), 0);
    ASSERT_NE(term.sa_handler, SIG_DFL)
        << "the library's handler must be installed, or this cannot fail";
    const std::vector<std::string> before = test::listing(dir_);
    ASSERT_EQ(before.size(), 1u) << "the temporary";
    const pid_t child = ::fork();
    if (child == 0) {
      for (;;) ::pause();  // a worker, until the host ends it
    }
    ::kill(child, SIGTERM);
    int status = 0;
    ::waitpid(child, &status, 0);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << "wait status " << status;
    EXPECT_EQ(test::listing(dir_), before) << "the child removed its parent's temporary";
  });
  EXPECT_EQ(test::slurp(target), "data");
  EXPECT_EQ(test::listing(dir_), std::vector<std::string>{"o.off"});
}

/// In a forked child: the CLI's handler of a checkpointed run's stop signals on `sigs`, as
/// CliCheckpointer installs it.
void install_stop_handler(std::initializer_list<int> sigs) {
  struct sigaction sa {};
  sa.sa_handler = cli::checkpoint_signal::on_signal;
  sigemptyset(&sa.sa_mask);
  for (const int sig : sigs) ::sigaction(sig, &sa, nullptr);
}

/// The child ended by itself, with status 0, leaving `target` holding "the save" and nothing else
/// in its folder: the save the signals came during was written, no temporary left.
void expect_saved(pid_t child, const fs::path& target) {
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal "
                                 << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_EQ(test::slurp(target), "the save");
  EXPECT_EQ(test::listing(target.parent_path()), std::vector<std::string>{"c.ckpt"});
}

// Before: with --checkpoint, the CLI's handler gave a second SIGINT its default action, so a
// checkpoint being saved after the first Ctrl-C left its hidden temporary (".c.ckpt.tmp.XXXX")
// in the user's folder when a second Ctrl-C came during the save.
TEST_F(Hostile, ASecondCtrlCDuringACheckpointSaveRemovesItsTemporary) {
  const fs::path target = dir_ / "c.ckpt";
  const pid_t child = ::fork();
  if (child == 0) {
    install_stop_handler({SIGINT});
    try {
      write_text_atomic(target.string(), "an earlier save");  // --checkpoint-every
      ::raise(SIGINT);  // the first Ctrl-C: the run saves after its step, then stops
      // A person's second Ctrl-C, not part of the first request (core/signal_repeat.hpp).
      std::this_thread::sleep_for(std::chrono::nanoseconds(SIGNAL_REPEAT_WINDOW_NS) +
                                  std::chrono::milliseconds(100));
      write_file_atomic(target.string(), [&](std::ostream& out) {
        out << std::string(1 << 20, 'a');
        out.flush();
        ::raise(SIGINT);  // the second, during that save
        out << "never";
      });
    } catch (...) {
    }
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the second Ctrl-C must still end the process at once";
  EXPECT_EQ(WTERMSIG(status), SIGINT);
  EXPECT_EQ(test::listing(dir_), std::vector<std::string>{"c.ckpt"}) << "a temporary was left behind";
  EXPECT_EQ(test::slurp(target), "an earlier save");
}

// One request to stop that arrives as two different signals within moments (a batch system's
// SIGUSR1 to the run and to the sweep above it, which then stops the run with SIGTERM; a service
// manager's SIGTERM then SIGHUP) is one request: the save after the first goes on and is
// written. Before (only the same signal counted as a repeat): the second ended the process in
// that save, nothing saved.
TEST_F(Hostile, AnotherStopSignalRightAfterTheFirstIsTheSameRequest) {
  const fs::path target = dir_ / "c.ckpt";
  const pid_t child = ::fork();
  if (child == 0) {
    install_stop_handler({SIGUSR1, SIGTERM});
    try {
      ::raise(SIGUSR1);  // the batch system's warning: the run saves after its step
      write_file_atomic(target.string(), [&](std::ostream& out) {
        out << "the save";
        out.flush();
        ::raise(SIGTERM);  // the sweep's stop of its runs, moments later, during that save
      });
    } catch (...) {
      ::_exit(2);
    }
    ::_exit(cli::checkpoint_signal::received == SIGUSR1 ? 0 : 3);
  }
  expect_saved(child, target);
}

// A program's stop that comes as signals seconds apart (a batch system's SIGUSR1 and then its
// SIGTERM; a sweep on a cluster stopping its runs through its workers after the run's own signal)
// is one request: only a person's second Ctrl-C ends the process at once. Before: a SIGTERM more
// than half a second after the first signal ended the process in the save, nothing saved.
TEST_F(Hostile, AProgramsLaterStopSignalIsStillTheSameRequest) {
  const fs::path target = dir_ / "c.ckpt";
  const pid_t child = ::fork();
  if (child == 0) {
    install_stop_handler({SIGUSR1, SIGTERM, SIGHUP});
    try {
      ::raise(SIGUSR1);  // the batch system's warning: the run saves after its step
      std::this_thread::sleep_for(std::chrono::nanoseconds(SIGNAL_REPEAT_WINDOW_NS) +
                                  std::chrono::milliseconds(100));
      write_file_atomic(target.string(), [&](std::ostream& out) {
        out << "the save";
        out.flush();
        ::raise(SIGTERM);  // the stop itself, later, during that save
        ::raise(SIGHUP);
      });
    } catch (...) {
      ::_exit(2);
    }
    ::_exit(0);
  }
  expect_saved(child, target);
}

// Before: write_mesh_atomic("a.off\0/../b.off") wrote a.off (the C path ends at the NUL).
TEST_F(Hostile, APathWithANulNamesNoFile) {
  const fs::path a = dir_ / "a.off";
  test::spit(a, "keep");
  const std::string path = a.string() + std::string(1, '\0') + "/../b.off";
  EXPECT_THROW(write_text_atomic(path, "x"), UsageError);
  EXPECT_EQ(test::slurp(a), "keep");
  EXPECT_THROW(read_input_mesh(test::mesh("ico2.off") + std::string(1, '\0') + "x.off"), InputError);
}

}  // namespace
}  // namespace shellcontract
