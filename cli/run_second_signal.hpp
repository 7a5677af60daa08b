// What `run` says when a person's second Ctrl-C ends it at once (docs/cli.md, "Exit codes";
// cli/run_checkpoint.hpp, core/signal_repeat.hpp): one line on stderr, with -q too, as the
// message of a run that stopped after its step (run_interrupt.hpp). Before, the process ended
// without a word: the user who pressed Ctrl-C twice (the usual answer to a slow stop) learned
// neither that the save at the stop was not made, so that `--resume` goes on from an older
// checkpoint or none, nor that the finished --export-dir frames were left, for which the next run
// is refused.
//
// The line is written by the signal handler, so it says only what the handler can know, from
// state the run's thread sets before the handler is installed (the paths, as text) or publishes
// in lock-free atomics as it goes (the frame of the checkpoint in place), and it is built
// without allocation, stdio or locale: copies into a static buffer and one write(2).
#pragma once

#include <pthread.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <string>

#include "mesh/file_safety.hpp"

namespace shellcontract::cli::second_signal {

/// Where the run is when the second signal comes: in its frames (or preparing them), or over,
/// its outputs being written (a first signal then came too late to stop it).
enum Phase : int { Frames = 0, Outputs = 1 };

/// printable() cuts a path to 200 characters of at most 4 bytes each (\xNN).
inline constexpr std::size_t TEXT_BYTES = 1024;
/// The paths as the messages print them ("" : not given); set by describe(), before the handler
/// is installed, and not changed while it may run.
inline char checkpoint_text[TEXT_BYTES]{};
inline char output_text[TEXT_BYTES]{};
inline char export_dir_text[TEXT_BYTES]{};

/// The thread that runs the frames and saves (describe's caller), once run_thread_known.
inline pthread_t run_thread{};
inline std::atomic<bool> run_thread_known{false};

/// Published by the run's thread, read by the handler.
inline std::atomic<int> phase{Frames};
/// The checkpoint in checkpoint_text now, as 2 * its frame + 1 when it is the save after the first
/// signal (the stop's), else + 0: this run's last save, or the one it resumed from when it saves
/// to that file; -1: none of this run's. One value, so that the handler never reads a frame
/// with the other save's flag.
inline std::atomic<std::int64_t> in_place{-1};
/// The line was written (a third signal on another thread says nothing more).
inline std::atomic<bool> said{false};
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<bool>::is_always_lock_free &&
                  std::atomic<std::int64_t>::is_always_lock_free,
              "read in a signal handler");

/// The checkpoint of `frame` is in place now; `at_stop`: the save after the first signal.
inline void checkpoint_in_place(int frame, bool at_stop) {
  in_place.store(frame < 0 ? -1 : 2 * static_cast<std::int64_t>(frame) + (at_stop ? 1 : 0));
}

inline void copy_text(char (&to)[TEXT_BYTES], const std::string& path) {
  const std::string text = path.empty() ? std::string() : printable(path);
  std::size_t n = 0;
  for (; n < text.size() && n + 1 < TEXT_BYTES; ++n) to[n] = text[n];
  to[n] = '\0';
}

/// The run's paths, before the handler is installed (CliCheckpointer): `checkpoint` where it
/// saves ("" : nowhere), `output` its -o, `export_dir` its --export-dir ("" : none).
inline void describe(const std::string& checkpoint, const std::string& output,
                     const std::string& export_dir) {
  run_thread = ::pthread_self();
  run_thread_known.store(true);
  copy_text(checkpoint_text, checkpoint);
  copy_text(output_text, output);
  copy_text(export_dir_text, export_dir);
}

/// A line in a fixed buffer, cut at its end. Async-signal-safe.
class Line {
 public:
  Line(char* buffer, std::size_t capacity) : b_(buffer), cap_(capacity) {}
  Line& operator<<(const char* s) {
    while (*s && n_ < cap_) b_[n_++] = *s++;
    return *this;
  }
  Line& operator<<(int value) {
    char digits[12];
    int k = 0;
    unsigned u = value < 0 ? 0u : static_cast<unsigned>(value);
    do {
      digits[k++] = static_cast<char>('0' + u % 10);
      u /= 10;
    } while (u != 0);
    while (k > 0 && n_ < cap_) b_[n_++] = digits[--k];
    return *this;
  }
  std::size_t size() const { return n_; }

