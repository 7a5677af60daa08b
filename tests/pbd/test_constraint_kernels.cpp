// One-constraint projections (math-spec 9, 13 "Pipeline" momentum, 9.1 properties).
#include <gtest/gtest.h>

#include <random>
#include <vector>

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

MembraneConstraint membrane_on(const std::vector<Vec3>& rest) {
  const TriangleRest r = triangle_rest(rest[0], rest[1], rest[2]);
  MembraneConstraint c;
  c.v = {0, 1, 2};
  c.Dm_inv = r.Dm_inv;
  c.rest_area = r.area;
  c.max_step = 1e9;  // no clamp unless a test sets one
  return c;
}

Stencil deformed(const std::vector<Vec3>& rest, std::mt19937& rng, double noise) {
  Stencil s;
  std::uniform_real_distribution<double> mass(0.5, 2.0);
  for (const Vec3& p : rest) {
    const Vec3 q = p + noise * test::random_vec3(rng);
    s.x.insert(s.x.end(), {q.x(), q.y(), q.z()});
    s.w.push_back(1.0 / mass(rng));
  }
  return s;
}

Vec3 at(const Stencil& s, int i) { return Vec3(s.x[3 * i], s.x[3 * i + 1], s.x[3 * i + 2]); }

ProjectionContext context(Stencil& s) {
  ProjectionContext ctx;
  ctx.x = s.x.data();
  ctx.w = s.w.data();
  return ctx;
}

TEST(MembraneProjection, ConservesMomentumAndReducesEnergy) {
  std::mt19937 rng(11);
  for (int t = 0; t < 20; ++t) {
    const std::vector<Vec3> rest{test::random_vec3(rng), test::random_vec3(rng), test::random_vec3(rng)};
    const MembraneConstraint c = membrane_on(rest);
    Stencil s = deformed(rest, rng, 0.1);
    const Stencil before = s;
    const Stvk m(MaterialParams{1.0, 1.0});
    ProjectionContext ctx = context(s);
    auto E = [&](const Stencil& q) {
      double e;
      Vec3 g1, g2, g3;
      element_energy_gradient(m, ElementMaterialData{}, at(q, 0), at(q, 1), at(q, 2),
                              triangle_rest(rest[0], rest[1], rest[2]), 1.0, e, g1, g2, g3);
      return e;
    };
    ASSERT_TRUE(project_membrane(m, c, 1.0, ctx, nullptr));
    Vec3 momentum = Vec3::Zero();
    double moved = 0;
    for (int i = 0; i < 3; ++i) {
      momentum += (at(s, i) - at(before, i)) / s.w[i];
      moved += (at(s, i) - at(before, i)).norm();
    }
    ASSERT_GT(moved, 0.0);
    EXPECT_LE(momentum.norm(), 1e-14 * (1 + moved)) << "trial " << t;
    EXPECT_LT(E(s), E(before)) << "trial " << t;
  }
}

TEST(MembraneProjection, PbdIsInvariantToEnergyScaleAndXpbdRigidLimitIsTwicePbd) {
  // math-spec 9.1(a): scaling E by alpha leaves the PBD step unchanged. 9.1(c)/9.2: with zero
  // compliance, XPBD on C = sqrt(2E) takes exactly twice the PBD(C = E) step.
  std::mt19937 rng(12);
  const std::vector<Vec3> rest{Vec3(0, 0, 0), Vec3(1, 0.1, 0), Vec3(0.2, 0.9, 0.1)};
  const MembraneConstraint c = membrane_on(rest);
  const Stencil start = deformed(rest, rng, 0.15);
  std::vector<std::vector<double>> steps;
  for (double alpha : {1e-3, 1.0, 1e4}) {
    Stencil s = start;
    ProjectionContext ctx = context(s);
    project_membrane(Stvk(MaterialParams{alpha * 1.0, alpha * 0.5}), c, 1.0, ctx, nullptr);
    steps.push_back(s.x);
  }
  for (std::size_t k = 0; k < start.x.size(); ++k) {
    const double d = steps[1][k] - start.x[k];
    EXPECT_NEAR(steps[0][k] - start.x[k], d, 1e-13);
    EXPECT_NEAR(steps[2][k] - start.x[k], d, 1e-13);
  }
  Stencil s = start;
  ProjectionContext ctx = context(s);
  ctx.alpha_tilde = 0.0;
  double lambda = 0.0;
  project_membrane(Stvk(MaterialParams{1.0, 0.5}), c, 1.0, ctx, &lambda);
  for (std::size_t k = 0; k < start.x.size(); ++k)
    EXPECT_NEAR(s.x[k] - start.x[k], 2.0 * (steps[1][k] - start.x[k]), 1e-13);
  EXPECT_LT(lambda, 0.0);
}

