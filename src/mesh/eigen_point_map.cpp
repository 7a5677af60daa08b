// positions_from_mesh: the one place where mesh points become the simulation's position array.
#include "mesh/eigen_point_map.hpp"

#include <stdexcept>

namespace shellcontract {

Positions positions_from_mesh(const Mesh& mesh) {
  // Row i is vertex i only when the index range has no holes (house-style.md section 3).
  if (mesh.has_garbage())
    throw std::invalid_argument("positions_from_mesh: the mesh has removed elements; call collect_garbage() first");
  Positions x(static_cast<Eigen::Index>(mesh.number_of_vertices()), 3);
  for (const VertexIndex v : mesh.vertices()) {
    const Point3& p = mesh.point(v);
    x.row(static_cast<Eigen::Index>(v.idx())) << p.x(), p.y(), p.z();
  }
  return x;
}

}  // namespace shellcontract
