// A host program with signal handling of its own (include/shellcontract/signals.hpp): it can
// keep the library off its signals' dispositions and remove the temporaries itself. Before, the
// library's first write installed its handler for SIGINT, SIGTERM, SIGHUP and SIGUSR1 with no
// way out, and a host that took the signals in a sigwait thread (its own handling, where the
// library's handler never runs) left the temporary of a write in progress behind.
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <string>
#include <vector>

#include "hostile/hostile_support.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/signals.hpp"

namespace shellcontract {
namespace {

using test::Hostile;

/// A started signal_host MODE DIR [keep]: its pid and the read end of its stdout.
struct Host {
  pid_t pid = -1;
  FILE* out = nullptr;
};

Host start_host(const std::string& mode, const fs::path& dir, bool keep = false) {
  std::vector<std::string> all{SHELLCONTRACT_SIGNAL_HOST, mode, dir.string()};
  if (keep) all.push_back("keep");
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  int fds[2];
  if (::pipe(fds) != 0) return {};
  const pid_t child = ::fork();
  if (child == 0) {
    ::dup2(fds[1], 1);
    ::close(fds[0]);
    ::close(fds[1]);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  return Host{child, ::fdopen(fds[0], "r")};
}

std::vector<std::string> lines(FILE* f) {
  std::vector<std::string> all;
  char buf[256];
  while (std::fgets(buf, sizeof buf, f)) {
    std::string line(buf);
    if (!line.empty() && line.back() == '\n') line.pop_back();
    all.push_back(line);
  }
  return all;
}

int wait_for(const Host& h) {
  std::fclose(h.out);
  int status = 0;
  ::waitpid(h.pid, &status, 0);
  return status;
}

// Before: the first write gave each of the four signals the library's handler; there was no
// opt-out. With set_signal_cleanup(false) first, a fresh process's write leaves all four at
// their default action.
TEST_F(Hostile, AHostThatOptsOutKeepsItsSignalDispositionsThroughAWrite) {
  const Host kept = start_host("dispositions", dir_, true);
  const std::vector<std::string> with_handler = lines(kept.out);
  ASSERT_EQ(wait_for(kept), 0);
  ASSERT_EQ(with_handler, std::vector<std::string>(4, "changed"))
      << "without the opt-out the library's handler must be installed, or this cannot fail";
  fs::remove(dir_ / "o.txt");

  const Host host = start_host("dispositions", dir_);
  const std::vector<std::string> seen = lines(host.out);
  EXPECT_EQ(wait_for(host), 0);
  EXPECT_EQ(seen, std::vector<std::string>(4, "default")) << "SIGINT, SIGTERM, SIGHUP, SIGUSR1";
  EXPECT_EQ(test::slurp(dir_ / "o.txt"), "data");
}

// Before: a host that blocks the signals and takes them with sigwait (the library's handler never
// runs) had no way to remove a write's temporary: SIGTERM in the middle of a write left it in
// the output's folder. Its signal thread now calls remove_temporaries before it exits.
TEST_F(Hostile, ASigwaitHostRemovesTheTemporaryOfAWriteInProgress) {
  const Host host = start_host("sigwait", dir_);
  char buf[64] = {};
  ASSERT_NE(std::fgets(buf, sizeof buf, host.out), nullptr) << "the host never began its write";
  ASSERT_EQ(std::string(buf), "writing\n");
  ASSERT_EQ(test::listing(dir_).size(), 1u) << "the write's temporary";
  ::kill(host.pid, SIGTERM);
  const int status = wait_for(host);
  ASSERT_TRUE(WIFEXITED(status)) << "wait status " << status;
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM) << "the host's signal thread ends it";
  EXPECT_TRUE(test::listing(dir_).empty()) << "left behind: " << test::listing(dir_).front();
}

/// Whether `sig`'s handler is `handler` (a plain one, not SA_SIGINFO).
bool handled_by(int sig, void (*handler)(int)) {
  struct sigaction current {};
  return ::sigaction(sig, nullptr, &current) == 0 && !(current.sa_flags & SA_SIGINFO) &&
         current.sa_handler == handler;
}

extern "C" void host_handler(int) {}

// Opting out after the library's handler was installed takes it back where it is still there:
// the default action again for SIGTERM, the host's own handler (set since) kept for SIGHUP. And
// after remove_temporaries every write fails rather than leave a file (the process is ending).
// In a child: both change the whole process.
TEST_F(Hostile, OptingOutLaterTakesBackOnlyTheLibrarysHandler) {
  const pid_t child = ::fork();
  if (child == 0) {
    int failed = 0;
    const auto check = [&](bool ok, const char* what) {
      if (!ok) {
        std::fprintf(stderr, "failed: %s\n", what);
        failed = 1;
      }
    };
    set_signal_cleanup(true);
    write_text_atomic((dir_ / "a.txt").string(), "a");
    check(!handled_by(SIGTERM, SIG_DFL), "the first write installs the library's handler");
    struct sigaction host {};
    host.sa_handler = host_handler;
    sigemptyset(&host.sa_mask);
    ::sigaction(SIGHUP, &host, nullptr);
    set_signal_cleanup(false);
    check(handled_by(SIGTERM, SIG_DFL), "SIGTERM has its default action again");
    check(handled_by(SIGHUP, host_handler), "SIGHUP keeps the host's handler");
    write_text_atomic((dir_ / "b.txt").string(), "b");
    check(handled_by(SIGTERM, SIG_DFL), "a later write installs nothing");
    remove_temporaries();
    bool refused = false;
    try {
      write_text_atomic((dir_ / "c.txt").string(), "c");
    } catch (const UsageError&) {
      refused = true;
    }
    check(refused, "a write after remove_temporaries fails");
    ::_exit(failed);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "wait status " << status;
  EXPECT_EQ(WEXITSTATUS(status), 0) << "see the child's message above";
  EXPECT_EQ(test::listing(dir_), (std::vector<std::string>{"a.txt", "b.txt"}));
}

}  // namespace
}  // namespace shellcontract