TEST(MembraneProjection, RestIsSkippedPinnedVertexNeverMovesAndClampHolds) {
  std::mt19937 rng(13);
  const std::vector<Vec3> rest{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  MembraneConstraint c = membrane_on(rest);
  const Stvk m(MaterialParams{});
  Stencil s = deformed(rest, rng, 0.0);
  ProjectionContext ctx = context(s);
  ctx.energy_floor = 1e-16;
  EXPECT_FALSE(project_membrane(m, c, 1.0, ctx, nullptr));

  Stencil p = deformed(rest, rng, 0.3);
  p.w[1] = 0.0;
  const Vec3 pinned = at(p, 1);
  c.max_step = 1e-3;
  ProjectionContext pc = context(p);
  const Stencil before = p;
  ASSERT_TRUE(project_membrane(m, c, 1.0, pc, nullptr));
  EXPECT_EQ(at(p, 1), pinned);
  double longest = 0;
  for (int i = 0; i < 3; ++i) longest = std::max(longest, (at(p, i) - at(before, i)).norm());
  EXPECT_NEAR(longest, 1e-3, 1e-15) << "a large step is clamped to exactly max_step";
}

TEST(MembraneProjection, StationaryPointWithPositiveEnergyIsSkipped) {
  // StVK at F = 0 (all vertices coincide): E > 0, gradient 0 (math-spec 9.1d).
  const std::vector<Vec3> rest{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const MembraneConstraint c = membrane_on(rest);
  Stencil s{{0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5}, {1, 1, 1}};
  ProjectionContext ctx = context(s);
  EXPECT_FALSE(project_membrane(Stvk(MaterialParams{}), c, 1.0, ctx, nullptr));
  for (double v : s.x) EXPECT_EQ(v, 0.5);
}

IsometricHingeConstraint hinge_on(const std::vector<Vec3>& rest) {
  const IsometricBendingRest r = isometric_bending_rest(rest[0], rest[1], rest[2], rest[3]);
  return {{0, 1, 2, 3}, r.K, 3.0 / r.area_sum, 1e9};
}

TEST(IsometricHingeProjection, UnitStiffnessHalvesHAndConservesMomentum) {
  std::mt19937 rng(14);
  const std::vector<Vec3> flat{Vec3(-0.4, 0, 0), Vec3(0.6, 0, 0), Vec3(0.1, 0.7, 0), Vec3(-0.2, -0.5, 0)};
  const IsometricHingeConstraint c = hinge_on(flat);
  Stencil s = deformed(flat, rng, 0.2);
  const Stencil before = s;
  ProjectionContext ctx = context(s);
  auto h = [&](const Stencil& q) {
    return Vec3(c.K(0) * at(q, 0) + c.K(1) * at(q, 1) + c.K(2) * at(q, 2) + c.K(3) * at(q, 3));
  };
  ASSERT_GT(h(before).norm(), 1e-3);
  ASSERT_TRUE(project_isometric_hinge(c, 1.0, ctx, nullptr));
  EXPECT_LE((h(s) - 0.5 * h(before)).norm(), 1e-13);
  Vec3 momentum = Vec3::Zero();
  for (int i = 0; i < 4; ++i) momentum += (at(s, i) - at(before, i)) / s.w[i];
  EXPECT_LE(momentum.norm(), 1e-14);
}

TEST(IsometricHingeProjection, XpbdRigidLimitZeroesH) {
  // alpha_tilde = 0: the vector constraint C = sqrt(beta) h is linear, so one projection
  // solves it exactly (h -> 0).
  std::mt19937 rng(15);
  const std::vector<Vec3> flat{Vec3(-0.4, 0, 0), Vec3(0.6, 0, 0), Vec3(0.1, 0.7, 0), Vec3(-0.2, -0.5, 0)};
  const IsometricHingeConstraint c = hinge_on(flat);
  Stencil s = deformed(flat, rng, 0.2);
  ProjectionContext ctx = context(s);
  double lambda[3] = {0, 0, 0};
  ASSERT_TRUE(project_isometric_hinge(c, 0.3, ctx, lambda));
  const Vec3 h = c.K(0) * at(s, 0) + c.K(1) * at(s, 1) + c.K(2) * at(s, 2) + c.K(3) * at(s, 3);
  EXPECT_LE(h.norm(), 1e-13);
}

TEST(DihedralHingeProjection, ReducesAngleErrorAndConservesMomentum) {
  std::mt19937 rng(16);
  const std::vector<Vec3> rest{Vec3(-0.4, 0, 0), Vec3(0.6, 0, 0), Vec3(0.1, 0.7, 0), Vec3(-0.2, -0.4, -0.3)};
  DihedralHingeConstraint c{{0, 1, 2, 3}, dihedral_bending_rest(rest[0], rest[1], rest[2], rest[3]), 1e9};
  Stencil s = deformed(rest, rng, 0.15);
  const Stencil before = s;
  ProjectionContext ctx = context(s);
  double th0, th1;
  dihedral_angle(at(before, 0), at(before, 1), at(before, 2), at(before, 3), th0);
  ASSERT_TRUE(project_dihedral_hinge(c, 1.0, ctx, nullptr));
  dihedral_angle(at(s, 0), at(s, 1), at(s, 2), at(s, 3), th1);
  EXPECT_LT(std::abs(th1 - c.rest.rest_angle), std::abs(th0 - c.rest.rest_angle));
  Vec3 momentum = Vec3::Zero();
  for (int i = 0; i < 4; ++i) momentum += (at(s, i) - at(before, i)) / s.w[i];
  EXPECT_LE(momentum.norm(), 1e-13);
}

TEST(DihedralHingeProjection, XpbdStepOnAFoldedHingeIsClamped) {
  // A hinge folded far from its rest angle, stiff next to its compliance: the linearized XPBD step
  // would move its vertices further than max_step. It must be clamped to exactly max_step, with
  // lambda taking the clamped increment, and still conserve momentum.
  const std::vector<Vec3> rest{Vec3(-0.4, 0, 0), Vec3(0.6, 0, 0), Vec3(0.1, 0.7, 0), Vec3(-0.2, -0.4, -0.3)};
  DihedralHingeConstraint c{{0, 1, 2, 3}, dihedral_bending_rest(rest[0], rest[1], rest[2], rest[3]), 1e-3};
  Stencil s{{-0.4, 0, 0, 0.6, 0, 0, 0.1, 0.7, 0, -0.2, 0.6, 0.05}, {1, 1, 1, 1}};  // vertex 3 folded over
  const Stencil before = s;
  ProjectionContext ctx = context(s);
  ctx.alpha_tilde = 1e-6;
  double lambda = 0.0;
  ASSERT_TRUE(project_dihedral_hinge(c, 1.0, ctx, &lambda));
  double longest = 0.0;
  Vec3 momentum = Vec3::Zero();
  for (int i = 0; i < 4; ++i) {
    longest = std::max(longest, (at(s, i) - at(before, i)).norm());
    momentum += (at(s, i) - at(before, i)) / s.w[i];
  }
  EXPECT_NEAR(longest, 1e-3, 1e-15) << "the XPBD step is clamped to exactly max_step";
  EXPECT_LE(momentum.norm(), 1e-15);
  // Unclamped, the same hinge moves a vertex by more than 0.1: the clamp is what acted.
  Stencil u = before;
  ProjectionContext uctx = context(u);
  uctx.alpha_tilde = 1e-6;
  double lambda_u = 0.0;
  c.max_step = 1e9;
  ASSERT_TRUE(project_dihedral_hinge(c, 1.0, uctx, &lambda_u));
  double longest_u = 0.0;
  for (int i = 0; i < 4; ++i) longest_u = std::max(longest_u, (at(u, i) - at(before, i)).norm());
  EXPECT_GT(longest_u, 0.1);
  EXPECT_NEAR(lambda / lambda_u, 1e-3 / longest_u, 1e-12) << "lambda takes the clamped increment";
}

}  // namespace
}  // namespace shellcontract

