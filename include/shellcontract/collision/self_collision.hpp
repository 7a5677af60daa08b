// Self-collision handling for one time step (paper section 4, math-spec 10): broad phase,
// non-penetration filter, narrow phase, signed-constraint response in rounds, and a fail-safe
// that guarantees the step creates no new contact. Eigen only (CGAL stays in broad_phase.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "shellcontract/collision/broad_phase.hpp"
#include "shellcontract/collision/contact.hpp"
#include "shellcontract/core/types.hpp"

namespace shellcontract {

/// Options of the collision handling (normalized units: bounding-box diagonal 1).
struct CollisionOptions {
  /// delta: contact distance. Primitives that come closer than delta during a step are pushed
  /// apart to 2 delta (math-spec 10.8, 14: paper value 1e-4, here relative to the diagonal).
  double delta = 1e-4;
  int rounds = 5;  ///< N_c detection/response rounds before the fail-safe (math-spec 10.8)
  BroadPhaseMethod method = DEFAULT_BROAD_PHASE_METHOD;
};

/// Counters of one step (CSV log) and the stages of the paper's Table 2.
struct CollisionStepStats {
  std::int64_t pairs_no_culling = 0;  ///< all non-adjacent VF + EE pairs
  std::int64_t pairs_broad = 0;       ///< after the broad phase (first round)
  std::int64_t pairs_filtered = 0;    ///< left after the non-penetration filter (first round)
  std::int64_t narrow_tests = 0;      ///< narrow-phase (cubic) tests run, all rounds
  std::int64_t contacts = 0;          ///< contacts found, all rounds
  int rounds = 0;                     ///< detection rounds run
  std::int64_t failsafe_vertices = 0; ///< vertices reverted to their start position
  std::int64_t unresolved = 0;        ///< static pairs still reported after the fail-safe
  double broad_seconds = 0.0;
  double filter_seconds = 0.0;
  double narrow_seconds = 0.0;
  double response_seconds = 0.0;
  double total_seconds() const { return broad_seconds + filter_seconds + narrow_seconds + response_seconds; }
};

/// Keeps a deforming closed mesh from passing through itself.
class SelfCollision {
 public:
  /// @param faces     #F by 3 faces
  /// @param rest      #V by 3 rest positions: primitive pairs that already touch there are
  ///                  excluded from then on; pairs closer than delta there get no response push
  ///                  (the rest state is kept) but are still kept from crossing
  /// @param options   see CollisionOptions
  SelfCollision(const Faces& faces, const Positions& rest, const CollisionOptions& options);

  /// Changes the end positions x1 of the step x0 -> x1 so that no pair that is not excluded
  /// touches at any t in [0,1]: response rounds (math-spec 10.8), then the fail-safe, which
  /// reverts the vertices of each still-touching pair to x0 until none is left. If x0 is free of
  /// contacts (true by induction from the rest state), so is the result.
  /// @param w  inverse masses (pinned vertices are not moved by the response)
  void resolve(const Positions& x0, Positions& x1, const Eigen::VectorXd& w, CollisionStepStats& stats);

  /// Number of VF and EE pairs excluded because they touch in the rest state.
  std::size_t excluded_pairs() const { return excluded_vf_.size() + excluded_ee_.size(); }

  const CollisionTopology& topology() const { return topo_; }

 private:
  /// Which of the pairs that were closer than delta at rest a detection pass tests.
  enum class NearPairs { Include, Skip, Only };

  /// Narrow phase over the current candidates with tolerance tol; appends contacts. Excluded
  /// (touching at rest) pairs are always skipped.
  void detect(const Positions& x0, const Positions& x1, double tol, std::vector<Contact>& out,
              CollisionStepStats* stats, bool count_stage, NearPairs near);

  CollisionTopology topo_;
  CollisionOptions options_;
  CandidatePairs candidates_;
  std::vector<std::array<int, 2>> excluded_vf_;  ///< sorted
  std::vector<std::array<int, 2>> excluded_ee_;  ///< sorted
  std::vector<std::array<int, 2>> near_vf_;      ///< closer than delta at rest, sorted
  std::vector<std::array<int, 2>> near_ee_;      ///< closer than delta at rest, sorted
  std::vector<Contact> contacts_;
};

}  // namespace shellcontract
