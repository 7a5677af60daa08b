// A region's table row recomputed from its face list alone, independently of the finder's code
// (docs/design/regions.md, "Output"): the area-weighted least-squares sphere of the region's
// vertices (weights: a third of each vertex's incident faces, over the whole mesh), the
// area-weighted RMS distance of those vertices to it over its radius, and the widest face
// centroid from the region's axis (the area-weighted mean unit direction from the centre to the
// face centroids). Used by test_region_at_bound.cpp and test_cli_regions.cpp.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "shellcontract/types.hpp"

namespace shellcontract::test {

struct MeasuredRegion {
  Vec3 centre = Vec3::Zero();
  double radius = 0.0, residual = 0.0, angle_deg = 0.0;
  double area = 0.0, total_area = 0.0;
};

/// faces: #F x 3 vertex ids (any Eigen integer matrix); region: the region's face ids.
template <class FaceArray>
MeasuredRegion measure_region(const Positions& x, const FaceArray& faces,
                              const std::vector<int>& region) {
  const auto nv = static_cast<std::size_t>(x.rows());
  const auto corner = [&](int f, int k) { return Vec3(x.row(faces(f, k))); };
  const auto face_area = [&](int f) {
    return 0.5 * (corner(f, 1) - corner(f, 0)).cross(corner(f, 2) - corner(f, 0)).norm();
  };
  std::vector<double> vertex_area(nv, 0.0);
  MeasuredRegion out;
  for (int f = 0; f < static_cast<int>(faces.rows()); ++f) {
    out.total_area += face_area(f);
    for (int k = 0; k < 3; ++k)
      vertex_area[static_cast<std::size_t>(faces(f, k))] += face_area(f) / 3.0;
  }
  std::set<int> verts;
  for (int f : region) {
    out.area += face_area(f);
    for (int k = 0; k < 3; ++k) verts.insert(faces(f, k));
  }
  // Weighted Kasa fit, |p|^2 = 2 c.p + d, about the vertices' mean (conditioning), solved by QR.
  Vec3 mean = Vec3::Zero();
  for (int v : verts) mean += Vec3(x.row(v));
  mean /= static_cast<double>(verts.size());
  Eigen::MatrixXd A(static_cast<Eigen::Index>(verts.size()), 4);
  Eigen::VectorXd b(A.rows());
  Eigen::Index i = 0;
  for (int v : verts) {
    const Vec3 q = Vec3(x.row(v)) - mean;
    const double w = std::sqrt(vertex_area[static_cast<std::size_t>(v)]);
    A.row(i) << 2.0 * w * q.transpose(), w;
    b(i) = w * q.squaredNorm();
    ++i;
  }
  const Eigen::Vector4d s = A.colPivHouseholderQr().solve(b);
  out.centre = mean + s.head<3>();
  out.radius = std::sqrt(s(3) + s.head<3>().squaredNorm());
  double w = 0.0, sq = 0.0;
  for (int v : verts) {
    const double e = (Vec3(x.row(v)) - out.centre).norm() - out.radius;
    w += vertex_area[static_cast<std::size_t>(v)];
    sq += vertex_area[static_cast<std::size_t>(v)] * e * e;
  }
  out.residual = std::sqrt(sq / w) / out.radius;
  Vec3 axis = Vec3::Zero();
  std::vector<Vec3> dirs;
  for (int f : region) {
    const Vec3 d = ((corner(f, 0) + corner(f, 1) + corner(f, 2)) / 3.0 - out.centre).normalized();
    dirs.push_back(d);
    axis += face_area(f) * d;
  }
  axis.normalize();
  constexpr double PI = 3.14159265358979323846;
  for (const Vec3& d : dirs)
    out.angle_deg =
        std::max(out.angle_deg, std::acos(std::clamp(d.dot(axis), -1.0, 1.0)) * 180.0 / PI);
  return out;
}

}  // namespace shellcontract::test
