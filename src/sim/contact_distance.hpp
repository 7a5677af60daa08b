// The contact distance of --delta auto: the paper's delta, or a fixed share of the mesh's mean
// edge length where that is smaller (lab/pages/pair-growth.md).
#pragma once

#include "shellcontract/mesh.hpp"

namespace shellcontract {

/// delta over the mean edge length that --delta auto keeps at most. The paper's bear has 1/88
/// (delta 1e-4, mean edge 0.0088 of the diagonal), so 1/80 leaves it, and every mesh as coarse,
/// at the paper's delta. A contact distance that is a fixed share of the diagonal is a growing
/// share of a finer mesh's edges: each face has more neighbours within it, and the broad phase's
/// candidate pairs per face grow with the resolution, while a delta kept at the same share of the
/// mean edge keeps them near the coarse mesh's count (lab/pages/pair-growth.md).
inline constexpr double AUTO_DELTA_PER_MEAN_EDGE = 1.0 / 80.0;

/// Mean length of the mesh's edges (each edge once), in the mesh's units; 0 for a mesh without
/// edges.
double mean_edge_length(const Mesh& mesh);

/// min(cap, AUTO_DELTA_PER_MEAN_EDGE * mean_edge_length(mesh)), or cap if the mesh has no edge of
/// positive length. `mesh` in normalized units (bounding-box diagonal 1), as cap.
double auto_contact_distance(const Mesh& mesh, double cap);

}  // namespace shellcontract
