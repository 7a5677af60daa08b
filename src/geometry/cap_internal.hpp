// Private to the region finder (cap_finder.cpp, cap_arrays.cpp, cap_shape.cpp): the mesh as flat
// arrays, a grown cap and its final shape.
#pragma once

#include <array>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "geometry/sphere_moments.hpp"
#include "shellcontract/mesh.hpp"
#include "shellcontract/regions.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {
struct CurvatureField;
}

namespace shellcontract::detail {

/// Mesh arrays the finder works on (vertex and face indices = idx()).
struct MeshArrays {
  std::size_t nv = 0, nf = 0;
  std::vector<std::array<int, 3>> tri;
  std::vector<double> face_area, vertex_area;            ///< vertex: a third of the incident faces
  /// Vertex v's neighbours nbr_to[k] at edge length nbr_len[k], k in [nbr_start[v],
  /// nbr_start[v + 1]) (flat arrays: the disc growth visits millions of them).
  std::vector<int> nbr_start, nbr_to;
  std::vector<double> nbr_len;
  std::vector<std::array<int, 3>> face_nbr;              ///< across each edge, -1 on a border
  std::vector<std::vector<int>> vertex_faces;
  double total_area = 0.0, size = 0.0;  ///< size = sqrt(total_area)
};

MeshArrays mesh_arrays(const Mesh& mesh, const Positions& x);

/// The widest a region may be: its faces lie within this angle (radians) of its axis, seen from
/// its sphere's centre: a hemisphere. A cap wider than a hemisphere is most of a limb or of a
/// body (a paw's cap of 140 degrees reaches down the arm), and a dimple mirrored through the rim
/// of such a cap turns the limb inside out (docs/math/cap-finder.md).
constexpr double MAX_CAP_ANGLE = 0.5 * 3.14159265358979323846;

/// A grown cap, or a region: its seed, the disc's radius, its fitted sphere and its faces.
struct Cap {
  int seed = -1;
  double rho = 0.0;  ///< geodesic (edge-graph) radius of the accepted disc
  detail::SphereFit sphere;
  /// Grown: the disc's angle from its area, acos(1 - area / (2 pi r^2)); shaped (shape_cap):
  /// the widest face centroid from the axis. Radians.
  double angle = 0.0;
  bool unbounded = false;  ///< the disc still fitted when it reached max_area_fraction
  std::vector<int> faces;
};

/// The area-weighted mean direction from c to the faces' centroids, normalised; zero when
/// there is none (faces all around c).
Vec3 cap_axis(const MeshArrays& m, const Positions& x, const std::vector<int>& faces, const Vec3& c);

/// The final shape of region `id` (the part's faces in cap.faces; owner_face = region per face,
/// -1 for none): with the sphere fitted to the part and its axis (cap_axis about that centre),
/// the faces within MAX_CAP_ANGLE of the axis, flooded over the faces near the sphere (corners
/// within twice the fit's residual of the radius, 0.02 to 0.1) within that angle that no other
/// region owns; the largest edge-connected piece; its holes filled where they lie within the
/// angle and hold no face of another region. Updates cap.faces, cap.sphere (residual: RMS
/// distance of the region's vertices to the sphere / radius), cap.angle and owner_face. False
/// when nothing is left or the part has no axis (faces all around its centre).
bool shape_cap(const MeshArrays& m, const Positions& x, Cap& cap, std::vector<int>& owner_face, int id);

/// select_spherical_regions, handing out the curvature field it computed (when curvature is not
/// null): mark_spherical_regions stores it for the PLY instead of computing it a second time.
std::vector<int> select_spherical_regions(const Mesh& mesh, const Positions& x, const RegionOptions& options,
                                          RegionReport* report, CurvatureField* curvature);

}  // namespace shellcontract::detail
