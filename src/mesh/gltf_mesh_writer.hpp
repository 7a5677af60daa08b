// Writing a bare triangle mesh as a glTF 2.0 file (private to src/mesh; repair_output.cpp):
// `repair`'s .glb and .gltf outputs where there is no glTF document of the input to write back
// (a repaired mesh, or a usable mesh of another format). The layout is that of the run's .glb
// (export/gltf_buffer.hpp, tinygltf's serializer) without frames or materials.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "shellcontract/mesh.hpp"

namespace shellcontract {

/// Writes the triangles on `points` as glTF 2.0, atomically (write_file_atomic: a failure leaves
/// no file): one scene, one node whose translation is the points' bounding-box centre
/// (gltf_centre, JSON doubles) unless the points stored as they are lose no more digits (then
/// none), one mesh, one triangle primitive with POSITION (float32 relative to the translation,
/// with min and max), NORMAL (float32, area-weighted vertex normals, unit
/// length; vertices at bitwise-identical positions, the copies of a split seam, share theirs) and
/// unsigned 32-bit indices, triangles and corners in the order given.
/// @param binary true: a .glb (JSON and BIN chunks); false: a .gltf, JSON whose buffer is
///        embedded as a base64 data URI, so that the file stands alone as the .glb does
/// @throws std::invalid_argument for no points or no triangles, a polygon that is not a triangle
///         or names a missing point, or a coordinate that is not finite
/// @throws UsageError if the file cannot be written, the mesh has more vertices than 32-bit
///         indices reach, or a position relative to the centre is beyond float32's range
void write_gltf_mesh_atomic(const std::string& path, const std::vector<Point3>& points,
                            const std::vector<std::vector<std::size_t>>& triangles, bool binary);

/// `points` as a reader of write_gltf_mesh_atomic's file places them: each coordinate relative to
/// the node's translation rounded to float32, plus the translation (a coordinate beyond
/// float32's range relative to it comes back infinite).
std::vector<Point3> points_as_stored_in_gltf(const std::vector<Point3>& points);

}  // namespace shellcontract