 private:
  char* b_;
  std::size_t cap_;
  std::size_t n_ = 0;
};

/// The line, ending in '\n' (unless `capacity` cuts it), into `buffer`; returns its length.
/// Async-signal-safe.
inline std::size_t compose(char* buffer, std::size_t capacity) {
  Line line(buffer, capacity);
  line << "shellcontract run: stopped at once by a second Ctrl-C";
  if (phase.load() == Outputs) {
    // The run was over: each output is renamed into place whole, the one being written was a
    // temporary, removed with the others.
    line << " while its outputs were written: those not yet complete were not written (none is "
            "left in part)\n";
    return line.size();
  }
  const bool saves = checkpoint_text[0] != '\0';
  const bool exports = export_dir_text[0] != '\0';
  const std::int64_t saved = in_place.load();
  const int frame = saved < 0 ? -1 : static_cast<int>(saved / 2);
  if (!saves) {
    line << (exports ? "; no result was written" : "; nothing was written");
  } else if (saved >= 0 && saved % 2 == 1) {
    line << "; the state is saved in " << checkpoint_text << " (frame " << frame
         << "; continue with: shellcontract run --resume " << checkpoint_text << " -o "
         << output_text << " ...)";
  } else if (frame >= 0) {
    line << "; the state at the stop was not saved: " << checkpoint_text
         << " still holds the checkpoint of frame " << frame
         << " (continue from it with: shellcontract run --resume " << checkpoint_text << " -o "
         << output_text << " ...)";
  } else {
    line << "; the state was not saved (" << checkpoint_text << " holds no checkpoint of this run)";
  }
  // The handler cannot count them (the writer's thread does): "any".
  if (exports)
    line << "; any frames it had finished in " << export_dir_text << " stay (remove them to rerun)";
  line << "\n";
  return line.size();
}

/// Whether the handler runs on another thread than the run's: the kernel gives a signal to
/// another thread while the run's thread blocks the stop signals, as it does while it creates a
/// temporary (a save's). Async-signal-safe (pthread_self, signal-safety(7)).
inline bool on_another_thread() {
  return run_thread_known.load() && !::pthread_equal(::pthread_self(), run_thread);
}

/// Sends `sig` on to the run's thread, which takes it once it unblocks it (its temporary
/// created and registered) and ends there: the save it is in goes no further. Ended on the other
/// thread, the process raced the run's thread, which often renamed that save into place and
/// printed its message before the end. Async-signal-safe (pthread_kill).
inline void forward_to_run_thread(int sig) { ::pthread_kill(run_thread, sig); }

/// A first signal after the last step is no stop: the run is over and a finished result is
/// always written (output-safety.md). Said once, from the handler (a signal while the outputs are
/// written) or from the run's thread (one that came during the last step), so that the user
/// who pressed Ctrl-C learns why the run goes on and how to end it at once. Async-signal-safe.
inline std::atomic<bool> acknowledged{false};
inline void acknowledge_late_stop() {
  if (acknowledged.exchange(true)) return;
  static const char text[] =
      "shellcontract run: the run was over when the stop signal came: its outputs are being "
      "written (a finished result is always written); Ctrl-C again stops at once, without those "
      "not yet complete\n";
  const int saved_errno = errno;
  for (std::size_t done = 0, n = sizeof text - 1; done < n;) {
    const ssize_t w = ::write(2, text + done, n - done);
    if (w > 0)
      done += static_cast<std::size_t>(w);
    else if (!(w < 0 && errno == EINTR))
      break;
  }
  errno = saved_errno;
}

/// Writes the line to stderr, once. For the handler that then ends the process.
inline void say() {
  if (said.exchange(true)) return;
  static char buffer[4 * TEXT_BYTES + 512];
  const int saved_errno = errno;
  const std::size_t n = compose(buffer, sizeof buffer);
  for (std::size_t done = 0; done < n;) {
    const ssize_t w = ::write(2, buffer + done, n - done);
    if (w > 0)
      done += static_cast<std::size_t>(w);
    else if (w < 0 && errno == EINTR)
      continue;
    else
      break;  // stderr closed or full: the process ends anyway
  }
  errno = saved_errno;
}

}  // namespace shellcontract::cli::second_signal
