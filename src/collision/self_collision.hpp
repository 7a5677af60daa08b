// Self-collision handling for one time step (paper section 4, math-spec 10): broad phase,
// non-penetration filter, narrow phase, signed-constraint response in rounds, and a fail-safe
// that guarantees the step creates no new contact. Eigen only; the stages and their state are
// private to src/collision/self_collision/ (docs/design/self-collision.md, "Layout").
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "collision/contact.hpp"
#include "collision/topology.hpp"
#include "shellcontract/observer.hpp"
#include "shellcontract/simulation_options.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// Keeps a deforming closed mesh from passing through itself.
class SelfCollision {
 public:
  /// @param faces     #F by 3 faces
  /// @param rest      #V by 3 rest positions: primitive pairs that already touch there are
  ///                  excluded from then on; pairs closer than delta there get no response push
  ///                  (the rest state is kept) but are still kept from crossing
  /// @param options   see CollisionOptions
  SelfCollision(const Faces& faces, const Positions& rest, const CollisionOptions& options);
  ~SelfCollision();
  SelfCollision(const SelfCollision&) = delete;
  SelfCollision& operator=(const SelfCollision&) = delete;

  /// Changes the end positions x1 of the step x0 -> x1 so that no pair that is not excluded
  /// touches at any t in [0,1]: response rounds (math-spec 10.8), then the fail-safe, which
  /// reverts the vertices of each still-touching pair to x0 until none is left. If x0 is free of
  /// contacts (true by induction from the rest state), so is the result.
  ///
  /// With CollisionOptions::warm_start, the previous step's contacts are first projected on x1
  /// (their frozen frames), so a resting contact is not detected and pushed again every step:
  /// those detected in the previous step and those its warm start still had to push (a contact
  /// stays in this cache while it is pressed together, one entry per pair).
  ///
  /// Work is incremental. One broad phase per step, on the swept boxes inflated by (delta + m)/2
  /// for a margin m (CollisionOptions::region_margin; broad_phase_inflation), gives the
  /// candidates of every round and of the fail-safe, because the response is clamped so that no
  /// vertex leaves its swept box grown by m/2 (a push it cannot complete is finished by the
  /// pair's other vertices in a later round, or by the fail-safe, whose revert to x0 stays inside
  /// too). After round 0 only the pairs with a vertex that the previous response moved are tested
  /// again: the others' positions, hence their answers, have not changed. The fail-safe tests the
  /// pairs not known to be free at their current positions. Before the filter, each pair's own
  /// swept boxes are compared (swept_boxes_apart): pairs kept only by the margin leave for a few
  /// nanoseconds.
  /// @param w  inverse masses (pinned vertices are not moved by the response)
  void resolve(const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
               CollisionStepStats& stats);

  /// Starts the broad phase of the step from x0 in the background (CollisionOptions::speculative),
  /// to overlap it with the constraint solve; call it with the solver's initial guess before the
  /// solve, then resolve(x0, solved positions, ...) with the same x0.
  ///
  /// The prediction of each vertex's end position is the guess plus the solve's correction of
  /// the last step, then the warm start (resolve's first move). Each predicted swept box (x0 to
  /// the prediction, inflated as resolve's broad phase) is grown by a skin: SKIN_MIN delta plus
  /// SKIN_GROWTH times the vertex's prediction error of the last step. The grid over these boxes
  /// and the pairs' records are built on a spare thread of the collision arena. resolve() then
  /// keeps the pairs whose actual boxes overlap (every pair of two primitives whose actual boxes
  /// lie inside their predicted ones is among the grid's pairs) and queries the grid again for
  /// the primitives of the vertices whose actual box left the predicted one (plus those pairs
  /// among themselves). If x0 differs, or too many vertices left, resolve runs the plain broad
  /// phase. With CollisionOptions::threads == 1 there is no spare thread: resolve runs the same
  /// task itself (the same result as with more threads, no time gained).
  /// @param x0       the step's start positions
  /// @param x_guess  the solver's initial guess of the end positions (copied)
  /// @param w        inverse masses (the warm start's weights)
  void predict(const Positions& x0, const Positions& x_guess, const Eigen::VectorXd& w);

  /// The contact cache the next step's warm start projects (CollisionOptions::warm_start): the
  /// last resolve's detections and the contacts its warm start still had to push, one per pair.
  const std::vector<Contact>& contact_cache() const;

  /// For tests: whether the last resolve's list of live pairs is what its rounds assume: in
  /// increasing order, none excluded or out of the candidates, each with its stencil beside it.
  bool live_pairs_consistent() const;

  /// The candidate pairs of the last resolve's broad phase, excluded ones included: VF pairs
  /// (vertex, face) and EE pairs (edge a < edge b), each list sorted (for tests and tools).
  /// Not between predict and resolve: the speculative task may be rewriting them.
  std::pair<std::vector<std::array<int, 2>>, std::vector<std::array<int, 2>>> candidate_pairs()
      const;

  /// Number of VF and EE pairs excluded because they touch in the rest state.
  std::size_t excluded_pairs() const;

  const CollisionTopology& topology() const;

  /// What a later step depends on besides the positions (a checkpoint's share,
  /// sim/simulator_state.hpp): the warm start's contact cache, and the speculative broad phase's
  /// last correction and skins, from which it predicts (its pairs, hence the order of the tests).
  /// Meaningful between steps only.
  struct PersistentState {
    std::vector<Contact> contact_cache;
    Positions correction;
    Eigen::VectorXd skin;
  };
  PersistentState persistent_state() const;
  /// Continues from a persistent_state() of a SelfCollision built from the same mesh and options.
  void restore_persistent_state(PersistentState state);

 private:
  struct Impl;  ///< the parts of the pipeline, wired in order (src/collision/self_collision/impl.hpp;
                ///< docs/design/collision-pipeline.md)
  std::unique_ptr<Impl> impl_;
};

}  // namespace shellcontract
