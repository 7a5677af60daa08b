// Which corners at one position share a new normal (docs/design/attributes.md, "glTF inputs").
// A file that stores a normal per vertex copy says where its shading is smooth and where it is
// hard: copies at one position with one normal (a UV seam, an edge between primitives) are one
// smooth vertex, copies with different normals (a flat-shaded side, a hard edge) are one vertex
// per side. The new normals keep that: each group gets the area-weighted sum over its own
// triangles only.
#pragma once

#include <cstddef>
#include <vector>

#include "shellcontract/types.hpp"

namespace shellcontract::soup {

/// Two unit input normals closer than this (the chord between them, about the angle in radians)
/// are the same normal: far above a float rounding of one unit vector (a few 1e-8 per
/// component, also after two node transforms bring it to world space), far below any hard edge
/// an artist makes (degrees), and too small a difference to show in shading.
inline constexpr double kSameNormal = 1e-5;

/// Per vertex, its normal group (numbered from 0 in order of each group's first vertex): the
/// vertices at one position (`rep`: soup::first_at_same_position) whose input normals are the
/// same, compared with the group's first vertex within kSameNormal.
/// @param rep per vertex, the first vertex at its position (rep[v] <= v)
/// @param dir per vertex, its input normal as a unit vector; zero for a vertex with none (no
///            NORMAL, or one of no length): those at one position are one group of their own
std::vector<std::size_t> normal_groups(const std::vector<std::size_t>& rep,
                                       const std::vector<Vec3>& dir);

/// Per file corner, its normal group among the copies welded into its vertex, for
/// MeshDocument::normal_groups (the glTF animation's hard edges): normal_groups with the copies
/// of one welded vertex as one position; -1 for a corner whose vertex has no normal.
/// @param welded        per file vertex, its simulation vertex (input_vertex_map)
/// @param dir           per file vertex, as normal_groups
/// @param corner_vertex per file corner, its vertex
/// @return empty when no vertex has a normal
std::vector<long long> welded_corner_groups(const std::vector<std::size_t>& welded,
                                            const std::vector<Vec3>& dir,
                                            const std::vector<std::size_t>& corner_vertex);

}  // namespace shellcontract::soup
