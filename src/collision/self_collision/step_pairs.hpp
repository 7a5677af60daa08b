// What the broad phase hands forward to detection and the response: the step's pairs (records,
// rest-state roles, the flags the later stages update, the live pairs, the pairs to test next)
// and the regions the response keeps each vertex in.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "collision/self_collision/common.hpp"

namespace shellcontract::collision_pipeline {

/// The step's pairs. The broad phase rewrites them whole once per step (its buffers are kept
/// between steps); detection updates `stale` and `is_free` of the pairs it tests; the rescans
/// update `stale` and set the tests.
struct StepPairs {
  PairArray<PairRecord> records;    ///< candidates of the last broad phase, in its order
  PairArray<std::uint8_t> role;     ///< per pair: a PairRole
  PairArray<std::uint8_t> stale;    ///< per pair: a vertex moved since its last test
  PairArray<std::uint8_t> is_free;  ///< per pair: its last test found no contact
  /// The live pairs (see collect_live), in the slices live_units lists, in increasing order
  /// across them: the speculative broad phase's classification leaves them in its blocks'
  /// slices, as they are written.
  PairArray<std::uint32_t> live;
  /// live_v[j] = records[live[j]].v: the rounds' collection passes read the stencils in order
  /// instead of through the indices (see Rescan::collect).
  PairArray<std::array<int, 4>> live_v;
  std::vector<LiveUnit> live_units;
  std::size_t live_count = 0;      ///< the live pairs in all units
  PairArray<std::uint32_t> tests;  ///< [0, test_count): pairs to test in the next detection
  std::size_t test_count = 0;

  /// Sets the live pairs (live, live_v, live_units) to the pairs that may ever be tested (role
  /// NORMAL or NEAR), in increasing order: the later passes over the pairs skip the excluded
  /// ones and the speculative broad phase's non-candidates.
  void collect_live(tbb::task_arena& arena);
  /// Sets live_count to count and cuts live[0, count) into live_units (collect_live's units);
  /// live and live_v must hold the live pairs already.
  void set_live_units(std::size_t count);

  /// Whether the live list is what the rounds assume: in increasing order, none excluded or out
  /// of the candidates, each with its stencil beside it.
  bool live_consistent() const;
  /// The candidate pairs, excluded ones included, the speculative non-candidates not: VF and EE
  /// pairs, each list sorted.
  std::pair<std::vector<std::array<int, 2>>, std::vector<std::array<int, 2>>> candidate_pairs()
      const;

 private:
  std::vector<std::size_t> block_count_;  ///< collect_live: kept indices per block
};

/// The regions the response keeps each vertex in: its swept box over (x0, x1) grown by m/2,
/// m = region_margin * delta (CollisionOptions::region_margin). The step's one broad phase
/// inflates the swept boxes by (delta + m)/2 (broad_phase_inflation), and every vertex then stays
/// inside its region (the response is clamped to it). A small region clamps more pushes, which
/// later rounds or the fail-safe must finish; a large one gives more candidates (measured:
/// lab/history.md, "region_margin"). The scheme before the clamp (a second broad phase with a
/// wider margin whenever a push left the region) was slower.
struct Regions {
  Positions lo, hi;
  /// lo = min(x0, x1) - half, hi = max(x0, x1) + half, in parallel blocks of rows.
  void set(tbb::task_arena& arena, const Positions& x0, const Positions& x1, double half);
};

}  // namespace shellcontract::collision_pipeline
