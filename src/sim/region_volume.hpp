// The local contraction as a constraint (docs/math/local-contraction.md): each region is closed by
// a fan from the centroid of its rim into a "cap", whose volume measures how far the region
// stands out (> 0) or is sunk in (< 0); a projection drives it to a target (the dimple of
// sim/region_dimple.hpp is such a cap). Eigen only.
#pragma once

#include <limits>
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

/// The edge-connected pieces of a region: its faces (rows of `faces`; ids outside [0, #F) and
/// repeats dropped) grouped by shared edges, each piece sorted, the pieces in the order of their
/// smallest face. A cap is one piece: the fan from one centroid over the rims of several pieces
/// closes a solid through the shell between them (two triangles on opposite sides of a cube
/// enclose a sixth of it), and sinking that "cap" drives the pieces through each other. So each
/// piece sinks as a dimple of its own (docs/math/local-contraction.md, section 2). Faces that
/// touch at a corner only are separate pieces: a cap's rim passes a vertex once.
std::vector<std::vector<int>> region_pieces(const Faces& faces,
                                            const std::vector<int>& region_faces);

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

/// The farthest rim vertex from the rim's centroid at x (every vertex from their centroid for a
/// cap without a rim): the cap's size, the bound of project_cap_volume's max_move.
double cap_reach(const Positions& x, const RegionCap& cap);

/// Moves the cap's vertices of x onto cap_volume = target with Newton steps
/// dx_i = -w_i lambda dV/dx_i, lambda = (V - target) / sum_i w_i |dV/dx_i|^2, until
/// |V - target| <= tolerance or max_steps steps; returns the steps taken. Nothing moves when the
/// gradient vanishes for the movable vertices. No vertex moves farther than max_move in one call:
/// a step that would is cut short along its direction and ends the call (the rest is left to the
/// next call). A cap whose every vertex is on its rim reaches V = 0 by shrinking onto its rim's
/// centroid, where the gradient (quadratic in the cap's size) vanishes and lambda grows without
/// bound: four such steps threw a cube's faces through each other and out of the mesh.
/// @param w  inverse masses of the whole mesh (#V); w = 0 holds a vertex
/// @param max_move  the farthest a vertex moves in one call (no bound by default)
int project_cap_volume(Positions& x, const RegionCap& cap, const Eigen::VectorXd& w, double target,
                       double tolerance, int max_steps = 4,
                       double max_move = std::numeric_limits<double>::infinity());

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
                               int max_steps = 4,
                               double max_move = std::numeric_limits<double>::infinity());

}  // namespace shellcontract
