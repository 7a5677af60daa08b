// A heat-smoothing problem for the tests of src/geometry/heat_smoothing.hpp: a bumpy icosphere,
// its cotangent Laplacian, a third of the incident areas as masses and a rough field to smooth,
// built here and not by the finder.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "support/mesh_fixtures.hpp"

namespace shellcontract::test {

struct HeatProblem {
  Eigen::SparseMatrix<double> L;  ///< cotangent Laplacian, positive semidefinite
  Eigen::VectorXd mass, rhs;      ///< rhs = M h
  std::vector<double> times;      ///< left to the test
  double area = 0.0;              ///< the surface's total area
};

/// icosphere(levels) scaled to radius 1 + amplitude sin(f0 x) sin(f1 y) sin(f2 z), and the field
/// h = z + sin(field x).
inline HeatProblem bumpy_heat_problem(int levels, double amplitude, const std::array<double, 3>& f,
                                      double field) {
  TriMesh m = icosphere(levels);
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) {
    const Eigen::Vector3d p = m.x.row(i);
    m.x.row(i) *= 1.0 + amplitude * std::sin(f[0] * p.x()) * std::sin(f[1] * p.y()) * std::sin(f[2] * p.z());
  }
  const Eigen::Index n = m.x.rows();
  HeatProblem h;
  h.mass = Eigen::VectorXd::Zero(n);
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index face = 0; face < m.faces.rows(); ++face) {
    const int c[3] = {m.faces(face, 0), m.faces(face, 1), m.faces(face, 2)};
    const Eigen::Vector3d p0 = m.x.row(c[0]), p1 = m.x.row(c[1]), p2 = m.x.row(c[2]);
    const double a = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    h.area += a;
    for (int k = 0; k < 3; ++k) {
      h.mass(c[k]) += a / 3.0;
      const int i = c[k], j = c[(k + 1) % 3], o = c[(k + 2) % 3];
      const Eigen::Vector3d u = m.x.row(i) - m.x.row(o), v = m.x.row(j) - m.x.row(o);
      const double w = 0.5 * u.dot(v) / u.cross(v).norm();
      t.emplace_back(i, j, -w);
      t.emplace_back(j, i, -w);
      t.emplace_back(i, i, w);
      t.emplace_back(j, j, w);
    }
  }
  h.L.resize(n, n);
  h.L.setFromTriplets(t.begin(), t.end());
  h.rhs.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) h.rhs(i) = h.mass(i) * (m.x(i, 2) + std::sin(field * m.x(i, 0)));
  return h;
}

}  // namespace shellcontract::test
