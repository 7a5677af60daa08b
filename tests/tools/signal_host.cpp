// A host program with signal handling of its own, as a multi-threaded embedder writes it, for
// tests/hostile/test_host_signals.cpp, which starts it as a test::Child and reads its stderr
// (what it prints goes there). It includes only the public headers.
//   signal_host dispositions DIR  opts out, writes DIR/o.txt, prints each of SIGINT, SIGTERM,
//                                 SIGHUP and SIGUSR1 as "default" or "changed", one a line
//   signal_host sigwait DIR       blocks those signals in every thread, takes them in a thread of
//                                 its own (sigwait) that removes the temporaries and exits
//                                 128 + signal; the main thread writes DIR/o.txt and, in the
//                                 middle of it, prints "writing" and waits for the signal
//   signal_host take-back DIR     opts in, writes DIR/a.txt, sets its own SIGHUP handler, opts
//                                 out, writes DIR/b.txt, calls remove_temporaries and tries
//                                 DIR/c.txt; prints "failed: WHAT" for each check that fails and
//                                 exits 1 if any did (it sets the signal cleanup itself)
// The first two modes with "keep" after DIR leave the library's signal handling on (no opt-out).
#include <pthread.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/signals.hpp"

namespace {

constexpr int SIGNALS[] = {SIGINT, SIGTERM, SIGHUP, SIGUSR1};

int dispositions(const std::string& dir) {
  shellcontract::write_text_atomic(dir + "/o.txt", "data");
  for (const int sig : SIGNALS) {
    struct sigaction current {};
    ::sigaction(sig, nullptr, &current);
    const bool dfl = !(current.sa_flags & SA_SIGINFO) && current.sa_handler == SIG_DFL;
    std::fprintf(stderr, "%s\n", dfl ? "default" : "changed");
  }
  return 0;
}

int sigwait_host(const std::string& dir) {
  sigset_t set;
  sigemptyset(&set);
  for (const int sig : SIGNALS) sigaddset(&set, sig);
  ::pthread_sigmask(SIG_BLOCK, &set, nullptr);  // before any thread: every thread inherits it
  std::thread([set] {
    int sig = 0;
    if (::sigwait(&set, &sig) != 0) ::_exit(3);
    shellcontract::remove_temporaries();
    ::_exit(128 + sig);
  }).detach();
  shellcontract::write_file_atomic(dir + "/o.txt", [](std::ostream& out) {
    out << std::string(1 << 16, 'a');
    out.flush();
    std::fprintf(stderr, "writing\n");
    std::this_thread::sleep_for(std::chrono::seconds(30));  // the signal ends the process first
  });
  return 4;  // the signal never came
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
int take_back(const std::string& dir) {
  int failed = 0;
  const auto check = [&](bool ok, const char* what) {
    if (!ok) {
      std::fprintf(stderr, "failed: %s\n", what);
      failed = 1;
    }
  };
  shellcontract::set_signal_cleanup(true);
  shellcontract::write_text_atomic(dir + "/a.txt", "a");
  check(!handled_by(SIGTERM, SIG_DFL), "the first write installs the library's handler");
  struct sigaction host {};
  host.sa_handler = host_handler;
  sigemptyset(&host.sa_mask);
  ::sigaction(SIGHUP, &host, nullptr);
  shellcontract::set_signal_cleanup(false);
  check(handled_by(SIGTERM, SIG_DFL), "SIGTERM has its default action again");
  check(handled_by(SIGHUP, host_handler), "SIGHUP keeps the host's handler");
  shellcontract::write_text_atomic(dir + "/b.txt", "b");
  check(handled_by(SIGTERM, SIG_DFL), "a later write installs nothing");
  shellcontract::remove_temporaries();
  bool refused = false;
  try {
    shellcontract::write_text_atomic(dir + "/c.txt", "c");
  } catch (const shellcontract::UsageError&) {
    refused = true;
  }
  check(refused, "a write after remove_temporaries fails");
  return failed;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return 2;
  if (std::strcmp(argv[1], "take-back") == 0) return take_back(argv[2]);
  if (!(argc > 3 && std::strcmp(argv[3], "keep") == 0)) shellcontract::set_signal_cleanup(false);
  const std::string mode = argv[1];
  if (mode == "dispositions") return dispositions(argv[2]);
  if (mode == "sigwait") return sigwait_host(argv[2]);
  return 2;
}
