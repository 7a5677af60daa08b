// Brute-force distances from a point to a mesh's surface, computed otherwise than the product's
// closest point (region_at.cpp uses the collision step's point_triangle_closest, which walks a
// triangle's Voronoi regions; here the plane's foot and the
// three edges), so that the region-at tests check select_regions_at against an independent answer.
#pragma once

#include <CGAL/boost/graph/iterator.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract::test {

/// Distance from p to triangle abc: the smallest of the distances to the plane's foot (when it
/// falls inside) and to the three edges.
inline double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const auto to_segment = [&](const Vec3& u, const Vec3& v) {
    const double len2 = (v - u).squaredNorm();
    const double s = len2 > 0.0 ? std::clamp((p - u).dot(v - u) / len2, 0.0, 1.0) : 0.0;
    return (p - (u + s * (v - u))).norm();
  };
  double d = std::min({to_segment(a, b), to_segment(b, c), to_segment(c, a)});
  const Vec3 n = (b - a).cross(c - a);
  if (n.norm() > 0.0) {
    const Vec3 nn = n.normalized();
    const Vec3 foot = p - nn * (p - a).dot(nn);
    const bool inside = (b - a).cross(foot - a).dot(n) >= 0.0 &&
                        (c - b).cross(foot - b).dot(n) >= 0.0 &&
                        (a - c).cross(foot - c).dot(n) >= 0.0;
    if (inside) d = std::min(d, (p - foot).norm());
  }
  return d;
}

struct NearestFace {
  std::size_t face = 0;
  double distance = std::numeric_limits<double>::infinity();
};

/// The face nearest to p (the first of equals) and its distance, over every face of the mesh.
inline NearestFace nearest_face(const Mesh& mesh, const Positions& x, const Vec3& p) {
  NearestFace best;
  for (FaceIndex f : mesh.faces()) {
    std::vector<Vec3> c;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      c.emplace_back(x.row(v.idx()));
    const double d = distance_to_triangle(p, c[0], c[1], c[2]);
    if (d < best.distance) best = {static_cast<std::size_t>(f.idx()), d};
  }
  return best;
}

}  // namespace shellcontract::test
