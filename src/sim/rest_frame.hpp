// The run's frame follows the rest of the shell while a local contraction acts: each step, the
// rigid part of the step of the vertices away from the regions (their shift and their turn) is
// taken out of every vertex.
#pragma once

#include <vector>

#include "shellcontract/types.hpp"

namespace shellcontract {

/// Relative size below which the smallest principal moment of the outside vertices' inertia
/// counts as zero (they lie on a line or at a point): their turn is then undefined and only the
/// shift is taken out. Far above rounding, and a ratio, so independent of the mesh's units.
inline constexpr double TURN_RANK_TOLERANCE = 1e-9;

/// Moves x (the step's end positions) so that the outside vertices (`outside`, indices into x)
/// make no rigid step from `prev` (the step's start): first by minus their mass-weighted mean
/// displacement, then by the affine map x_i -= omega x (x_i - c), c their mass centre at `prev`,
/// with omega such that their net turn about c, sum_k m_k r_k x d_k (r_k = prev_k - c, d_k = x_k -
/// prev_k), is zero afterwards (to first order omega is the linearized Kabsch rotation of the step,
/// I omega = sum_k m_k r_k x d_k with I the inertia of the r_k). Afterwards sum_k m_k d_k = 0 and
/// sum_k m_k r_k x d_k = 0 to rounding. Being affine, the map keeps a configuration free of
/// intersections. Masses are 1 / inv_mass; vertices with inv_mass <= 0 are left out of the sums.
/// docs/math/region-mirror.md, section 3.
void follow_rest_frame(Positions& x, const Positions& prev, const Eigen::VectorXd& inv_mass,
                       const std::vector<int>& outside);

}  // namespace shellcontract
