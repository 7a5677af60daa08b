// Writing a polygon soup as read (private to src/mesh; write_mesh.cpp): `repair` writes a usable
// input into another format with the file's own vertices, polygons, order and winding.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "shellcontract/mesh.hpp"

namespace shellcontract {

/// Writes points (input units) and polygons (0-based indices, kept as given: order, corners and
/// winding) with CGAL's polygon-soup writer for the extension (OFF, OBJ, PLY; STL holds triangles
/// only) at 17 significant digits, atomically (temporary file + rename), as write_mesh_atomic.
/// @param binary as write_mesh_atomic's: a binary PLY or STL; OFF and OBJ are text
/// @throws UsageError if the file cannot be written or the extension is unknown
/// @throws std::invalid_argument for a polygon that names a missing point, or that is not a
///         triangle in an STL
void write_polygon_soup_atomic(const std::string& path, const std::vector<Point3>& points,
                               const std::vector<std::vector<std::size_t>>& polygons, bool binary = false);

}  // namespace shellcontract
