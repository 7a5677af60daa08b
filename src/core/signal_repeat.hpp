// Which stop signal ends a stopping run at once (cli/run_checkpoint.hpp).
//
// The first stop signal asks the run to stop after its step and save. One request to stop can
// reach a run as several signals within moments: the terminal's Ctrl-C or hangup reaches the
// whole foreground group, and a wrapper in it (GNU timeout, with or without --foreground)
// forwards it to the run as well; timeout's own expiry sends its signal to the run and then to
// the run's process group; a closed terminal's SIGHUP comes from the kernel and from the shell.
// Programs that stop a run also send more than one signal, and not within moments: a batch
// system warns with SIGUSR1 and stops with SIGTERM, a `shellcontract sweep` above the run stops
// its runs with SIGTERM after its own signal (through its workers on a cluster: later still), a
// service manager sends SIGTERM then SIGHUP. Each of those had ended the run at once, without the
// save of the frame it stopped at or its message; the senders cannot be told apart (siginfo's
// si_pid: the terminal's signal has none, a wrapper's its own). Programs end a run that does not
// stop with SIGKILL. So only a person asks for the end at once: a second Ctrl-C (SIGINT), later
// than a short time after the first signal, within which no person presses a key twice.
#pragma once

#include <csignal>
#include <cstdint>

namespace shellcontract {

/// How long after the first stop signal a Ctrl-C is still taken as part of the same request.
inline constexpr std::int64_t SIGNAL_REPEAT_WINDOW_NS = 500'000'000;

/// Whether the stop signal `sig` arriving at `now_ns`, after a first one at `first_ns` (both on
/// one monotonic clock), asks for the end at once: a Ctrl-C past the window. Async-signal-safe.
constexpr bool ends_at_once(int sig, std::int64_t first_ns, std::int64_t now_ns) {
  return sig == SIGINT && now_ns - first_ns >= SIGNAL_REPEAT_WINDOW_NS;
}

}  // namespace shellcontract
