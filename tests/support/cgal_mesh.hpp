// Builds a CGAL Surface_mesh from the Eigen fixtures of mesh_fixtures.hpp.
#pragma once

#include <stdexcept>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract::test {

inline Mesh to_surface_mesh(const TriMesh& m) {
  Mesh mesh;
  std::vector<VertexIndex> v;
  for (Eigen::Index i = 0; i < m.x.rows(); ++i)
    v.push_back(mesh.add_vertex(Point3(m.x(i, 0), m.x(i, 1), m.x(i, 2))));
  for (Eigen::Index j = 0; j < m.faces.rows(); ++j)
    if (mesh.add_face(v[m.faces(j, 0)], v[m.faces(j, 1)], v[m.faces(j, 2)]) == Mesh::null_face())
      throw std::runtime_error("fixture is not a manifold mesh");
  return mesh;
}

}  // namespace shellcontract::test
