// The size of one projection step, checked against the defining equations of PBD and XPBD rather
// than against the kernels' own formulas (math-spec 8.2, 8.3, 9.1, 9.2):
//  * PBD on E = C^2-like energies moves along the mass-weighted gradient and, to first order,
//    halves a quadratic constraint with k = 1 (the isometric test in test_constraint_kernels.cpp
//    shows it for the linear h; here the dihedral angle, which is not linear);
//  * XPBD solves C(x + dx) + alpha~ (lambda + dlambda) = 0 to first order in dx (Macklin et al.
//    2016, eq. (18)), exactly when C is linear (the isometric h). The rigid-limit tests
//    (alpha~ = 0) cannot see a compliance term that is dropped or mis-scaled; these use a
//    compliance of the size of |grad C|^2_w, where both terms of the denominator count.
// C is evaluated here from positions alone (dihedral_angle, the element energy), never from the
// kernel's intermediates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "bending/dihedral_bending.hpp"
#include "bending/isometric_bending.hpp"
#include "material/stvk.hpp"
#include "pbd/constraint_kernels.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

struct Stencil {
  std::vector<double> x;  // 3 per vertex
  std::vector<double> w;
};

Vec3 at(const Stencil& s, int i) { return Vec3(s.x[3 * i], s.x[3 * i + 1], s.x[3 * i + 2]); }

Stencil stencil_of(const std::vector<Vec3>& p, const std::vector<double>& w) {
  Stencil s;
  for (const Vec3& q : p) s.x.insert(s.x.end(), {q.x(), q.y(), q.z()});
  s.w = w;
  return s;
}

ProjectionContext context(Stencil& s, double alpha_tilde) {
  ProjectionContext ctx;
  ctx.x = s.x.data();
  ctx.w = s.w.data();
  ctx.alpha_tilde = alpha_tilde;
  return ctx;
}

/// A hinge (edge 0-1, wings 2 and 3) at rest with its wing 3 turned by `turn` about the edge
/// (the x axis), so that theta - theta_bar = +-turn.
struct TurnedHinge {
  DihedralHingeConstraint c;
  Stencil s;
};

TurnedHinge turned_hinge(double turn) {
  const std::vector<Vec3> rest{Vec3(-0.4, 0, 0), Vec3(0.6, 0, 0), Vec3(0.1, 0.7, 0),
                               Vec3(-0.2, -0.4, -0.3)};
  TurnedHinge h{{{0, 1, 2, 3}, dihedral_bending_rest(rest[0], rest[1], rest[2], rest[3]), 1e9}, {}};
  const Eigen::AngleAxisd r(turn, Vec3::UnitX());
  std::vector<Vec3> p = rest;
  p[3] = r * rest[3];
  h.s = stencil_of(p, {1.0, 0.7, 1.3, 0.9});
  return h;
}

double angle_error(const TurnedHinge& h) {
  double theta = 0.0;
  EXPECT_TRUE(dihedral_angle(at(h.s, 0), at(h.s, 1), at(h.s, 2), at(h.s, 3), theta));
  return wrapped_angle_difference(theta, h.c.rest.rest_angle);
}

TEST(DihedralHingeStep, PbdWithUnitStiffnessHalvesASmallAngleError) {
  // PBD with C = E = kappa d^2: dx = -(E / |grad E|^2_w) w grad E = -(d / (2 |grad theta|^2_w))
  // w grad theta, so d changes by -d / 2 to first order (math-spec 8.3, 9.1).
  for (double turn : {2e-3, -2e-3}) {
    TurnedHinge h = turned_hinge(turn);
    const double d0 = angle_error(h);
    ASSERT_NEAR(std::abs(d0), 2e-3, 1e-9);
    ProjectionContext ctx = context(h.s, 0.0);
    ASSERT_TRUE(project_dihedral_hinge(h.c, 1.0, ctx, nullptr));
    EXPECT_NEAR(angle_error(h) / d0, 0.5, 0.01) << "turn " << turn;
  }
}

