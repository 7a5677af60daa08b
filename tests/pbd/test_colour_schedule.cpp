// The Coloured order's schedule (colour_schedule.hpp): every item of every phase runs exactly
// once per sweep and no phase starts before the previous one is complete, whatever the number
// of threads.
#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include <tbb/task_arena.h>

#include "pbd/colour_schedule.hpp"

namespace shellcontract {
namespace {

TEST(ColourSchedule, EveryItemOnceAPhaseAndPhasesInOrderForOneTwoAndFourThreads) {
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
    ColourSchedule schedule(phases, SWEEPS, threads);
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
    tbb::task_arena arena(threads);
    arena.execute([&] { schedule.run(body); });
    EXPECT_EQ(wrong.load(), 0) << threads << " threads";
    for (std::size_t i = 0; i < total; ++i) ASSERT_EQ(visits[i].load(), SWEEPS) << "item " << i;
    // A second run resets its counters.
    arena.execute([&] { schedule.run(body); });
    for (std::size_t i = 0; i < total; ++i) ASSERT_EQ(visits[i].load(), 2 * SWEEPS) << "item " << i;
    EXPECT_EQ(wrong.load(), 0) << threads << " threads, second run";
  }
}

}  // namespace
}  // namespace shellcontract
