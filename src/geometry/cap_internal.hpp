// Private to the region finder (cap_finder.cpp, cap_merge.cpp): the mesh as flat arrays and a
// grown cap.
#pragma once

#include <array>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "geometry/sphere_moments.hpp"
#include "shellcontract/mesh.hpp"
#include "shellcontract/regions.hpp"
#include "shellcontract/types.hpp"

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

/// A grown cap: the disc's radius, its fitted sphere and its faces.
struct Cap {
  int seed = -1;
  double rho = 0.0;  ///< geodesic (edge-graph) radius of the accepted disc
  detail::SphereFit sphere;
  double angle = 0.0;  ///< rho / radius, radians
  bool unbounded = false;  ///< the disc still fitted when it reached max_area_fraction
  std::vector<int> faces;
};

/// Merges kept caps that are parts of one part: two caps whose gap (the faces between them, with
/// corners on both) is convex (at most options.max_concave_fraction of its corners' area has
/// concave_field < 0) become one region with the gap, when the union stays within
/// options.max_compactness and options.max_area_fraction. A crease between a head and an ear is
/// concave and keeps them apart; two caps of one head meet on a convex band and are joined.
/// Caps are taken in their order (the rank), so the result does not depend on the vertex order.
/// The merged cap keeps the first cap's seed and the larger angle; its sphere is refitted.
std::vector<Cap> merge_adjacent_caps(const Mesh& mesh, const MeshArrays& m, const Positions& x,
                                     const Eigen::VectorXd& concave_field, std::vector<Cap> caps,
                                     const RegionOptions& options);

}  // namespace shellcontract::detail
