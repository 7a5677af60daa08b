// Helpers shared by the region finders' tests (test_cap_regions.cpp, test_tip_finder.cpp): mesh
// conversions, midpoint subdivision, vertex permutation, region comparison, and closed surfaces
// of revolution (a capsule, a dumbbell) whose parts are known in closed form.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "geometry/region_metrics.hpp"
#include "mesh/eigen_point_map.hpp"
#include "shellcontract/regions.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"
#include "test_paths.hpp"

namespace shellcontract::test {

inline std::string paper_mesh(const std::string& name) {
  return std::string(PAPER_MESH_DIR) + "/" + name + ".off";
}

inline TriMesh to_tri_mesh(const Mesh& mesh) {
  TriMesh m;
  m.x = positions_from_mesh(mesh);
  m.faces.resize(static_cast<Eigen::Index>(mesh.number_of_faces()), 3);
  for (FaceIndex f : mesh.faces()) {
    int k = 0;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      m.faces(static_cast<Eigen::Index>(f.idx()), k++) = static_cast<int>(v.idx());
  }
  return m;
}

/// The regions as a set of face sets (ids by area can swap between two regions of nearly the
/// same area; the sets are what must not change).
inline std::set<std::vector<int>> face_sets(const std::vector<int>& ids) {
  const std::vector<std::vector<int>> lists = regions_from_face_ids(ids);
  return {lists.begin(), lists.end()};
}

/// Midpoint subdivision: face j becomes faces 4j .. 4j+3 (corners, then the middle), each with a
/// quarter of its area, so a face set of the coarse mesh maps to one of the fine mesh exactly.
inline TriMesh split_in_four(const TriMesh& m) {
  std::vector<Vec3> v;
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) v.emplace_back(m.x.row(i));
  std::map<std::pair<int, int>, int> mid;
  const auto midpoint = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    const auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    v.push_back(0.5 * (v[static_cast<std::size_t>(a)] + v[static_cast<std::size_t>(b)]));
    return mid[key] = static_cast<int>(v.size()) - 1;
  };
  TriMesh out;
  out.faces.resize(4 * m.faces.rows(), 3);
  for (Eigen::Index j = 0; j < m.faces.rows(); ++j) {
    const int a = m.faces(j, 0), b = m.faces(j, 1), c = m.faces(j, 2);
    const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    out.faces.row(4 * j) << a, ab, ca;
    out.faces.row(4 * j + 1) << b, bc, ab;
    out.faces.row(4 * j + 2) << c, ca, bc;
    out.faces.row(4 * j + 3) << ab, bc, ca;
  }
  out.x.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    out.x.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
  return out;
}

/// The same surface with its vertices renumbered at random (faces keep their order).
inline TriMesh shuffle_vertices(const TriMesh& m, unsigned seed) {
  std::vector<int> perm(static_cast<std::size_t>(m.x.rows()));  // new index of each old vertex
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
  TriMesh shuffled = m;
  for (Eigen::Index i = 0; i < m.x.rows(); ++i)
    shuffled.x.row(perm[static_cast<std::size_t>(i)]) = m.x.row(i);
  for (Eigen::Index j = 0; j < m.faces.rows(); ++j)
    for (int k = 0; k < 3; ++k)
      shuffled.faces(j, k) = perm[static_cast<std::size_t>(m.faces(j, k))];
  return shuffled;
}

