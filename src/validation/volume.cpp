// enclosed_volume: PMP::volume with the position array as vertex point map; surface_topology.
#include "shellcontract/validation.hpp"

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/boost/graph/helpers.h>

#include <stdexcept>
#include <string>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {

namespace {

/// The guards both functions keep: removed elements or a row count that differs from the
/// vertex count would index past the rows of x.
void check_positions(const Mesh& mesh, const Positions& x) {
  if (mesh.has_garbage())
    throw std::invalid_argument("enclosed_volume: the mesh has removed elements; call collect_garbage() first");
  if (static_cast<std::size_t>(x.rows()) != mesh.number_of_vertices())
    throw std::invalid_argument("enclosed_volume: " + std::to_string(x.rows()) + " position rows for " +
                                std::to_string(mesh.number_of_vertices()) + " vertices");
}

double pmp_volume(const Mesh& mesh, const Positions& x) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  return PMP::volume(mesh, CGAL::parameters::vertex_point_map(EigenPointMap(x)));
}

}  // namespace

double enclosed_volume(const Mesh& mesh, const Positions& x) {
  check_positions(mesh, x);
  if (!CGAL::is_triangle_mesh(mesh)) throw InputError("enclosed_volume: not a triangle mesh");
  if (!CGAL::is_closed(mesh)) {
    std::size_t border = 0;
    for (const EdgeIndex e : mesh.edges())
      if (mesh.is_border(e)) ++border;
    throw InputError("enclosed_volume: the mesh is not closed (" + std::to_string(border) +
                     " border edges), so it encloses no volume");
  }
  return pmp_volume(mesh, x);
}

double enclosed_volume_unchecked(const Mesh& mesh, const Positions& x) {
  check_positions(mesh, x);
  return pmp_volume(mesh, x);
}

SurfaceTopology surface_topology(const Mesh& mesh, std::size_t components) {
  SurfaceTopology t;
  t.euler_characteristic = static_cast<long long>(mesh.number_of_vertices()) -
                           static_cast<long long>(mesh.number_of_edges()) +
                           static_cast<long long>(mesh.number_of_faces());
  t.genus = (2 * static_cast<long long>(components) - t.euler_characteristic) / 2;
  return t;
}

}  // namespace shellcontract