namespace shellcontract {
namespace {

TEST(MembraneCForm, AgreesWithTheFrameLiftIncludingCollapsedTriangles) {
  // math-spec 4.4: for energies of C alone, P3 = F S equals p^T Pbar. The solver's fast path
  // (C-form) must give the same energy and gradient as fem/triangle_element's frame path.
  std::mt19937 rng(17);
  const Stvk m(MaterialParams{1.3, 0.4});
  for (int t = 0; t < 40; ++t) {
    const std::vector<Vec3> rest{test::random_vec3(rng), test::random_vec3(rng), test::random_vec3(rng)};
    const MembraneConstraint c = membrane_on(rest);
    std::vector<Vec3> x(3);
    for (int i = 0; i < 3; ++i) x[i] = 0.7 * rest[i] + 0.3 * test::random_vec3(rng);
    if (t == 0) x[2] = 0.5 * (x[0] + x[1]);  // collinear: frame not regular
    std::array<Vec3, 3> g_c, g_f;
    const double E_c = membrane_energy_gradient_cform(m, c, x[0], x[1], x[2], g_c);
    double E_f;
    element_energy_gradient(m, ElementMaterialData{}, x[0], x[1], x[2],
                            triangle_rest(rest[0], rest[1], rest[2]), 1.0, E_f, g_f[0], g_f[1], g_f[2]);
    ASSERT_GT(E_f, 0.0);
    EXPECT_NEAR(E_c, E_f, 1e-12 * E_f) << "trial " << t;
    for (int i = 0; i < 3; ++i)
      EXPECT_LE((g_c[i] - g_f[i]).norm(), 1e-11 * (1.0 + g_f[i].norm())) << "trial " << t << " vertex " << i;
  }
}

}  // namespace
}  // namespace shellcontract

