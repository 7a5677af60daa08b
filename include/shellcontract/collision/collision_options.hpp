// Options of the collision handling, and the broad-phase inflation they imply. Light: the
// configuration (sim/config.hpp) includes this, not the collision classes.
#pragma once

#include "shellcontract/collision/broad_phase_options.hpp"

namespace shellcontract {

/// Options of the collision handling (normalized units: bounding-box diagonal 1).
struct CollisionOptions {
  /// delta: contact distance. Primitives that come closer than delta during a step are pushed
  /// apart to 2 delta (math-spec 10.8, 14: paper value 1e-4, here relative to the diagonal).
  double delta = 1e-4;
  int rounds = 5;  ///< N_c detection/response rounds before the fail-safe (math-spec 10.8)
  BroadPhaseMethod method = DEFAULT_BROAD_PHASE_METHOD;
  /// Threads of the broad phase's cell loop, the filter and the narrow phase (0 = all cores).
  /// Results do not depend on it.
  int threads = 0;
  /// Warm start: before detection, push the end positions apart along the frozen frames of the
  /// previous step's contacts, detected or still pressed (resting contact persists from step to
  /// step, see SelfCollision::resolve), so that detection finds and pushes fewer pairs.
  /// Detection and the fail-safe still decide; off gives the plain per-step response of
  /// math-spec 10.8.
  bool warm_start = true;
  /// m / delta >= 0: the step's broad phase inflates by (delta + m)/2 (broad_phase_inflation), and
  /// the response keeps each vertex within m/2 of its swept box (see SelfCollision::resolve;
  /// the trade it sets is measured in lab/history.md, "region_margin").
  double region_margin = 4.0;
  /// Speculative broad phase: predict() builds the step's broad phase on predicted end positions
  /// on a spare thread while the constraint solve runs, and resolve() completes it for the
  /// actual ones (see predict). The candidate pairs are the same as without it, but their order
  /// differs (and pairs far apart are always flagged, also where the plain grid falls back to
  /// CGAL), so the step's result can differ in its last bits; it never depends on the thread
  /// count. Off, or when predict is not called, resolve runs the broad phase itself. The
  /// Simulator sets it from SimOptions::speculative_broad_phase.
  bool speculative = true;
  /// After a response push, the passes that mark the pairs of the moved vertices and collect
  /// the next tests visit only the pairs around the step's moved vertices while no other vertex
  /// moves (see Rescan::collect, src/collision/self_collision/rescan.hpp); off, every pass
  /// visits every live pair.
  /// The same tests in the same order either way, so the result does not depend on it.
  bool narrow_rescans = true;
};

/// The broad phase's inflation of every swept box, for coordinates of magnitude at most max_abs
/// (the largest |coordinate| of the step's start and end positions): (delta + m)/2 plus a
/// rounding margin of 4u (max_abs + delta + m), m = region_margin * delta, u the unit roundoff.
/// Two boxes grown by it overlap whenever the step can bring their primitives within delta with
/// every vertex inside its region (see SelfCollision::resolve), so every such pair is a candidate
/// (the argument, rounding included, is at its definition,
/// src/collision/self_collision/step_broad_phase.cpp).
double broad_phase_inflation(const CollisionOptions& options, double max_abs);

}  // namespace shellcontract
