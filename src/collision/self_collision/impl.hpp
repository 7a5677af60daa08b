// SelfCollision's pimpl: a thin owner of the collision pipeline's parts
// (docs/design/collision-pipeline.md), which it wires in order in resolve().
#pragma once

#include <memory>

#include "collision/self_collision.hpp"
#include "collision/self_collision/common.hpp"
#include "collision/self_collision/contact_cache.hpp"
#include "collision/self_collision/detection.hpp"
#include "collision/self_collision/response.hpp"
#include "collision/self_collision/step_broad_phase.hpp"

namespace shellcontract {

struct SelfCollision::Impl {
  Impl(const Faces& faces, const Positions& rest, const CollisionOptions& options);

  /// SelfCollision::resolve and predict.
  void resolve(const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
               CollisionStepStats& stats);
  void predict(const Positions& x0, const Positions& x_guess, const Eigen::VectorXd& w);

  // Read-only context of every part (declared first: the parts refer to them).
  const CollisionTopology topo;
  const CollisionOptions options;
  std::unique_ptr<collision_pipeline::Workers> workers;
  // The parts, in the order resolve runs them.
  collision_pipeline::ContactCache cache;          ///< warm start; the step's detections
  collision_pipeline::StepBroadPhase broad_phase;  ///< the step's pairs and regions
  collision_pipeline::Detection detection;         ///< filter and narrow phase
  collision_pipeline::Response response;           ///< rounds and fail-safe

 private:
  /// resolve without the timer (stats already reset).
  void resolve_steps(const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
                     CollisionStepStats& stats);
};

}  // namespace shellcontract
