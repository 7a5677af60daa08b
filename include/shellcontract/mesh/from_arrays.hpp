// A checked Mesh from in-memory arrays (the Python module's numpy input, a C++ caller's buffers),
// with the checks and messages of read_input_mesh (mesh/io.hpp) for a triangle soup.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "shellcontract/mesh/io.hpp"
#include "shellcontract/mesh/surface_mesh.hpp"

namespace shellcontract {

/// A read-only view of a triangle soup held by the caller; nothing is copied until the Mesh is
/// built. Rows are C-contiguous: vertex i is vertices[3i .. 3i+2], face j is faces[3j .. 3j+2].
/// Exactly one of faces32 / faces64 is set.
struct TriangleSoupView {
  const double* vertices = nullptr;  ///< #V by 3, any length unit
  std::size_t num_vertices = 0;
  const std::int32_t* faces32 = nullptr;  ///< #F by 3 vertex indices, 0-based
  const std::int64_t* faces64 = nullptr;  ///< #F by 3 vertex indices, 0-based
  std::size_t num_faces = 0;
};

/// Builds the mesh of a triangle soup after the checks read_input_mesh applies to a file: finite
/// coordinates, indices in range, no repeated corner, no duplicate face, no isolated vertex, every
/// edge shared by exactly two faces in opposite directions (closed, manifold, consistently
/// oriented), one fan per vertex. Zero-area faces are reported. Vertex and face order are kept,
/// and each face lists its corners as given.
/// @param name     what the messages call the input (read_input_mesh uses the file name)
/// @param reorient flip inside-out components as read_input_mesh does (with a warning); false
///                 keeps the faces exactly as given (writing a result back)
/// @throws InputError "<name>: <problem>: <where and details>", as read_input_mesh
Mesh mesh_from_arrays(const TriangleSoupView& soup, const std::string& name,
                      InputReport* report = nullptr, bool reorient = true);

}  // namespace shellcontract
