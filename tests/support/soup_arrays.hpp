// A mesh as the arrays of the triangle soup that gives it (Python's vertices and faces), and
// those arrays as an OFF file: the fixtures of the tests that give mesh_from_arrays and the file
// reader the same soup.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "shellcontract/mesh_io.hpp"
#include "test_paths.hpp"

namespace shellcontract::test {

/// Positions (x, y, z per vertex) and corners (three per face), flat as numpy's arrays are.
struct SoupArrays {
  std::vector<double> v;
  std::vector<std::int64_t> f;
};

/// `mesh`'s soup: its positions and its faces' corners in index order, as read.
inline SoupArrays arrays_of(const Mesh& mesh) {
  SoupArrays a;
  const Positions x = positions_from_mesh(mesh);
  a.v.assign(x.data(), x.data() + x.size());
  for (const FaceIndex f : mesh.faces())
    for (const VertexIndex v : vertices_around_face(mesh.halfedge(f), mesh)) a.f.push_back(v.idx());
  return a;
}

/// The soup of the test mesh `name` (meshes/).
inline SoupArrays arrays_of_test_mesh(const std::string& name) {
  return arrays_of(read_input_mesh(std::string(MESH_DIR) + "/" + name));
}

/// Writes the soup as an ASCII OFF file at `path`, every double to 17 digits (read back exactly).
inline void write_soup_off(const std::string& path, const SoupArrays& a) {
  std::ofstream off(path);
  off.precision(17);
  off << "OFF\n" << a.v.size() / 3 << " " << a.f.size() / 3 << " 0\n";
  for (std::size_t i = 0; i < a.v.size(); i += 3)
    off << a.v[i] << " " << a.v[i + 1] << " " << a.v[i + 2] << "\n";
  for (std::size_t f = 0; f < a.f.size(); f += 3)
    off << "3 " << a.f[f] << " " << a.f[f + 1] << " " << a.f[f + 2] << "\n";
}

}  // namespace shellcontract::test
