// A closed mesh whose parts all pass through each other: `count` thin tetrahedral needles
// through the origin, each along its own direction, so that every needle crosses every other
// near the origin and the self-intersecting face pairs number about 8 per pair of needles (the
// square of the faces: 4 faces a needle). Review complexity F7's gen_needles.py drew one needle
// through glTF nodes; this writes each out, as an OFF file or arrays.
#pragma once

#include <cmath>
#include <fstream>
#include <string>

#include "support/mesh_fixtures.hpp"

namespace shellcontract::test {

inline TriMesh crossing_needles(int count, double width = 0.05) {
  TriMesh m;
  m.x.resize(4 * count, 3);
  m.faces.resize(4 * count, 3);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int n = 0; n < count; ++n) {
    // Directions spread over a half sphere (a needle along d is one along -d).
    const double z = 1.0 - (n + 0.5) / count, r = std::sqrt(1.0 - z * z), a = golden * n;
    const Vec3 d(r * std::cos(a), r * std::sin(a), z);
    const Vec3 u = d.cross(std::abs(d.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).normalized();
    const Vec3 v = d.cross(u);
    const Vec3 tip = -d;
    const Vec3 b0 = d + width * u, b1 = d + width * (-0.5 * u + 0.87 * v),
               b2 = d + width * (-0.5 * u - 0.87 * v);
    for (const auto& [i, p] : {std::pair{0, tip}, {1, b0}, {2, b1}, {3, b2}})
      m.x.row(4 * n + i) = p.transpose();
    // Outward (positive volume): the base b0 b1 b2 is counter-clockwise seen from the tip.
    const int o = 4 * n;
    m.faces.row(4 * n) << o, o + 2, o + 1;
    m.faces.row(4 * n + 1) << o, o + 3, o + 2;
    m.faces.row(4 * n + 2) << o, o + 1, o + 3;
    m.faces.row(4 * n + 3) << o + 1, o + 2, o + 3;
  }
  return m;
}

inline void write_off(const TriMesh& m, const std::string& path) {
  std::ofstream out(path);
  out.precision(17);
  out << "OFF\n" << m.x.rows() << ' ' << m.faces.rows() << " 0\n";
  for (Eigen::Index i = 0; i < m.x.rows(); ++i)
    out << m.x(i, 0) << ' ' << m.x(i, 1) << ' ' << m.x(i, 2) << '\n';
  for (Eigen::Index j = 0; j < m.faces.rows(); ++j)
    out << "3 " << m.faces(j, 0) << ' ' << m.faces(j, 1) << ' ' << m.faces(j, 2) << '\n';
}

}  // namespace shellcontract::test
