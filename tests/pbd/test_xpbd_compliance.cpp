// XPBD at finite stiffness (math-spec 9.2) against a step computed by hand, through the default
// run's own option resolution: the material's Young's modulus, Poisson ratio and thickness become
// mu and lambda, the time step becomes alpha~ = alpha / dt^2, and one Gauss-Seidel sweep over one
// membrane moves its vertices by an amount that is proportional to the stiffness.
//
// The rigid limit (alpha~ = 0, tests/pbd/test_constraint_kernels.cpp) does not see the
// stiffness at all: there the step is -e / (2 s) whatever E is. At the default's alpha~ = 10^4 the
// step is (mu + lambda) / alpha~ times the strain, so a stiffness or time step off by a factor
// moves it by that factor.
//
// Fails with: DEFAULT_SHELL_YOUNG doubled or DEFAULT_SHELL_THICKNESS halved (config.hpp), which
// reach the step only through membrane_lame_from_young: the step moves by about 2x (checked by
// doubling mu and lambda there, and by halving its thickness); dt doubled moves it 4x.
#include <gtest/gtest.h>

#include <cmath>

#include "pbd/solver.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract {
namespace {

// The README's default shell ("--young 1000 --thickness 0.002", Poisson 0.3) and the time step
// of math-spec 14, written here as numbers so that the test does not read them from the code.
constexpr double YOUNG = 1000.0, POISSON = 0.3, THICKNESS = 0.002, DT = 0.01;

/// One membrane on the rest triangle X3 = 0, X1 = e_x, X2 = e_y (rest area 1/2; the rest frame
/// puts X1 - X3 on the first axis, so Dm = I), every inverse mass 1.
ConstraintSet one_membrane() {
  MembraneConstraint c;
  c.v = {0, 1, 2};
  c.Dm_inv = Mat2::Identity();
  c.rest_area = 0.5;
  c.max_step = 1e9;  // XPBD has no step clamp; large anyway so that nothing hides behind one
  ConstraintSet set;
  set.membranes.push_back(c);
  return set;
}

TEST(XpbdCompliance, OneSweepOfTheDefaultShellMovesAsComputedByHand) {
  RunOptions o;  // the default run: XPBD, the default shell material
  resolve_run_options(o);
  ASSERT_EQ(o.sim.solver.kind, SolverKind::Xpbd);
  ASSERT_EQ(o.sim.material, MaterialKind::Stvk);
  SolverSettings settings = o.sim.solver;
  settings.iterations = 1;
  settings.order = ConstraintOrder::Sequential;
  auto solver = make_constraint_solver(o.sim.material, o.sim.material_params, one_membrane(), settings);

  // The triangle stretched uniformly by s: x_i = s X_i.
  const double s = 1.1;
  Positions x(3, 3);
  x << s, 0, 0, 0, s, 0, 0, 0, 0;
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(3);
  const Positions before = x;
  solver->solve(x, w);

  // By hand. F = s [e_x e_y], Green strain E = e I with e = (s^2 - 1) / 2. StVK with the
  // plane-stress Lame parameters of math-spec 6, mu = E_Y h / (2 (1 + nu)) and
  // lambda = E_Y h nu / (1 - nu^2), so mu + lambda = E_Y h / (2 (1 - nu)):
  //   psi = mu tr(E^2) + lambda / 2 tr(E)^2 = 2 e^2 (mu + lambda),  energy U = A psi = e^2 (mu + lambda);
  //   S = 2 mu E + lambda tr(E) I = 2 e (mu + lambda) I,  first Piola P = F S,
  //   dU/dx_1 = A P e_1 = s e (mu + lambda) e_x,  dU/dx_2 = s e (mu + lambda) e_y,  dU/dx_3 = -(sum).
  // XPBD on C = sqrt(2 U) with alpha = 1 (the stiffness is in U), alpha~ = 1 / dt^2, lambda_0 = 0:
  //   grad C_i = (dU/dx_i) / C,  sum_i w_i |grad C_i|^2 = 4 s^2 e^2 (mu + lambda)^2 / (2 U) = 2 s^2 (mu + lambda),
  //   Delta lambda = -C / (2 s^2 (mu + lambda) + alpha~),  dx_i = w_i grad C_i Delta lambda, so
  //   dx_1 = -s e (mu + lambda) / (2 s^2 (mu + lambda) + alpha~) e_x  (and dx_2 the same along e_y).
  const double mu_plus_lambda = YOUNG * THICKNESS / (2.0 * (1.0 - POISSON));
  const double alpha_tilde = 1.0 / (DT * DT);
  const double e = 0.5 * (s * s - 1.0);
  const double step = -s * e * mu_plus_lambda / (2.0 * s * s * mu_plus_lambda + alpha_tilde);
  // The compliance dominates: the step is nearly (mu + lambda) dt^2 times the strain, far from the
  // rigid limit -e / (2 s), so a factor in the stiffness shows as the same factor here.
  ASSERT_LT(std::abs(step), 1e-2 * e / (2.0 * s));

  const Positions moved = x - before;
  const double tol = 1e-9 * std::abs(step);  // the sums above, a few roundings
  EXPECT_NEAR(moved(0, 0), step, tol);
  EXPECT_NEAR(moved(1, 1), step, tol);
  EXPECT_NEAR(moved(2, 0), -step, tol);
  EXPECT_NEAR(moved(2, 1), -step, tol);
  const int still[5][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 2}};
  for (const auto& ik : still)
    EXPECT_NEAR(moved(ik[0], ik[1]), 0.0, tol) << "vertex " << ik[0] << " axis " << ik[1];
}