TEST(DihedralHingeStep, XpbdSolvesTheComplianceEquationToFirstOrder) {
  // C = sqrt(2 k_B kappa) d, G = |grad C|^2_w = 2 k_B kappa |grad theta|^2_w. From lambda = 0 the
  // step is dlambda = -C0 / (G + alpha~) along w grad C, so C1 = C0 alpha~ / (G + alpha~) and
  // C(x1) + alpha~ lambda1 = 0, both up to O(dx^2); alpha~ = s G makes C1 / C0 = s / (1 + s).
  const double k_b = 0.8;
  for (double at_scale : {0.5, 2.0}) {
    TurnedHinge h = turned_hinge(1e-3);
    std::array<Vec3, 4> grad;
    double theta = 0.0;
    ASSERT_TRUE(
        dihedral_angle_gradient(at(h.s, 0), at(h.s, 1), at(h.s, 2), at(h.s, 3), theta, grad));
    double wg = 0.0;
    for (int i = 0; i < 4; ++i) wg += h.s.w[i] * grad[i].squaredNorm();
    const double root = std::sqrt(2.0 * k_b * h.c.rest.kappa);
    const double alpha_tilde = at_scale * root * root * wg;
    const double c0 = root * angle_error(h);
    double lambda = 0.0;
    ProjectionContext ctx = context(h.s, alpha_tilde);
    ASSERT_TRUE(project_dihedral_hinge(h.c, k_b, ctx, &lambda));
    const double c1 = root * angle_error(h);
    EXPECT_NEAR(c1 + alpha_tilde * lambda, 0.0, 1e-2 * std::abs(c0)) << "alpha~ scale " << at_scale;
    // The remaining constraint is the compliant fraction alpha~ / (|grad C|^2 + alpha~) of C0.
    EXPECT_NEAR(c1 / c0, at_scale / (1.0 + at_scale), 1e-2) << "alpha~ scale " << at_scale;
  }
}

IsometricHingeConstraint hinge_on(const std::vector<Vec3>& rest) {
  const IsometricBendingRest r = isometric_bending_rest(rest[0], rest[1], rest[2], rest[3]);
  return {{0, 1, 2, 3}, r.K, 3.0 / r.area_sum, 1e9};
}

TEST(IsometricHingeStep, XpbdWithComplianceSolvesTheLinearConstraintExactly) {
  // C = sqrt(beta) h(x) is linear in x, so the XPBD step satisfies C(x1) + alpha~ lambda1 = 0
  // exactly (up to rounding), for any compliance and any starting lambda.
  std::mt19937 rng(21);
  const std::vector<Vec3> flat{Vec3(-0.4, 0, 0), Vec3(0.6, 0, 0), Vec3(0.1, 0.7, 0),
                               Vec3(-0.2, -0.5, 0)};
  const IsometricHingeConstraint c = hinge_on(flat);
  const double k_b = 0.3, beta = k_b * c.three_over_area;
  for (double alpha_tilde : {0.05, 1.0, 20.0}) {
    std::vector<Vec3> p = flat;
    for (Vec3& q : p) q += 0.2 * test::random_vec3(rng);
    Stencil s = stencil_of(p, {1.0, 0.5, 2.0, 1.5});
    double lambda[3] = {0.01, -0.02, 0.03};
    ProjectionContext ctx = context(s, alpha_tilde);
    ASSERT_TRUE(project_isometric_hinge(c, k_b, ctx, lambda));
    const Vec3 h = c.K(0) * at(s, 0) + c.K(1) * at(s, 1) + c.K(2) * at(s, 2) + c.K(3) * at(s, 3);
    const Vec3 residual = std::sqrt(beta) * h + alpha_tilde * Vec3(lambda[0], lambda[1], lambda[2]);
    EXPECT_LE(residual.norm(), 1e-12) << "alpha~ " << alpha_tilde;
    EXPECT_GT(h.norm(), 1e-4) << "the compliance leaves part of h: alpha~ " << alpha_tilde;
  }
}

