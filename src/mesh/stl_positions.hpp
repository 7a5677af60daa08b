// An STL stores each facet's corners as coordinates and no vertex identity: its readers (CGAL's,
// ours) merge equal positions into one vertex. Every writer of an STL (write_mesh_atomic, repair's
// output, run's -o and frames) refuses a mesh that would come back as another one, so that what
// is written can be read back (private to src/mesh and cli/).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "shellcontract/mesh.hpp"

namespace shellcontract {

/// @param what     the start of the message ("cannot write 'a.stl'", "-o a.stl")
/// @param points   the positions the file stores, one per written vertex
/// @param vertex_of per point, the vertex it is a copy of (a mesh welded along its seams writes
///                 each copy of a vertex at its position: read back, they are that vertex again);
///                 empty: every point is its own vertex
/// @param floats   the file stores 32-bit floats (a binary STL): positions equal as floats merge
/// Points with a coordinate that is not finite are skipped (the writers refuse them themselves).
/// @throws UsageError naming two points (in the written numbering) that would be stored at one
///         position, and the position
void require_distinct_stl_positions(const std::string& what,
                                    const std::vector<std::array<double, 3>>& points,
                                    const std::vector<std::size_t>& vertex_of, bool floats);

/// require_distinct_stl_positions for write_mesh_atomic's arguments (x: one row per mesh vertex,
/// or per input vertex of a welded mesh), as the file would store them (input_positions).
/// @throws UsageError as require_distinct_stl_positions
void require_distinct_stl_positions(const std::string& what, const Mesh& mesh, const Positions& x,
                                    bool floats);

}  // namespace shellcontract
