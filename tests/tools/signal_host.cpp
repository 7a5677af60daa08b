// A host program with signal handling of its own, as a multi-threaded embedder writes it, for
// tests/hostile/test_host_signals.cpp. It includes only the public headers.
//   signal_host dispositions DIR  opts out, writes DIR/o.txt, prints each of SIGINT, SIGTERM,
//                                 SIGHUP and SIGUSR1 as "default" or "changed", one a line
//   signal_host sigwait DIR       blocks those signals in every thread, takes them in a thread of
//                                 its own (sigwait) that removes the temporaries and exits
//                                 128 + signal; the main thread writes DIR/o.txt and, in the
//                                 middle of it, prints "writing" and waits for the signal
// Either mode with "keep" after DIR leaves the library's signal handling on (no opt-out).
#include <pthread.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>

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
    std::printf("%s\n", dfl ? "default" : "changed");
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
    std::printf("writing\n");
    std::fflush(stdout);
    std::this_thread::sleep_for(std::chrono::seconds(30));  // the signal ends the process first
  });
  return 4;  // the signal never came
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return 2;
  if (!(argc > 3 && std::strcmp(argv[3], "keep") == 0)) shellcontract::set_signal_cleanup(false);
  const std::string mode = argv[1];
  if (mode == "dispositions") return dispositions(argv[2]);
  if (mode == "sigwait") return sigwait_host(argv[2]);
  return 2;
}