TEST(IsometricHingeStep, PbdStepIsClampedToMaxStepAlongTheSameDirection) {
  // math-spec 9.1(d): the step is scaled down, not cut per vertex, so that no vertex moves more
  // than max_step; the clamped step is the unclamped one times max_step / its longest move.
  std::mt19937 rng(22);
  const std::vector<Vec3> flat{Vec3(-0.4, 0, 0), Vec3(0.6, 0, 0), Vec3(0.1, 0.7, 0),
                               Vec3(-0.2, -0.5, 0)};
  IsometricHingeConstraint c = hinge_on(flat);
  std::vector<Vec3> p = flat;
  for (Vec3& q : p) q += 0.3 * test::random_vec3(rng);
  const Stencil start = stencil_of(p, {1.0, 0.5, 2.0, 1.5});
  Stencil free = start;
  ProjectionContext fctx = context(free, 0.0);
  ASSERT_TRUE(project_isometric_hinge(c, 1.0, fctx, nullptr));
  double longest = 0.0;
  for (int i = 0; i < 4; ++i) longest = std::max(longest, (at(free, i) - at(start, i)).norm());
  ASSERT_GT(longest, 1e-2);
  c.max_step = 0.25 * longest;
  Stencil clamped = start;
  ProjectionContext cctx = context(clamped, 0.0);
  ASSERT_TRUE(project_isometric_hinge(c, 1.0, cctx, nullptr));
  double longest_clamped = 0.0;
  for (int i = 0; i < 4; ++i) {
    const Vec3 dc = at(clamped, i) - at(start, i), df = at(free, i) - at(start, i);
    longest_clamped = std::max(longest_clamped, dc.norm());
    EXPECT_LE((dc - 0.25 * df).norm(), 1e-14) << "vertex " << i;
  }
  EXPECT_NEAR(longest_clamped, c.max_step, 1e-15);
}

TEST(MembraneStep, XpbdWithComplianceSolvesTheComplianceEquationToFirstOrder) {
  // C = sqrt(2E) of a StVK membrane stretched by a few percent, alpha~ a multiple of |grad C|^2_w
  // so that both terms of the step's denominator count. The first multiplier step is exact;
  // the residual is checked where the step is small enough for first order to hold.
  const std::vector<Vec3> rest{Vec3(0, 0, 0), Vec3(1, 0.1, 0), Vec3(0.2, 0.9, 0.1)};
  const TriangleRest r = triangle_rest(rest[0], rest[1], rest[2]);
  MembraneConstraint c;
  c.v = {0, 1, 2};
  c.Dm_inv = r.Dm_inv;
  c.rest_area = r.area;
  c.max_step = 1e9;
  const Stvk m(MaterialParams{1.0, 0.5});
  auto C_of = [&](const Stencil& s, std::array<Vec3, 3>* g) {
    double e;
    Vec3 g1, g2, g3;
    element_energy_gradient(m, ElementMaterialData{}, at(s, 0), at(s, 1), at(s, 2), r, 1.0, e, g1,
                            g2, g3);
    if (g) *g = {g1, g2, g3};
    return std::sqrt(2.0 * e);
  };
  for (double at_scale : {0.25, 1.0, 4.0, 16.0}) {
    Stencil s =
        stencil_of({rest[0], Vec3(1.03, 0.1, 0.01), Vec3(0.21, 0.93, 0.1)}, {1.0, 0.6, 1.4});
    std::array<Vec3, 3> g;
    const double c0 = C_of(s, &g);
    double grad_c_sq = 0.0;  // |grad C|^2_w = sum w |g|^2 / C^2
    for (int i = 0; i < 3; ++i) grad_c_sq += s.w[i] * g[i].squaredNorm() / (c0 * c0);
    const double alpha_tilde = at_scale * grad_c_sq;
    double lambda = 0.0;
    ProjectionContext ctx = context(s, alpha_tilde);
    ASSERT_TRUE(project_membrane(m, c, 1.0, ctx, &lambda));
    const double c1 = C_of(s, nullptr);
    // First order only where the step is a small part of C (C = sqrt(2E) bends along it).
    if (at_scale >= 4.0) {
      EXPECT_NEAR(c1 + alpha_tilde * lambda, 0.0, 0.01 * c0) << "alpha~ scale " << at_scale;
    }
    EXPECT_LT(c1, c0);
    EXPECT_NEAR(lambda, -c0 / (grad_c_sq + alpha_tilde), 1e-12 * c0 / grad_c_sq)
        << "the first multiplier step of math-spec 9.2, alpha~ scale " << at_scale;
  }
}

}  // namespace
}  // namespace shellcontract