/// dU/dx of the StVK membrane of one_membrane() at x, written from the energy (not the code's
/// kernels): F = [x_1 - x_3, x_2 - x_3] (Dm = I), Green strain G = (F^T F - I) / 2,
/// S = 2 mu G + lambda tr(G) I, P = F S, dU/dx_1 = A P e_1, dU/dx_2 = A P e_2, dU/dx_3 = -(sum).
Positions stvk_gradient(const Positions& x, double mu, double lambda) {
  Eigen::Matrix<double, 3, 2> F;
  F.col(0) = (x.row(0) - x.row(2)).transpose();
  F.col(1) = (x.row(1) - x.row(2)).transpose();
  const Mat2 G = 0.5 * (F.transpose() * F - Mat2::Identity());
  const Mat2 S = 2.0 * mu * G + lambda * G.trace() * Mat2::Identity();
  const Eigen::Matrix<double, 3, 2> P = 0.5 * F * S;  // times the rest area 1/2
  Positions g(3, 3);
  g.row(0) = P.col(0).transpose();
  g.row(1) = P.col(1).transpose();
  g.row(2) = -(g.row(0) + g.row(1));
  return g;
}

TEST(XpbdCompliance, ManySweepsReachTheImplicitElasticStep) {
  // Converged XPBD with alpha = 1 on C = sqrt(2 U) satisfies x - x~ = W grad C lambda and
  // C + alpha~ lambda = 0, i.e. x = x~ - dt^2 W dU/dx(x) (math-spec 9.2; Macklin et al. 2016):
  // the implicit Euler step of the elastic force alone. The test solves that equation itself by
  // fixed-point iteration (a contraction: dt^2 (mu + lambda) is about 1e-4) with its own StVK
  // gradient and the literal material, and the solver's 30 sweeps must land on it. The sweeps
  // use the gradient at each iterate, the equation the gradient at the end: they agree to second
  // order in the step, far inside the tolerance (1 % of the step).
  RunOptions o;
  resolve_run_options(o);
  SolverSettings settings = o.sim.solver;
  settings.iterations = 30;
  settings.order = ConstraintOrder::Sequential;
  auto solver = make_constraint_solver(o.sim.material, o.sim.material_params, one_membrane(), settings);
  Positions predicted(3, 3);  // stretched and sheared: every entry of the strain is non-zero
  predicted << 1.15, 0.05, 0.02, -0.03, 1.08, -0.01, 0.0, 0.0, 0.0;
  Positions x = predicted;
  solver->solve(x, Eigen::VectorXd::Ones(3));

  const double mu = YOUNG * THICKNESS / (2.0 * (1.0 + POISSON));
  const double lambda = YOUNG * THICKNESS * POISSON / (1.0 - POISSON * POISSON);
  Positions want = predicted;
  for (int k = 0; k < 100; ++k) want = predicted - DT * DT * stvk_gradient(want, mu, lambda);
  ASSERT_LE((want - (predicted - DT * DT * stvk_gradient(want, mu, lambda))).cwiseAbs().maxCoeff(), 1e-15);

  const double step = (want - predicted).cwiseAbs().maxCoeff();
  ASSERT_GT(step, 1e-6);
  EXPECT_LE((x - want).cwiseAbs().maxCoeff(), 1e-2 * step)
      << "solver moved " << (x - predicted).cwiseAbs().maxCoeff() << ", implicit step " << step;
}

}  // namespace
}  // namespace shellcontract
