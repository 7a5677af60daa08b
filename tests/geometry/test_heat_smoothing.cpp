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
#include "shellcontract/error.hpp"
#include "support/heat_problem.hpp"

namespace shellcontract {
namespace {

using test::HeatProblem;

/// A bumpy sphere (radius 1 + 0.15 sin 3x sin 4y sin 5z; support/heat_problem.hpp),
/// h = z + sin 6x, and the finder's times at a size of 1.
HeatProblem bumpy_problem(int levels) {
  HeatProblem h = test::bumpy_heat_problem(levels, 0.15, {3.0, 4.0, 5.0}, 6.0);
  for (double s : {0.01, 0.02, 0.05, 0.1}) h.times.push_back(s * s * h.area);
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

// A singular system (a vertex of zero mass and no Laplacian row: what degenerate input geometry
// would give) is the input's fault, not the caller's: InputError (exit code 2), not UsageError.
TEST(HeatSolves, ASingularSystemIsAnInputError) {
  Eigen::SparseMatrix<double> L(2, 2);
  L.insert(0, 0) = 0.0;
  L.insert(1, 1) = 0.0;
  const Eigen::VectorXd mass = Eigen::Vector2d(1.0, 0.0);
  const Eigen::VectorXd rhs = Eigen::Vector2d(1.0, 1.0);
  EXPECT_THROW(detail::heat_solves(L, mass, rhs, {0.1}, false), InputError);
}

}  // namespace
}  // namespace shellcontract
