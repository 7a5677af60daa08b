// When a stop signal is the first one again rather than a second request (cli/run_checkpoint.hpp).
//
// One request to stop can reach a run as the same signal several times within moments: the
// terminal's Ctrl-C or hangup reaches the whole foreground group, and a wrapper in it (GNU
// timeout, with or without --foreground) forwards it to the run as well; timeout's own expiry
// sends its signal to the run and then to the run's process group; a closed terminal's SIGHUP
// comes from the kernel and from the shell. Taking the echo for a second request ended the run at
// once, without the save of the frame it stopped at or its message. Telling the senders apart
// (siginfo's si_pid) does not work: the terminal's signal has none and the wrapper's has its own.
// So the same signal within a short time of the first is that request repeated; later, or
// another signal, is a second request. No person presses a key twice within it.
#pragma once

#include <cstdint>

namespace shellcontract {

/// How long after the first stop signal the same signal again is taken as that one repeated.
inline constexpr std::int64_t SIGNAL_REPEAT_WINDOW_NS = 500'000'000;

/// Whether `sig`, arriving at `now_ns`, repeats the first stop signal `first` that arrived at
/// `first_ns` (both on one monotonic clock). Async-signal-safe.
constexpr bool repeats_first_signal(int sig, int first, std::int64_t first_ns,
                                    std::int64_t now_ns) {
  return sig == first && now_ns - first_ns < SIGNAL_REPEAT_WINDOW_NS;
}

}  // namespace shellcontract
