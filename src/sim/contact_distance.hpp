// The contact distance of --delta auto: the paper's delta, or a fixed share of the mesh's mean
// edge length where that is smaller (lab/pages/pair-growth.md), or half the rest state's smallest
// gap where that is smaller still; and the bound on a given delta.
#pragma once

#include <string>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/simulation_options.hpp"

namespace shellcontract {

/// delta over the mean edge length that --delta auto keeps at most. The paper's bear has 1/88
/// (delta 1e-4, mean edge 0.0088 of the diagonal), so 1/80 leaves it, and every mesh as coarse,
/// at the paper's delta. A contact distance that is a fixed share of the diagonal is a growing
/// share of a finer mesh's edges: each face has more neighbours within it, and the broad phase's
/// candidate pairs per face grow with the resolution, while a delta kept at the same share of the
/// mean edge keeps them near the coarse mesh's count (lab/pages/pair-growth.md).
inline constexpr double AUTO_DELTA_PER_MEAN_EDGE = 1.0 / 80.0;

/// A given delta over the mean edge length above which the run is refused. A pair of primitives
/// that are not neighbours (a vertex and a face across its one-ring's edges, two edges across a
/// triangle) lies about a triangle's height apart at rest, less on a mesh with uneven edges, and
/// a pair that comes within delta is pushed apart to 2 delta. Once 2 delta nears that spacing,
/// pairs are in contact at rest (held there: choose_contact_distance) and each push drives its
/// pair into their other neighbours, which are pushed in turn: the shell swells instead of
/// contracting while the fail-safe reverts most vertices every step. An eighth of the mean edge
/// keeps 2 delta a quarter of it; --delta auto (at most 1/80) is never refused, nor is the
/// default (CollisionOptions::delta) on a mesh fine enough for it to exceed the share.
inline constexpr double MAX_DELTA_PER_MEAN_EDGE = 1.0 / 8.0;

/// --delta auto's delta over the smallest rest gap (collision/rest_gap.hpp) where that gap is
/// below the edge-based choice: half the gap leaves every pair that does not touch at rest out of
/// contact there, so none is held at its rest distance.
inline constexpr double AUTO_DELTA_PER_REST_GAP = 0.5;

/// The share of the edge-based choice below which --delta auto does not go for a small rest gap:
/// a gap that much smaller is a near-degenerate input (a fold, a sliver), and a contact distance
/// at such a scale would let the rest of the mesh pass through itself within rounding.
inline constexpr double AUTO_DELTA_FLOOR_SHARE = 1e-3;

/// The contact distance of a run and what the user should know about it.
struct ContactDistanceChoice {
  double delta = 0.0;
  std::vector<std::string> warnings;
  /// Nearly every vertex is held at rest by pairs closer than delta (a flat or very thin shell):
  /// a warning says "nothing can move" and names the remedy, so the run's frozen-run warning,
  /// whose remedies do not apply, is not given as well.
  bool held_at_rest = false;
};

/// The contact distance for `mesh` (normalized units) with `options` (resolved): with auto_delta,
/// auto_contact_distance, lowered to AUTO_DELTA_PER_REST_GAP of the smallest rest gap if that is
/// smaller (not below AUTO_DELTA_FLOOR_SHARE of the edge-based choice); otherwise
/// options.collision.delta. Warns when pairs that do not touch at rest are closer than the
/// chosen delta there (the collision step holds them at their rest distance, hence in place).
/// @throws UsageError if a given delta is above MAX_DELTA_PER_MEAN_EDGE of the mean edge and above
///         the default
ContactDistanceChoice choose_contact_distance(const Mesh& mesh, const SimOptions& options);

/// Mean length of the mesh's edges (each edge once), in the mesh's units; 0 for a mesh without
/// edges.
double mean_edge_length(const Mesh& mesh);

/// min(cap, AUTO_DELTA_PER_MEAN_EDGE * mean_edge_length(mesh)), or cap if the mesh has no edge of
/// positive length. `mesh` in normalized units (bounding-box diagonal 1), as cap.
double auto_contact_distance(const Mesh& mesh, double cap);

}  // namespace shellcontract
