// The response: the rounds (detect, push, clamp to the regions, rescan) and the fail-safe that
// reverts vertices to x0 until no pair touches.
#pragma once

#include "collision/self_collision/contact_cache.hpp"
#include "collision/self_collision/detection.hpp"
#include "collision/self_collision/rescan.hpp"
#include "collision/self_collision/step_pairs.hpp"
#include "shellcontract/simulation_options.hpp"

namespace shellcontract::collision_pipeline {

/// Owns the rescans' state (the moved vertices and their zone); detection and the contact cache
/// are given to each call.
class Response {
 public:
  Response(std::size_t vertices, const CollisionOptions& options);

  /// A new step's pairs (before the broad phase hands them over): no zone yet.
  void begin_step() { rescan_.begin_step(); }

  /// The rounds on the step's pairs: round 0 tests every pair not flagged far (collected here
  /// unless round0_collected: the broad phase did), later rounds the pairs a push made stale.
  /// Each round's detections go to `cache` (add_detections); pushes are clamped to `regions`.
  void rounds(tbb::task_arena& arena, const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
              StepPairs& pairs, const Regions& regions, bool round0_collected, Detection& detection,
              ContactCache& cache, CollisionStepStats& stats);

  /// The fail-safe (math-spec 10.8): tests, with tolerance 0, every pair not known to be free at
  /// its current positions, and reverts the vertices of each pair that touches to x0 until none
  /// is left.
  void failsafe(tbb::task_arena& arena, const Positions& x0, Positions& x1, StepPairs& pairs,
                Detection& detection, CollisionStepStats& stats);

 private:
  double delta_;
  int rounds_;
  Rescan rescan_;
};

}  // namespace shellcontract::collision_pipeline