/// A rotation about a generic axis, a scale that is not a power of two and a shift, so every
/// coordinate changes in its last bits.
inline TriMesh moved(const TriMesh& m) {
  const Mat3 R = Eigen::AngleAxisd(1.234, Vec3(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  TriMesh out = m;
  for (Eigen::Index i = 0; i < out.x.rows(); ++i)
    out.x.row(i) = (3.7 * R * Vec3(m.x.row(i)) + Vec3(5.0, -2.0, 1.0)).transpose();
  return out;
}

/// Each region of `coarse` against the best-overlapping region of `fine` (= split_in_four of
/// coarse: coarse face j is fine faces 4j .. 4j+3, a quarter of its area each, so IoU by face
/// count is IoU by area), and each region of `fine` against those of `coarse`: the smallest of
/// these best IoUs.
inline double worst_subdivision_iou(const std::vector<int>& coarse_ids,
                                    const std::vector<int>& fine_ids, std::string* where) {
  const std::vector<std::vector<int>> coarse = regions_from_face_ids(coarse_ids),
                                      fine = regions_from_face_ids(fine_ids);
  const std::size_t nf = fine_ids.size();
  const auto flags_of = [&](const std::vector<int>& faces, bool from_coarse) {
    std::vector<char> flag(nf, 0);
    for (int f : faces)
      for (int k = 0; k < (from_coarse ? 4 : 1); ++k)
        flag[static_cast<std::size_t>(from_coarse ? 4 * f + k : f)] = 1;
    return flag;
  };
  double worst = 1.0;
  for (int side = 0; side < 2; ++side) {
    const auto& these = side == 0 ? coarse : fine;
    const auto& others = side == 0 ? fine : coarse;
    for (std::size_t r = 0; r < these.size(); ++r) {
      const std::vector<char> a = flags_of(these[r], side == 0);
      double best = 0.0;
      for (const std::vector<int>& o : others)
        best = std::max(best, face_set_iou(a, flags_of(o, side == 1)));
      if (best < worst) {
        worst = best;
        *where = (side == 0 ? "region " : "region of the split mesh ") + std::to_string(r);
      }
    }
  }
  return worst;
}

/// Perimeter^2 / (4 pi area) of a face list, from an edge count over vertex pairs (not the
/// halfedge walk of region_shape).
inline double compactness_by_edge_count(const TriMesh& m, const std::vector<int>& faces) {
  std::map<std::pair<int, int>, int> uses;
  double area = 0.0;
  for (int f : faces) {
    const Vec3 p0(m.x.row(m.faces(f, 0))), p1(m.x.row(m.faces(f, 1))), p2(m.x.row(m.faces(f, 2)));
    area += 0.5 * (p1 - p0).cross(p2 - p0).norm();
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(m.faces(f, k), m.faces(f, (k + 1) % 3))];
  }
  double perimeter = 0.0;
  for (const auto& [e, n] : uses)
    if (n == 1) perimeter += (Vec3(m.x.row(e.first)) - Vec3(m.x.row(e.second))).norm();
  return perimeter * perimeter / (4.0 * 3.14159265358979323846 * area);
}

/// A closed surface of revolution about the z axis: `profile` is a polyline (rho, z) from the
/// top pole (rho = 0) to the bottom pole (rho = 0). It is resampled at `rings` + 1 points equally
/// spaced in arc length; each inner point becomes a ring of `around` vertices (every other ring
/// turned by half a step, so the triangles are nearly equilateral), the poles one vertex each.
/// Faces outward and counter-clockwise.
inline TriMesh revolution(const std::vector<std::pair<double, double>>& profile, int rings,
                          int around) {
  constexpr double PI = 3.14159265358979323846;
  std::vector<double> s{0.0};
  for (std::size_t i = 1; i < profile.size(); ++i)
    s.push_back(s.back() + std::hypot(profile[i].first - profile[i - 1].first,
                                      profile[i].second - profile[i - 1].second));
  const auto at = [&](double t) {  // the profile point at arc length t
    const auto it = std::upper_bound(s.begin(), s.end(), t);
    const std::size_t i = std::min<std::size_t>(
        static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - s.begin(), 1)), s.size() - 1);
    const double w =
        s[i] > s[i - 1] ? std::clamp((t - s[i - 1]) / (s[i] - s[i - 1]), 0.0, 1.0) : 0.0;
    return std::make_pair((1 - w) * profile[i - 1].first + w * profile[i].first,
                          (1 - w) * profile[i - 1].second + w * profile[i].second);
  };
  std::vector<Vec3> v{Vec3(0, 0, profile.front().second)};
  for (int k = 1; k < rings; ++k) {
    const auto [rho, z] = at(s.back() * k / rings);
    for (int j = 0; j < around; ++j) {
      const double phi = 2.0 * PI * (j + 0.5 * (k % 2)) / around;
      v.emplace_back(rho * std::cos(phi), rho * std::sin(phi), z);
    }
  }
  v.emplace_back(0, 0, profile.back().second);
  const int bottom = static_cast<int>(v.size()) - 1;
  const auto ring = [&](int k, int j) {
    return 1 + (k - 1) * around + ((j % around) + around) % around;
  };
  std::vector<std::array<int, 3>> f;
  for (int j = 0; j < around; ++j) f.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int k = 1; k + 1 < rings; ++k)
    for (int j = 0; j < around; ++j) {
      // Ring k + 1 is turned by half a step against ring k (either way, by parity).
      const int a = ring(k, j), b = ring(k, j + 1);
      if (k % 2 == 1) {
        const int c = ring(k + 1, j), d = ring(k + 1, j + 1);  // c lies between a and b
        f.push_back({a, c, b});
        f.push_back({b, c, d});
      } else {
        const int c = ring(k + 1, j - 1), d = ring(k + 1, j);  // a lies between c and d
        f.push_back({a, c, d});
        f.push_back({a, d, b});
      }
    }
  for (int j = 0; j < around; ++j)
    f.push_back({bottom, ring(rings - 1, j + 1), ring(rings - 1, j)});
  TriMesh m;
  m.x.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    m.x.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
  m.faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t j = 0; j < f.size(); ++j)
    m.faces.row(static_cast<Eigen::Index>(j)) << f[j][0], f[j][1], f[j][2];
  if (signed_volume(m.x, m.faces) < 0.0)  // outward, whatever the winding above turned out
    for (Eigen::Index j = 0; j < m.faces.rows(); ++j) std::swap(m.faces(j, 1), m.faces(j, 2));
  return m;
}

