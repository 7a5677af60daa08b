// The local contraction as a constraint (docs/math/local-contraction.md): each region is closed by
// a fan from the centroid of its rim into a "cap", whose volume measures how far the region
// stands out (> 0) or is sunk in (< 0); a projection drives it to a target (the dimple of
// sim/region_dimple.hpp is such a cap). Eigen only.
#pragma once

#include <vector>

#include "shellcontract/types.hpp"

namespace shellcontract {

/// A region's faces with their own vertex numbering, and its rim.
struct RegionCap {
  std::vector<int> vertices;  ///< mesh vertex ids of the region's corners, sorted
  Faces faces;                ///< the region's faces, as indices into `vertices`, ccw from outside
  std::vector<int> rim;       ///< indices into `vertices` of the rim: corners of a boundary edge
  double rest_volume = 0.0;   ///< cap_volume at the rest positions (set by the caller)
};

/// The cap of the faces `region_faces` (rows of `faces`): a boundary edge is one that a single
/// region face uses. Face ids outside [0, #F) are skipped.
RegionCap make_region_cap(const Faces& faces, const std::vector<int>& region_faces);

/// Volume of the region's faces closed by the fan from the rim's centroid c (the mean of the rim
/// vertices): sum over the faces (a, b, d) of (x_a - c) . ((x_b - c) x (x_d - c)) / 6. The fan's
/// own triangles contain c and add nothing. > 0 for a bump (a convex cap seen from outside), 0 for
/// a flat region, < 0 for a dent; invariant under translation and rotation. A region without a rim
/// (a whole closed component) gives its enclosed volume.
double cap_volume(const Positions& x, const RegionCap& cap);

/// dV/dx for the cap's vertices (cap.vertices.size() by 3, same order): the faces' terms, and
/// minus their sum shared equally by the rim vertices through c. The rows sum to zero, so a
/// mass-weighted projection along it moves no centre of mass (and, V being rotation-invariant,
/// adds no angular momentum).
void cap_volume_gradient(const Positions& x, const RegionCap& cap, Positions& g);

/// Moves the cap's vertices of x onto cap_volume = target with Newton steps
/// dx_i = -w_i lambda dV/dx_i, lambda = (V - target) / sum_i w_i |dV/dx_i|^2, until
/// |V - target| <= tolerance or max_steps steps; returns the steps taken. Nothing moves when the
/// gradient vanishes for the movable vertices.
/// @param w  inverse masses of the whole mesh (#V); w = 0 holds a vertex
int project_cap_volume(Positions& x, const RegionCap& cap, const Eigen::VectorXd& w, double target,
                       double tolerance, int max_steps = 4);

/// The same projection with some vertices held (held[i] != 0: in contact), where a held vertex
/// keeps its share of the correction instead of passing it to the others: lambda is taken over
/// every vertex with its inverse mass w_i, and only the free ones move. So no free vertex moves
/// farther than it would with nothing held, and the target is reached in part (after max_steps
/// steps the error is (1 - f)^max_steps of it, f = the free vertices' share of
/// sum_i w_i |dV/dx_i|^2). Without this, a cap held at all but a few vertices moves those few as
/// far as its whole volume change needs (docs/math/local-contraction.md, section 5).
/// With no vertex held it is project_cap_volume, bit for bit.
/// @param held  #V flags, or empty (nothing held)
int project_cap_volume_sharing(Positions& x, const RegionCap& cap, const Eigen::VectorXd& w,
                               const std::vector<char>& held, double target, double tolerance,
                               int max_steps = 4);

}  // namespace shellcontract
