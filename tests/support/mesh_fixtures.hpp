// Small closed meshes generated in code (Eigen arrays), for tests that need no file.
#pragma once

#include <map>
#include <utility>
#include <vector>

#include "shellcontract/types.hpp"

namespace shellcontract::test {

struct TriMesh {
  Positions x;
  Faces faces;
};

/// Icosahedron subdivided `levels` times and projected to the sphere of radius r (outward,
/// counter-clockwise faces).
inline TriMesh icosphere(int levels, double r = 1.0) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                      {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f{{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (Vec3& p : v) p.normalize();
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      mid[key] = static_cast<int>(v.size()) - 1;
      return static_cast<int>(v.size()) - 1;
    };
    std::vector<std::array<int, 3>> g;
    for (const auto& [a, b, c] : f) {
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      g.push_back({a, ab, ca});
      g.push_back({b, bc, ab});
      g.push_back({c, ca, bc});
      g.push_back({ab, bc, ca});
    }
    f.swap(g);
  }
  TriMesh m;
  m.x.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) m.x.row(static_cast<Eigen::Index>(i)) = r * v[i].transpose();
  m.faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t j = 0; j < f.size(); ++j)
    m.faces.row(static_cast<Eigen::Index>(j)) << f[j][0], f[j][1], f[j][2];
  return m;
}

/// icosphere(levels) with face 0 split in three at its centroid, and then `splits` - 1 times
/// more the last of the three new faces (around the newest vertex): a fan of ever smaller faces
/// whose new vertices have small one-rings and masses, the light vertices that the explicit
/// pressure's mass floor raises (sim/mass_scaling.hpp).
inline TriMesh icosphere_with_small_faces(int levels, int splits) {
  TriMesh m = icosphere(levels);
  Eigen::Index face = 0;
  for (int s = 0; s < splits; ++s) {
    const Eigen::Index n = m.x.rows(), nf = m.faces.rows();
    const int a = m.faces(face, 0), b = m.faces(face, 1), c = m.faces(face, 2);
    m.x.conservativeResize(n + 1, 3);
    m.x.row(n) = (m.x.row(a) + m.x.row(b) + m.x.row(c)) / 3.0;
    m.faces.row(face) << a, b, static_cast<int>(n);
    m.faces.conservativeResize(nf + 2, 3);
    m.faces.row(nf) << b, c, static_cast<int>(n);
    m.faces.row(nf + 1) << c, a, static_cast<int>(n);
    face = nf + 1;
  }
  return m;
}

/// Signed enclosed volume V = 1/6 sum x1 . (x2 x x3) (math-spec 1.1), for closed-form checks.
inline double signed_volume(const Positions& x, const Faces& faces) {
  double V = 0.0;
  for (Eigen::Index j = 0; j < faces.rows(); ++j)
    V += Vec3(x.row(faces(j, 0))).dot(Vec3(x.row(faces(j, 1))).cross(Vec3(x.row(faces(j, 2)))));
  return V / 6.0;
}

}  // namespace shellcontract::test
