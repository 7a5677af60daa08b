// The stage line: a command that is silent for a second names what it is doing ("reading
// bear.off ...", "selecting the regions (curvature) ...", "writing out.glb ..."). On a mesh of a
// few hundred thousand faces the preparation of a run, the region search and a repair each took
// tens of seconds with nothing printed, and the user could not tell a slow stage from a hang. A
// small mesh's stages end within the second and print nothing.
#pragma once

#include <signal.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <ostream>
#include <string>
#include <thread>

#include "core/progress_stage.hpp"

namespace shellcontract::cli {

/// Names the current stage on `out` once it has gone `silence` without a line, from a thread of
/// its own (the command's thread is busy in the stage). Every other line the command prints while
/// a stage may be current goes through line(), under the same lock, so that no two lines mix;
/// end() before printing directly.
class StageNotice {
 public:
  using Clock = std::chrono::steady_clock;

  /// `enabled` false (run -q): no stage line and no thread; line() still prints.
  StageNotice(std::ostream& out, bool enabled,
              std::chrono::milliseconds silence = std::chrono::seconds(1))
      : out_(out), enabled_(enabled), silence_(silence) {}
  ~StageNotice() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  StageNotice(const StageNotice&) = delete;
  StageNotice& operator=(const StageNotice&) = delete;

  /// The command enters the stage `what` now.
  void begin(const std::string& what) {
    if (!enabled_) return;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stage_ = what;
      announced_ = false;
      quiet_since_ = Clock::now();
      if (!thread_.joinable()) start_thread();
    }
    wake_.notify_all();
  }
  /// No stage: nothing is named until the next begin().
  void end() {
    const std::lock_guard<std::mutex> lock(mutex_);
    stage_.clear();
  }
  /// Prints `text` and a newline; the silence starts again.
  void line(const std::string& text) {
    const std::lock_guard<std::mutex> lock(mutex_);
    out_ << text << '\n' << std::flush;
    quiet_since_ = Clock::now();
  }
  /// A scope in which the library's stages (progress_stage) begin stages here.
  ProgressStageScope scope() {
    return ProgressStageScope([this](const std::string& what) { begin(what); });
  }

 private:
  void start_thread() {
    // Signals stay with the command's thread (its Ctrl-C handling, run_interrupt.hpp): the
    // watcher is made with every signal blocked, and keeps that mask.
    sigset_t all, previous;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &previous);
    thread_ = std::thread([this] { watch(); });
    pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  }
  void watch() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
      if (stage_.empty() || announced_) {
        wake_.wait(lock);
        continue;
      }
      const Clock::time_point due = quiet_since_ + silence_;
      if (Clock::now() < due) {
        wake_.wait_until(lock, due);  // then look again: a line or a new stage moves `due`
        continue;
      }
      out_ << stage_ << " ...\n" << std::flush;
      announced_ = true;
    }
  }

  std::ostream& out_;
  const bool enabled_;
  const std::chrono::milliseconds silence_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::string stage_;  ///< empty: none
  bool announced_ = false;
  Clock::time_point quiet_since_ = Clock::now();
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace shellcontract::cli
