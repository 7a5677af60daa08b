// Our own PLY reader. CGAL 5.5's reader crashes on legal and on malformed files
// (README, Limitations), so read_input_mesh and reconstruct never hand it a PLY file.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace shellcontract {

/// What a PLY file holds for a mesh or an oriented point set.
struct PlyData {
  std::vector<std::array<double, 3>> points;   ///< x, y, z of element "vertex", in file order
  std::vector<std::array<double, 3>> normals;  ///< nx, ny, nz of "vertex", if all three are present
  std::vector<std::vector<std::size_t>> faces;  ///< "vertex_indices" (or "vertex_index") of element "face"
  std::vector<std::size_t> vertex_line;  ///< ascii only: 1-based line where vertex i starts
  std::vector<std::size_t> face_line;    ///< ascii only: 1-based line where face i starts
};

/// Parses a PLY file held in memory: format ascii, binary_little_endian or binary_big_endian;
/// any numeric type for the vertex properties (char/int8 ... double/float64); list properties
/// with any integer count and index types; other elements and properties are skipped. Every
/// declared count is checked against the bytes that follow the header before anything is
/// allocated for it. Face indices are not checked against the vertex count (the caller does).
/// @param path  the file's name, for messages only
/// @param bytes the whole file
/// @throws InputError "<path>: <problem>: <where>" for anything that is not a valid PLY file
PlyData read_ply(const std::string& path, const std::string& bytes);

}  // namespace shellcontract