#include "material/anisotropic_arap.hpp"

namespace shellcontract {
namespace {

TEST(AnisotropicPaperProjection, InwardPushMatchesMathSpec93AndIsZeroAtRest) {
  // math-spec 9.3 / 13: with the k_A term, sum_i m_i dx_i = -3 k_A (E_A / Gt) n, with
  // Gt = sum w |g|^2 + k_A^2 sum w; at rest E_A = 0 and nothing moves (the E_A gate).
  std::mt19937 rng(18);
  const std::vector<Vec3> rest{Vec3(0, 0, 0), Vec3(1, 0.1, 0), Vec3(0.2, 0.9, 0.1)};
  MembraneConstraint c = membrane_on(rest);
  c.data.fiber = Vec2(0.6, 0.8);
  MaterialParams p;
  p.mu_aniso = 2.0;
  const AnisotropicArap arap(p);
  const double k_a = 0.7;
  const Vec3 n = (rest[0] - rest[2]).cross(rest[1] - rest[2]).normalized();
  Stencil at_rest = deformed(rest, rng, 0.0);
  ProjectionContext ctx0 = context(at_rest);
  ctx0.energy_floor = 1e-16;
  EXPECT_FALSE(project_anisotropic_paper(arap, c, k_a, n, ctx0));

  Stencil s = deformed(rest, rng, 0.1);
  const Stencil before = s;
  // The solver freezes the current face normal; the fibre gradients are orthogonal to it.
  const Vec3 n_now = (at(s, 0) - at(s, 2)).cross(at(s, 1) - at(s, 2)).normalized();
  double E;
  std::array<Vec3, 3> g;
  element_energy_gradient(arap, c.data, at(s, 0), at(s, 1), at(s, 2),
                          triangle_rest(rest[0], rest[1], rest[2]), 1.0, E, g[0], g[1], g[2]);
  ASSERT_GT(E, 1e-8);
  double Gt = 0.0;
  for (int i = 0; i < 3; ++i) Gt += s.w[i] * (g[i].squaredNorm() + k_a * k_a);
  ProjectionContext ctx = context(s);
  ASSERT_TRUE(project_anisotropic_paper(arap, c, k_a, n_now, ctx));
  Vec3 momentum = Vec3::Zero();
  for (int i = 0; i < 3; ++i) momentum += (at(s, i) - at(before, i)) / s.w[i];
  const Vec3 expected = -3.0 * k_a * (E / Gt) * n_now;
  EXPECT_LE((momentum - expected).norm(), 1e-12 * expected.norm()) << momentum.transpose();
}

}  // namespace
}  // namespace shellcontract
