// Regions and their strength from a per-vertex weight in [0, 1] (--region-weights FILE, Python
// region_weights=W): how Blender's vertex groups, Houdini's Vellum and Unreal's weight maps
// mark where an effect acts and how strongly. docs/design/keyframes.md, "Weights".
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// Face map of the weighted regions: the face's weight, the mean of its three vertex weights, in
/// [0, 1]. The local contraction's strength on the face is --region-shrink times it.
inline constexpr const char* REGION_WEIGHT_MAP = "f:region_weight";

/// Reads a weight file: one number in [0, 1] per line, line k for the k-th vertex of the mesh
/// file (its vertex order); blank lines and lines starting with '#' are skipped.
/// @throws InputError "<path>:<line>: <problem>" for a token that is not a number, a weight
///         outside [0, 1], two values on a line or more weights than vertices; "<path>: N weights
///         for M vertices" for too few; "<path>: cannot open" when it cannot be read
std::vector<double> read_vertex_weights(const std::string& path, std::size_t num_vertices);

/// Checks weights given as an array (Python): one per vertex, each in [0, 1].
/// @param what  how the message names the array ("region_weights")
/// @throws UsageError "<what>: N weights for M vertices" or "<what>[i] = w is outside [0, 1]"
void check_vertex_weights(const std::vector<double>& weights, std::size_t num_vertices,
                          const std::string& what);

/// The mean of each face's three vertex weights (faces of a garbage-free mesh, in face order).
std::vector<double> face_weights(const Mesh& mesh, const std::vector<double>& vertex_weights);

/// Marks the regions of weighted faces: every edge-connected set of faces with weight > 0 is one
/// region ("f:region", ids by lowest face id), the faces with weight 0 are outside; the face
/// weights go to REGION_WEIGHT_MAP.
/// @param vertex_weights  checked weights (read_vertex_weights, check_vertex_weights)
/// @return the number of regions
std::size_t mark_weighted_regions(Mesh& mesh, const std::vector<double>& vertex_weights);

/// Attaches the strengths of a face-list file's regions (read_region_file_with_strengths) as
/// REGION_WEIGHT_MAP: each face of regions[r] gets strength[r], the other faces 0. Attaches
/// nothing when every strength is 1, so a file without strengths runs as it did before them.
/// @param strength  one per region, each in [0, 1]
void store_region_strengths(Mesh& mesh, const std::vector<std::vector<int>>& regions,
                            const std::vector<double>& strength);

/// The weights of REGION_WEIGHT_MAP, one per face; empty when the map is not attached (every
/// region then acts at the full --region-shrink).
std::vector<double> stored_region_weights(const Mesh& mesh);

/// The area-weighted mean of a region's face weights at positions x (the rest state): the
/// strength factor of the region's dimple. 1 when `weight` is empty (no weights), 0 for a
/// region of zero area.
double mean_region_weight(const Positions& x, const Faces& faces, const std::vector<int>& region,
                          const std::vector<double>& weight);

}  // namespace shellcontract
