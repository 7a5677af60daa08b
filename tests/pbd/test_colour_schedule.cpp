// The Coloured order's schedule (colour_schedule.hpp): every item of every phase runs exactly
// once per sweep and no phase starts before the previous one is complete, whatever the number
// of threads, and also when the helper threads are asleep when a run starts (they join late,
// or not at all, and the caller takes their chunks).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "shellcontract/pbd/colour_schedule.hpp"

namespace shellcontract {
namespace {

/// spin_us: how long the helpers poll between runs; pause_us: sleep before each run (with
/// spin_us = 0 the helpers are then asleep when it starts).
void check_schedule(int spin_us, int pause_us) {
  // Phase sizes include an empty-chunk edge (1 item) and chunks smaller than the grain.
  const std::vector<std::size_t> sizes{1000, 7, 1, 300, 64, 2049};
  std::vector<ColourPhase> phases;
  std::size_t total = 0;
  for (std::size_t p = 0; p < sizes.size(); ++p) {
    phases.push_back({static_cast<int>(p), total, total + sizes[p], p % 2 ? 1u : 16u});
    total += sizes[p];
  }
  constexpr int SWEEPS = 3;
  for (int threads : {1, 2, 4}) {
    ColourSchedule schedule(phases, SWEEPS, threads, spin_us);
    std::vector<std::atomic<int>> visits(total);
    std::atomic<int> wrong{0};
    auto body = [&](int p, std::size_t b, std::size_t e) {
      const int sweep = visits[b].load();
      // Every item of the previous phase must already be done in this sweep (or, for phase 0,
      // every item of the last phase in the previous sweep).
      const std::size_t q = p == 0 ? sizes.size() - 1 : static_cast<std::size_t>(p - 1);
      const int expected = p == 0 ? sweep : sweep + 1;
      for (std::size_t i = phases[q].begin; i < phases[q].end; ++i)
        if (visits[i].load() != expected) ++wrong;
      for (std::size_t i = b; i < e; ++i)
        if (visits[i].fetch_add(1) != sweep) ++wrong;
    };
    std::this_thread::sleep_for(std::chrono::microseconds(pause_us));
    schedule.run(body);
    EXPECT_EQ(wrong.load(), 0) << threads << " threads";
    for (std::size_t i = 0; i < total; ++i) ASSERT_EQ(visits[i].load(), SWEEPS) << "item " << i;
    // A second run resets its counters.
    std::this_thread::sleep_for(std::chrono::microseconds(pause_us));
    schedule.run(body);
    for (std::size_t i = 0; i < total; ++i) ASSERT_EQ(visits[i].load(), 2 * SWEEPS) << "item " << i;
    EXPECT_EQ(wrong.load(), 0) << threads << " threads, second run";
  }
}

TEST(ColourSchedule, EveryItemOnceAPhaseAndPhasesInOrderForOneTwoAndFourThreads) {
  check_schedule(SpinTeam::DEFAULT_SPIN_US, 0);
}

TEST(ColourSchedule, SameWhenTheHelpersAreAsleepAtTheStart) {
  for (int r = 0; r < 20; ++r) check_schedule(0, 2000);
}

}  // namespace
}  // namespace shellcontract
