// symmetric_hausdorff_distance: CGAL's bounded-error Hausdorff distance with one Eigen point map
// per side (the CGAL headers stay in this file).
#include "shellcontract/validation.hpp"

#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/boost/graph/helpers.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "mesh/eigen_point_map.hpp"

namespace shellcontract {

namespace {
void check_rows(const Mesh& mesh, const Positions& x, const char* name) {
  if (static_cast<std::size_t>(x.rows()) != mesh.number_of_vertices())
    throw std::invalid_argument(std::string("symmetric_hausdorff_distance: ") + name + " has " +
                                std::to_string(x.rows()) + " rows for " +
                                std::to_string(mesh.number_of_vertices()) + " vertices");
}
}  // namespace

double symmetric_hausdorff_distance(const Mesh& mesh, const Positions& a, const Positions& b,
                                    double error_bound) {
  if (mesh.has_garbage())
    throw std::invalid_argument("symmetric_hausdorff_distance: the mesh has removed elements");
  if (!(error_bound > 0.0) || !std::isfinite(error_bound))
    throw std::invalid_argument("symmetric_hausdorff_distance: error bound must be positive");
  check_rows(mesh, a, "a");
  check_rows(mesh, b, "b");
  if (!CGAL::is_triangle_mesh(mesh) || mesh.is_empty())
    throw std::invalid_argument("symmetric_hausdorff_distance: not a non-empty triangle mesh");
  namespace PMP = CGAL::Polygon_mesh_processing;
  // The bounded-error variant (rather than approximate_Hausdorff_distance's random sampling) so
  // that a table of small errors is reproducible and its accuracy is known.
  return PMP::bounded_error_symmetric_Hausdorff_distance<CGAL::Sequential_tag>(
      mesh, mesh, error_bound, CGAL::parameters::vertex_point_map(EigenPointMap(a)),
      CGAL::parameters::vertex_point_map(EigenPointMap(b)));
}

double max_vertex_distance(const Positions& a, const Positions& b) {
  if (a.rows() != b.rows())
    throw std::invalid_argument("max_vertex_distance: " + std::to_string(a.rows()) + " vs " +
                                std::to_string(b.rows()) + " rows");
  if (a.rows() == 0) return 0.0;
  return (a - b).rowwise().norm().maxCoeff();
}

}  // namespace shellcontract
