#include "shellcontract/mesh/reconstruction.hpp"

#include <CGAL/IO/read_points.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/poisson_surface_reconstruction.h>
#include <CGAL/property_map.h>

#include <string>
#include <utility>
#include <vector>

#include "shellcontract/core/error.hpp"

namespace shellcontract {

Mesh reconstruct_from_oriented_points(const std::string& path, const ReconstructionOptions& options) {
  using Vector3 = Kernel::Vector_3;
  using PointWithNormal = std::pair<Point3, Vector3>;
  std::vector<PointWithNormal> points;
  if (!CGAL::IO::read_points(path, std::back_inserter(points),
                             CGAL::parameters::point_map(CGAL::First_of_pair_property_map<PointWithNormal>())
                                 .normal_map(CGAL::Second_of_pair_property_map<PointWithNormal>())))
    throw InputError(path + ": cannot read an oriented point set (x y z nx ny nz per line)");
  if (points.size() < 10)
    throw InputError(path + ": only " + std::to_string(points.size()) + " points; need an oriented point set");
  const double spacing = CGAL::compute_average_spacing<CGAL::Sequential_tag>(
      points, options.spacing_neighbours,
      CGAL::parameters::point_map(CGAL::First_of_pair_property_map<PointWithNormal>()));
  Mesh mesh;
  if (!(spacing > 0.0) ||
      !CGAL::poisson_surface_reconstruction_delaunay(
          points.begin(), points.end(), CGAL::First_of_pair_property_map<PointWithNormal>(),
          CGAL::Second_of_pair_property_map<PointWithNormal>(), mesh, spacing, options.angle,
          options.radius, options.distance))
    throw InputError(path + ": Poisson surface reconstruction failed");
  if (!CGAL::is_closed(mesh) || !CGAL::is_triangle_mesh(mesh))
    throw InputError(path + ": the reconstructed surface is not a closed triangle mesh");
  // Outward orientation, as the simulator expects (math-spec 1.1).
  if (!CGAL::Polygon_mesh_processing::is_outward_oriented(mesh))
    CGAL::Polygon_mesh_processing::reverse_face_orientations(mesh);
  mesh.collect_garbage();
  return mesh;
}

}  // namespace shellcontract
