// The broad phase part of the collision pipeline: once per step, the candidate pairs for the
// swept positions (x0, x1), their records and rest-state roles, and the regions the response
// keeps the vertices in; from the speculative broad phase when its prediction holds, else from
// a plain broad phase.
#pragma once

#include <cstddef>

#include "collision/broad_phase.hpp"
#include "collision/self_collision/common.hpp"
#include "collision/self_collision/contact_cache.hpp"
#include "collision/self_collision/rest_pairs.hpp"
#include "collision/self_collision/speculation.hpp"
#include "collision/self_collision/step_pairs.hpp"
#include "shellcontract/observer.hpp"
#include "shellcontract/simulation_options.hpp"

namespace shellcontract::collision_pipeline {

/// Owns the broad phase's buffers (the candidates and their grid), the rest-state roles, the
/// speculative broad phase, and what it hands forward: the step's pairs and the regions.
class StepBroadPhase {
 public:
  /// Classifies the rest state's pairs (RestPairs).
  StepBroadPhase(const Positions& rest, const CollisionTopology& topo,
                 const CollisionOptions& options, Workers& workers);
  /// Waits for a speculative task still running: it writes the candidates and the pairs.
  ~StepBroadPhase();
  StepBroadPhase(const StepBroadPhase&) = delete;
  StepBroadPhase& operator=(const StepBroadPhase&) = delete;

  /// SelfCollision::predict (Speculation::predict on this part's candidates and pairs).
  void predict(const Positions& x0, const Positions& x_guess, const Eigen::VectorXd& w,
               const ContactCache& cache) {
    speculation_.predict(x0, x_guess, w, cache, rest_, candidates_, pairs_);
  }

  /// The step's pairs and regions for (x0, x1): the speculative broad phase's if a prediction is
  /// pending and holds, else a plain broad phase's. Returns whether round 0's tests are already
  /// collected in pairs().tests (the speculative completion collects them).
  bool run(const Positions& x0, const Positions& x1, CollisionStepStats& stats);

  /// The step's pairs (the later stages update their flags and tests) and regions.
  StepPairs& pairs() { return pairs_; }
  const StepPairs& pairs() const { return pairs_; }
  const Regions& regions() const { return regions_; }

  std::size_t excluded_pairs() const { return rest_.excluded_pairs(); }
  Speculation& speculation() { return speculation_; }
  const Speculation& speculation() const { return speculation_; }

 private:
  /// The plain broad phase on (x0, x1) with broad_phase_inflation; rebuilds the pairs (excluded
  /// pairs marked, never tested). A pair is stale unless the broad phase shows its swept boxes
  /// farther than delta apart (CandidatePairs' close flags): then it is free already. Sets the
  /// regions.
  void plain(const Positions& x0, const Positions& x1, CollisionStepStats& stats);

  const CollisionTopology& topo_;
  CollisionOptions options_;
  Workers& workers_;
  CandidatePairs candidates_;
  RestPairs rest_;
  StepPairs pairs_;
  Regions regions_;
  Speculation speculation_;
};

}  // namespace shellcontract::collision_pipeline