/// The profile of a capsule: a cylinder of radius r and length L along z, centred at 0, closed
/// by hemispheres (points every `step` radians on the ends).
inline std::vector<std::pair<double, double>> capsule_profile(double r, double L,
                                                              double step = 0.01) {
  constexpr double PI = 3.14159265358979323846;
  std::vector<std::pair<double, double>> p;
  for (double a = 0.0; a < 0.5 * PI; a += step)
    p.emplace_back(r * std::sin(a), 0.5 * L + r * std::cos(a));
  p.emplace_back(r, 0.5 * L);
  for (double a = 0.5 * PI; a >= 0.0; a -= step)
    p.emplace_back(r * std::sin(a), -0.5 * L - r * std::cos(a));
  p.emplace_back(0.0, -0.5 * L - r);
  p.front() = {0.0, 0.5 * L + r};
  return p;
}

/// The profile of a dumbbell: two unit spheres centred at z = +-c joined by a cylinder of radius
/// n < 1 (a concave crease where each sphere meets it).
inline std::vector<std::pair<double, double>> dumbbell_profile(double c, double n,
                                                               double step = 0.01) {
  constexpr double PI = 3.14159265358979323846;
  const double rim = PI - std::asin(n);  // polar angle where a sphere meets the neck
  std::vector<std::pair<double, double>> p;
  for (double a = 0.0; a < rim; a += step) p.emplace_back(std::sin(a), c + std::cos(a));
  p.emplace_back(n, c + std::cos(rim));
  p.emplace_back(n, -c - std::cos(rim));
  for (double a = rim; a > 0.0; a -= step) p.emplace_back(std::sin(a), -c - std::cos(a));
  p.emplace_back(0.0, -c - 1.0);
  return p;
}

}  // namespace shellcontract::test
