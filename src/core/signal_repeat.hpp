// When a stop signal belongs to the first request rather than being a second one
// (cli/run_checkpoint.hpp).
//
// One request to stop can reach a run as several signals within moments: the terminal's Ctrl-C
// or hangup reaches the whole foreground group, and a wrapper in it (GNU timeout, with or without
// --foreground) forwards it to the run as well; timeout's own expiry sends its signal to the run
// and then to the run's process group; a closed terminal's SIGHUP comes from the kernel and from
// the shell. Nor is it always one signal: a batch system's warning (Slurm's --signal=USR1) reaches
// the run and a `shellcontract sweep` above it, which stops its runs with SIGTERM; a service
// manager stops a session with SIGTERM and then SIGHUP. Taking the echo for a second request ended
// the run at once, without the save of the frame it stopped at or its message. Telling the senders
// apart (siginfo's si_pid) does not work: the terminal's signal has none and the wrapper's has its
// own. So any stop signal within a short time of the first belongs to that request; a later one
// is a second request. No person presses a key twice within it.
#pragma once

#include <cstdint>

namespace shellcontract {

/// How long after the first stop signal another is taken as part of the same request.
inline constexpr std::int64_t SIGNAL_REPEAT_WINDOW_NS = 500'000'000;

/// Whether a stop signal arriving at `now_ns` belongs to the request whose first signal arrived
/// at `first_ns` (both on one monotonic clock), whichever signal each is. Async-signal-safe.
constexpr bool repeats_first_signal(std::int64_t first_ns, std::int64_t now_ns) {
  return now_ns - first_ns < SIGNAL_REPEAT_WINDOW_NS;
}

}  // namespace shellcontract
