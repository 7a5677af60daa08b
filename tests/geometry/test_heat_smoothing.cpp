// The region finder's heat solves (src/geometry/heat_smoothing.hpp): the two-level conjugate
// gradient used on large meshes solves the same systems as the direct solver, keeps the heat
// (the mass-weighted sum), and needs about as many iterations on a finer mesh as on a coarser
// one. The Laplacian, the masses and the residuals are built here, not by the finder.
// Checked to fail without the coarse correction (the iteration count then grows with the
// resolution) and with a one-sided (non-symmetric) cycle (CG no longer converges; the counts
// fall to 0, the direct fallback).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <Eigen/SparseCore>

#include "geometry/heat_smoothing.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

struct HeatProblem {
  Eigen::SparseMatrix<double> L;
  Eigen::VectorXd mass, rhs;
  std::vector<double> times;
};

/// A bumpy sphere (radius 1 + 0.15 sin 3x sin 4y sin 5z), its cotangent Laplacian, a third of
/// the incident areas as masses, h = z + sin 6x, and the finder's times at a size of 1.
HeatProblem bumpy_problem(int levels) {
  test::TriMesh m = test::icosphere(levels);
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) {
    const Eigen::Vector3d p = m.x.row(i);
    m.x.row(i) *= 1.0 + 0.15 * std::sin(3 * p.x()) * std::sin(4 * p.y()) * std::sin(5 * p.z());
  }
  const Eigen::Index n = m.x.rows();
  HeatProblem h;
  h.mass = Eigen::VectorXd::Zero(n);
  std::vector<Eigen::Triplet<double>> t;
  double area = 0.0;
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
    const int c[3] = {m.faces(f, 0), m.faces(f, 1), m.faces(f, 2)};
    const Eigen::Vector3d p0 = m.x.row(c[0]), p1 = m.x.row(c[1]), p2 = m.x.row(c[2]);
    const double a = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    area += a;
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
  for (Eigen::Index i = 0; i < n; ++i) h.rhs(i) = h.mass(i) * (m.x(i, 2) + std::sin(6 * m.x(i, 0)));
  for (double s : {0.01, 0.02, 0.05, 0.1}) h.times.push_back(s * s * area);
  return h;
}

TEST(HeatSmoothing, IterativeSolvesTheSystemsTheDirectSolverSolves) {
  const HeatProblem h = bumpy_problem(4);
  std::vector<int> iterations;
  const std::vector<Eigen::VectorXd> it = detail::heat_solves(h.L, h.mass, h.rhs, h.times, true, &iterations);
  const std::vector<Eigen::VectorXd> direct = detail::heat_solves(h.L, h.mass, h.rhs, h.times, false);
  ASSERT_EQ(it.size(), h.times.size());
  for (std::size_t k = 0; k < h.times.size(); ++k) {
    EXPECT_GT(iterations[k], 0) << "time " << k << " fell back to the direct solver";
    const Eigen::VectorXd residual = h.rhs - (h.mass.asDiagonal() * it[k] + h.times[k] * (h.L * it[k]));
    EXPECT_LE(residual.norm(), 1e-10 * h.rhs.norm()) << "time " << k;
    EXPECT_LE((it[k] - direct[k]).cwiseAbs().maxCoeff(), 1e-8 * direct[k].cwiseAbs().maxCoeff()) << "time " << k;
    // L's rows sum to zero, so the heat sum M u = sum M h is kept.
    EXPECT_NEAR(h.mass.dot(it[k]), h.rhs.sum(), 1e-10 * h.rhs.cwiseAbs().sum()) << "time " << k;
  }
}

TEST(HeatSmoothing, IterationCountDoesNotGrowWithTheResolution) {
  // Four times the vertices: plain conjugate gradients would need about twice the iterations
  // (their count grows like the inverse edge length); the aggregates take the smooth error.
  const HeatProblem coarse = bumpy_problem(4), fine = bumpy_problem(5);
  std::vector<int> nc, nf;
  detail::heat_solves(coarse.L, coarse.mass, coarse.rhs, coarse.times, true, &nc);
  detail::heat_solves(fine.L, fine.mass, fine.rhs, fine.times, true, &nf);
  for (std::size_t k = 0; k < nc.size(); ++k) {
    ASSERT_GT(nc[k], 0);
    ASSERT_GT(nf[k], 0);
    EXPECT_LE(nf[k], nc[k] * 1.4 + 2) << "time " << k << ": " << nc[k] << " then " << nf[k] << " iterations";
  }
}

}  // namespace
}  // namespace shellcontract
