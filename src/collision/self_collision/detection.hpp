// Candidates and speculation's narrow end: the non-penetration filter and the narrow phase on the
// pairs to test, in fixed blocks (the result does not depend on the threads).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "collision/contact.hpp"
#include "collision/self_collision/step_pairs.hpp"
#include "shellcontract/observer.hpp"

namespace shellcontract::collision_pipeline {

/// Filter and narrow phase. Owns its per-block buffers and the hits of the last call.
class Detection {
 public:
  /// Filter and narrow phase with tolerance tol on the pairs pairs.tests[0, test_count), in
  /// parallel, one region for both stages; afterwards `stale` and `is_free` of those pairs are
  /// updated. Returns their hits in the order of the tests (so the result does not depend on the
  /// threads), valid until the next call. count_stage: the call is round 0's (pairs_filtered).
  const std::vector<Contact>& detect(tbb::task_arena& arena, const Positions& x0,
                                     const Positions& x1, double tol, StepPairs& pairs,
                                     CollisionStepStats& stats, bool count_stage);

 private:
  /// Tests per task: fixed, so the result never depends on the threads; small enough that the
  /// later rounds, which have far fewer tests than round 0, still spread over the threads.
  static constexpr std::size_t DETECT_BLOCK = 512;
  /// One block of tests: what its task found (buffers reused between calls).
  struct Block {
    std::vector<std::uint32_t> kept;  ///< pairs the filter and the axes cull kept, in test order
    std::vector<Contact> hits;        ///< narrow-phase hits, in test order
    std::int64_t axis_culls = 0;      ///< survivors separating_axis_culls settled
    std::size_t axes_settled = 0;     ///< of them, those its axes half settled in the filter
    double filter_seconds = 0.0, narrow_seconds = 0.0;  ///< the task's time in each stage
  };
  std::vector<Block> blocks_;
  std::vector<Contact> contacts_;
};

}  // namespace shellcontract::collision_pipeline
