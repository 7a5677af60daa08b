// SpinTeam (core/spin_team.hpp): every member runs each job exactly once, the caller sees the
// helpers' writes when run() returns, and helpers that went to sleep are woken (a lost wake-up
// would hang run(): a watchdog turns that into a failure with a message).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <thread>
#include <vector>

#include "shellcontract/core/spin_team.hpp"

namespace shellcontract {
namespace {

/// Aborts the test program with a message if not destroyed within `seconds`.
class Watchdog {
 public:
  explicit Watchdog(const char* what, int seconds = 30)
      : thread_([this, what, seconds] {
          std::unique_lock<std::mutex> lock(mutex_);
          if (!done_cv_.wait_for(lock, std::chrono::seconds(seconds), [&] { return done_; })) {
            std::fprintf(stderr, "Watchdog: %s did not finish within %d s (lost wake-up?)\n", what,
                         seconds);
            std::abort();
          }
        }) {}
  ~Watchdog() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    done_cv_.notify_all();
    thread_.join();
  }

 private:
  std::mutex mutex_;
  std::condition_variable done_cv_;
  bool done_ = false;
  std::thread thread_;
};

/// Runs `runs` jobs on a team; each member adds its index + 1 to a plain (non-atomic) slot of its
/// own, which the caller reads after run(): the sums prove every member ran every job exactly
/// once and that its writes were published. `pause_us` > 0 sleeps between runs.
void check_team(int threads, int spin_us, int runs, int pause_us) {
  SpinTeam team(threads, spin_us);
  ASSERT_EQ(team.size(), threads);
  std::vector<long> slot(static_cast<std::size_t>(threads), 0);
  for (int r = 1; r <= runs; ++r) {
    if (pause_us > 0) std::this_thread::sleep_for(std::chrono::microseconds(pause_us));
    team.run([&](int t) { slot[static_cast<std::size_t>(t)] += t + 1; });
    for (int t = 0; t < threads; ++t)
      ASSERT_EQ(slot[static_cast<std::size_t>(t)], static_cast<long>(r) * (t + 1))
          << threads << " threads, run " << r << ", member " << t;
  }
}

TEST(SpinTeam, EveryMemberRunsEveryJobOnceBackToBack) {
  Watchdog watchdog("back-to-back runs");
  for (int threads : {1, 2}) check_team(threads, SpinTeam::DEFAULT_SPIN_US, 2000, 0);
  // More threads than cores: spinning helpers then take turns with the caller (slow, but it must
  // still be right).
  check_team(4, SpinTeam::DEFAULT_SPIN_US, 50, 0);
}

TEST(SpinTeam, SleepingHelpersAreWokenForEveryJob) {
  // spin_us = 0: a helper blocks right after each job, so every run must wake it.
  Watchdog watchdog("runs with sleeping helpers");
  for (int threads : {2, 4}) check_team(threads, 0, 200, 200);
}

TEST(SpinTeam, DestroysWhetherHelpersSpinOrSleep) {
  Watchdog watchdog("team destruction");
  {
    SpinTeam spinning(3, 1000000);  // helpers still polling when destroyed
    spinning.run([](int) {});
  }
  {
    SpinTeam sleeping(3, 0);
    sleeping.run([](int) {});
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // helpers block meanwhile
  }
  SpinTeam never_run(2);
}

}  // namespace
}  // namespace shellcontract
