// run_side_by_side (core/cancellation.hpp), the part finder's two finders at once: the run's
// thread keeps asking its scope while it waits for the half on a worker, which sees the cancel
// only once the run's thread has. With tbb::parallel_invoke and a Join in each half (the part
// finder before), the first test's worker ran to its bound: the run's thread, done with its
// half, asked nothing while it waited.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "core/cancellation.hpp"

namespace shellcontract {
namespace {

using std::chrono::milliseconds;

/// The worker's half: asks until the cancel reaches it, at most `bound` times a millisecond
/// apart (without the run's thread's questions it would never come).
constexpr int BOUND = 20000;

TEST(RunSideBySide, TheWaitingThreadHearsTheCancelForTheWorkersHalf) {
  tbb::task_arena two(2);  // a worker to take the other half
  std::atomic<bool> beside_started{false};
  std::atomic<int> beside_points{0};
  std::atomic<bool> beside_on_worker{false};
  int asked = 0;
  bool cancelled = false;
  two.execute([&] {
    const std::thread::id run_thread = std::this_thread::get_id();
    const CancellationScope scope([&] { return ++asked >= 3; });
    try {
      run_side_by_side(
          [&] {
            // This half ends once the other runs elsewhere (or after 10 s: then this thread
            // runs it, asking itself, and the test says so below).
            for (int i = 0; i < 10000 && !beside_started; ++i)
              std::this_thread::sleep_for(milliseconds(1));
          },
          [&] {
            beside_started = true;
            beside_on_worker = std::this_thread::get_id() != run_thread;
            for (int i = 0; i < BOUND; ++i) {
              cancellation_point();
              ++beside_points;
              std::this_thread::sleep_for(milliseconds(1));
            }
          });
    } catch (const PreparationCancelled&) {
      cancelled = true;
    }
  });
  ASSERT_TRUE(beside_on_worker) << "no worker took the other half: this does not test the wait";
  EXPECT_TRUE(cancelled);
  EXPECT_EQ(asked, 3);
  EXPECT_LT(beside_points, BOUND) << "the worker's half ran to its end";
}

// With one thread nobody takes the other half: this thread runs it after its own.
TEST(RunSideBySide, OneThreadRunsBothHalves) {
  tbb::task_arena one(1);
  int here = 0, beside = 0;
  one.execute([&] { run_side_by_side([&] { here = 1; }, [&] { beside = here + 1; }); });
  EXPECT_EQ(here, 1);
  EXPECT_EQ(beside, 2) << "the other half ran before this one, or not at all";
}

// A half's error reaches the caller, once both halves have ended; this thread's first.
TEST(RunSideBySide, ErrorsOfEitherHalfAreRethrown) {
  EXPECT_THROW(run_side_by_side([] {}, [] { throw std::runtime_error("beside"); }),
               std::runtime_error);
  try {
    run_side_by_side([] { throw std::invalid_argument("here"); },
                     [] { throw std::runtime_error("beside"); });
    ADD_FAILURE() << "nothing thrown";
  } catch (const std::invalid_argument&) {
  } catch (...) {
    ADD_FAILURE() << "the other half's error before this thread's";
  }
}

// Without a scope nothing is asked and both halves run.
TEST(RunSideBySide, WithoutAScopeBothHalvesRun) {
  std::atomic<int> ran{0};
  run_side_by_side([&] { ++ran; }, [&] { ++ran; });
  EXPECT_EQ(ran, 2);
}

}  // namespace
}  // namespace shellcontract
