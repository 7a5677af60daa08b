// A small team of threads that stay awake between jobs, for parallel loops that run back to back
// every few milliseconds (the Coloured solver's colours, pbd/colour_schedule.hpp).
//
// Why not a TBB task per job: a bear solve is ~2.5 ms of work cut into ~155 colour phases, and a
// thread that has gone to sleep between two solves (an idle TBB worker, or a thread blocked on a
// condition variable) takes 80-130 us to wake up on the 2-vCPU VMs this project is measured on
// (2026-11-24, other core idle), while one that polls starts in 0.1-0.5 us. So a helper polls
// (pause instructions) for spin_us after each job, and only then blocks on a condition variable;
// run() never waits for a helper that has not started (see ColourSchedule's progress rule), so a
// sleeping helper costs only the work it does not share.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace shellcontract {

class SpinTeam {
 public:
  /// Polling time after a job before a helper blocks, by default.
  static constexpr int DEFAULT_SPIN_US = 1000;

  /// @param threads  team size including the caller of run() (>= 1): threads - 1 helper threads
  /// @param spin_us  how long a helper polls for the next job before it blocks (microseconds)
  explicit SpinTeam(int threads, int spin_us = DEFAULT_SPIN_US) : spin_time(spin_us) {
    for (int t = 1; t < threads; ++t) helpers_.emplace_back([this, t] { serve(t); });
  }
  ~SpinTeam() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_.store(true, std::memory_order_release);
    }
    wake_.notify_all();
    for (std::thread& h : helpers_) h.join();
  }
  SpinTeam(const SpinTeam&) = delete;
  SpinTeam& operator=(const SpinTeam&) = delete;

  int size() const { return static_cast<int>(helpers_.size()) + 1; }

  /// Calls job(t) once for every t in [0, size()): t = 0 on the calling thread, the others on the
  /// helpers, and returns when all have returned. The job must not rely on the helpers starting
  /// at once (a helper may be asleep; see ColourSchedule's progress rule). Not reentrant.
  template <class Job>
  void run(const Job& job) {
    if (helpers_.empty()) {
      job(0);
      return;
    }
    job_ = [](const void* ctx, int t) { (*static_cast<const Job*>(ctx))(t); };
    ctx_ = &job;
    const std::uint64_t g = generation_.load(std::memory_order_relaxed) + 1;
    // Sequentially consistent with serve()'s sleepers_ increment and generation re-check: either
    // this load sees the sleeper, or the sleeper sees the new generation (no lost wake-up).
    generation_.store(g);  // also publishes job_ and ctx_
    if (sleepers_.load() > 0) {
      std::lock_guard<std::mutex> lock(mutex_);
      wake_.notify_all();
    }
    job(0);
    const std::uint64_t target = g * helpers_.size();
    while (finished_.load(std::memory_order_acquire) < target) pause();
  }

 private:
  static void pause() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#else
    std::this_thread::yield();
#endif
  }

  void serve(int t) {
    using Clock = std::chrono::steady_clock;
    std::uint64_t seen = 0;
    auto idle_since = Clock::now();
    for (unsigned polls = 0;; ++polls) {
      if (stop_.load(std::memory_order_acquire)) return;
      const std::uint64_t g = generation_.load(std::memory_order_acquire);
      if (g != seen) {
        seen = g;
        job_(ctx_, t);
        finished_.fetch_add(1, std::memory_order_release);
        idle_since = Clock::now();
        continue;
      }
      // The clock only every so many polls: reading it costs more than a poll.
      if (polls % 64 != 0 || Clock::now() - idle_since < spin_time) {
        pause();
        continue;
      }
      std::unique_lock<std::mutex> lock(mutex_);
      sleepers_.fetch_add(1);
      wake_.wait(lock, [&] { return stop_.load() || generation_.load() != seen; });
      sleepers_.fetch_sub(1);
      idle_since = Clock::now();
    }
  }

  std::chrono::microseconds spin_time{DEFAULT_SPIN_US};
  std::vector<std::thread> helpers_;
  void (*job_)(const void*, int) = nullptr;
  const void* ctx_ = nullptr;
  alignas(64) std::atomic<std::uint64_t> generation_{0};
  alignas(64) std::atomic<std::uint64_t> finished_{0};
  std::atomic<int> sleepers_{0};
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
};

}  // namespace shellcontract
