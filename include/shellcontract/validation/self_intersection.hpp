// Self-intersection tests at given positions (CGAL PMP::self_intersections and
// does_self_intersect through an EigenPointMap; design.md, "validate"). The heavy PMP headers
// stay in the .cpp file.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "shellcontract/core/types.hpp"
#include "shellcontract/mesh/surface_mesh.hpp"

namespace shellcontract {

/// Two faces that intersect, smaller face index first.
using FacePair = std::pair<FaceIndex, FaceIndex>;

/// All pairs of faces that intersect when the vertices are at x. Faces sharing a vertex or an
/// edge count only if they intersect beyond the shared element (CGAL's definition).
/// @param mesh  triangle mesh (connectivity; its own points are ignored)
/// @param x     #V by 3 positions, row i = vertex i, any length unit
/// @pre !mesh.has_garbage(), x.rows() == number of vertices, triangle mesh
/// @return the pairs, each ordered (smaller index first), sorted; empty if none
/// @throws std::invalid_argument if a precondition fails
std::vector<FacePair> self_intersecting_pairs(const Mesh& mesh, const Positions& x);

/// Whether any two faces intersect at positions x; stops at the first pair found (cheaper than
/// self_intersecting_pairs when the answer is usually "no").
/// @pre as for self_intersecting_pairs
bool does_self_intersect(const Mesh& mesh, const Positions& x);

/// Number of intersecting face pairs at positions x that are not in `baseline` (the pairs that
/// the input mesh already had, e.g. elk.off's 7), so that validation blames the simulation only
/// for intersections it created.
/// @param baseline  pairs from self_intersecting_pairs on the input positions (any order)
/// @pre as for self_intersecting_pairs
/// @return count of new pairs (0 when the result adds none)
std::size_t new_self_intersections(const Mesh& mesh, const Positions& x, const std::vector<FacePair>& baseline);

}  // namespace shellcontract
