// Bending kernels (math-spec 8, 13 "Bending"): cotangent weights, FD gradients, the isometric
// fold closed form, the dihedral angle's sign, branch cut and degenerate guards.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "bending/dihedral_bending.hpp"
#include "bending/isometric_bending.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/material.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

using Stencil = std::array<Vec3, 4>;
constexpr double PI = 3.14159265358979323846;

/// A hinge along the x axis: x0 = (-a,0,0), x1 = (b,0,0); face A's tip in the xy plane at +y,
/// face B's tip rotated by the fold angle phi about the x axis (phi = 0: flat).
Stencil folded_hinge(double phi, double a = 0.4, double b = 0.6, double yA = 0.7, double yB = 0.5) {
  return {Vec3(-a, 0, 0), Vec3(b, 0, 0), Vec3(0.1, yA, 0),
          Vec3(-0.2, -yB * std::cos(phi), -yB * std::sin(phi))};
}

template <class EnergyFn>
std::array<Vec3, 4> fd(EnergyFn E, const Stencil& x, double h) {
  std::array<Vec3, 4> g;
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k) {
      Stencil p = x, m = x;
      p[i](k) += h;
      m[i](k) -= h;
      g[i](k) = (E(p) - E(m)) / (2 * h);
    }
  return g;
}

double rel(const std::array<Vec3, 4>& a, const std::array<Vec3, 4>& b) {
  double num = 0, den = 0;
  for (int i = 0; i < 4; ++i) {
    num += (a[i] - b[i]).squaredNorm();
    den += b[i].squaredNorm();
  }
  return std::sqrt(num / den);
}

TEST(GuardedCotangent, KnownAnglesClampAndZeroLength) {
  EXPECT_NEAR(guarded_cotangent(Vec3(1, 0, 0), Vec3(1, 1, 0)), 1.0, 1e-15);
  EXPECT_NEAR(guarded_cotangent(Vec3(1, 0, 0), Vec3(0, 2, 0)), 0.0, 1e-15);
  EXPECT_NEAR(guarded_cotangent(Vec3(1, 0, 0), Vec3(-1, std::sqrt(3.0), 0)), -1 / std::sqrt(3.0), 1e-15);
  EXPECT_EQ(guarded_cotangent(Vec3(1, 0, 0), Vec3(1, 1e-9, 0)), MAX_COTANGENT);
  EXPECT_EQ(guarded_cotangent(Vec3(1, 0, 0), Vec3(2, 0, 0)), MAX_COTANGENT);   // parallel
  EXPECT_EQ(guarded_cotangent(Vec3(1, 0, 0), Vec3(-2, 0, 0)), -MAX_COTANGENT); // antiparallel
  EXPECT_EQ(guarded_cotangent(Vec3::Zero(), Vec3(1, 0, 0)), 0.0);
  EXPECT_NEAR(MAX_COTANGENT, 1.0 / std::tan(PI / 180.0), 1e-12);
}

TEST(IsometricBending, WeightsSumToZeroAndFlatHingeHasZeroEnergy) {
  const Stencil x = folded_hinge(0.0);
  const IsometricBendingRest r = isometric_bending_rest(x[0], x[1], x[2], x[3]);
  EXPECT_NEAR(r.K.sum(), 0.0, 1e-14);
  EXPECT_GT(r.K.norm(), 1.0);
  EXPECT_LE(isometric_bending_h(r, x[0], x[1], x[2], x[3]).norm(), 1e-14);
  EXPECT_LE(isometric_bending_energy(r, x[0], x[1], x[2], x[3]), 1e-28);
  // Cotangents of interior angles: for a right isosceles face the weight is known.
  const Stencil s{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, -1, 0)};
  const IsometricBendingRest q = isometric_bending_rest(s[0], s[1], s[2], s[3]);
  // c01 (at x1, face A) = cot 45 = 1, c02 (at x0, face A) = cot 90 = 0,
  // c03 (at x0, face B) = cot 45 = 1, c04 (at x1, face B) = cot 90 = 0.
  EXPECT_NEAR(q.K(0), 1.0, 1e-15);
  EXPECT_NEAR(q.K(1), 1.0, 1e-15);
  EXPECT_NEAR(q.K(2), -1.0, 1e-15);
  EXPECT_NEAR(q.K(3), -1.0, 1e-15);
}

TEST(IsometricBending, SliverRestAnglesAreClampedAndCounted) {
  // Face A has an angle of ~0.06 degrees at x1: its cotangent is clamped (math-spec 11).
  const Stencil s{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.001, 0.001, 0), Vec3(0.5, -0.5, 0)};
  int clamped = 0;
  const IsometricBendingRest r = isometric_bending_rest(s[0], s[1], s[2], s[3], &clamped);
  EXPECT_EQ(clamped, 1);
  EXPECT_TRUE(r.K.allFinite());
  EXPECT_NEAR(r.K.sum(), 0.0, 1e-12);
  int none = 0;
  const Stencil flat = folded_hinge(0.0);
  isometric_bending_rest(flat[0], flat[1], flat[2], flat[3], &none);
  EXPECT_EQ(none, 0);
}

TEST(IsometricBending, IsometricFoldMatchesClosedForm) {
  const Stencil flat = folded_hinge(0.0);
  const IsometricBendingRest r = isometric_bending_rest(flat[0], flat[1], flat[2], flat[3]);
  const double e0 = (flat[1] - flat[0]).norm();
  for (double theta : {0.0, 0.3, 1.0, 2.0, 3.0}) {
    const Stencil x = folded_hinge(theta);
    // math-spec 8.2: E_B = 6 |e0|^2 sin^2(theta/2) / (A0 + A1); area_sum = A0 + A1.
    const double closed = 6 * e0 * e0 * std::pow(std::sin(theta / 2), 2) / r.area_sum;
    EXPECT_NEAR(isometric_bending_energy(r, x[0], x[1], x[2], x[3]), closed, 1e-12 * (1 + closed))
        << "theta " << theta;
  }
}

TEST(IsometricBending, GradientMatchesFiniteDifferencesAndConservesMomentum) {
  std::mt19937 rng(5);
  for (int t = 0; t < 30; ++t) {
    const Stencil rest = folded_hinge(0.5 * t / 30.0);
    const IsometricBendingRest r = isometric_bending_rest(rest[0], rest[1], rest[2], rest[3]);
    Stencil x;
    for (int i = 0; i < 4; ++i) x[i] = rest[i] + 0.2 * test::random_vec3(rng);
    auto E = [&](const Stencil& y) { return isometric_bending_energy(r, y[0], y[1], y[2], y[3]); };
    const auto g = isometric_bending_gradient(r, x[0], x[1], x[2], x[3]);
    ASSERT_GT(g[0].norm(), 1e-8);
    EXPECT_LE(rel(g, fd(E, x, 1e-6)), 1e-6);
    Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
    for (int i = 0; i < 4; ++i) {
      force += g[i];
      torque += x[i].cross(g[i]);
    }
    EXPECT_LE(force.norm(), 1e-12 * g[0].norm());
    // h is translation invariant and rotates with the stencil: E_B is rigid-motion invariant,
    // so its forces exert no net torque.
    EXPECT_LE(torque.norm(), 1e-11 * g[0].norm());
  }
}

TEST(DihedralBending, ForcesHaveNoNetForceOrTorqueAndAreRotationInvariant) {
  std::mt19937 rng(8);
  for (int t = 0; t < 20; ++t) {
    const Stencil rest = folded_hinge(0.3);
    const DihedralBendingRest r = dihedral_bending_rest(rest[0], rest[1], rest[2], rest[3]);
    Stencil x;
    for (int i = 0; i < 4; ++i) x[i] = rest[i] + 0.1 * test::random_vec3(rng);
    const auto g = dihedral_bending_gradient(r, 0.5, x[0], x[1], x[2], x[3]);
    double scale = 0;
    Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
    for (int i = 0; i < 4; ++i) {
      scale = std::max(scale, g[i].norm());
      force += g[i];
      torque += x[i].cross(g[i]);
    }
    ASSERT_GT(scale, 0.0);
    EXPECT_LE(force.norm(), 1e-12 * scale);
    EXPECT_LE(torque.norm(), 1e-11 * scale);
    const Mat3 Q = test::random_rotation(rng);
    Stencil y;
    for (int i = 0; i < 4; ++i) y[i] = Q * x[i] + Vec3(1, -2, 3);
    EXPECT_NEAR(dihedral_bending_energy(r, 0.5, y[0], y[1], y[2], y[3]),
                dihedral_bending_energy(r, 0.5, x[0], x[1], x[2], x[3]), 1e-12);
    const auto gy = dihedral_bending_gradient(r, 0.5, y[0], y[1], y[2], y[3]);
    for (int i = 0; i < 4; ++i) EXPECT_LE((gy[i] - Q * g[i]).norm(), 1e-10 * scale);
  }
}

TEST(IsometricBending, CurvedRestHingeIsNotAtRest) {
  // Documented property of the paper's model (math-spec 8.2): a hinge bent by 0.5 rad has
  // positive energy at its own rest shape.
  const Stencil bent = folded_hinge(0.5);
  const IsometricBendingRest r = isometric_bending_rest(bent[0], bent[1], bent[2], bent[3]);
  EXPECT_GT(isometric_bending_energy(r, bent[0], bent[1], bent[2], bent[3]), 0.01);
}

TEST(DihedralAngle, SignFlatAndConvexFold) {
  double theta = 1;
  const Stencil flat = folded_hinge(0.0);
  ASSERT_TRUE(dihedral_angle(flat[0], flat[1], flat[2], flat[3], theta));
  EXPECT_NEAR(theta, 0.0, 1e-15);
  // folded_hinge(phi) with phi > 0 turns face B's tip to -z: with face A's outward normal +z
  // (A = (x0, x1, x2) counter-clockwise seen from +z) the hinge is convex seen from outside.
  for (double phi : {0.3, 1.0, 2.5}) {
    const Stencil x = folded_hinge(phi);
    ASSERT_TRUE(dihedral_angle(x[0], x[1], x[2], x[3], theta));
    EXPECT_NEAR(theta, phi, 1e-12) << phi;
    const Stencil y = folded_hinge(-phi);
    ASSERT_TRUE(dihedral_angle(y[0], y[1], y[2], y[3], theta));
    EXPECT_NEAR(theta, -phi, 1e-12) << -phi;
  }
}

TEST(DihedralAngle, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(6);
  for (int t = 0; t < 30; ++t) {
    Stencil x = folded_hinge(-2.5 + 5.0 * t / 30.0);
    for (int i = 0; i < 4; ++i) x[i] += 0.05 * test::random_vec3(rng);
    double theta;
    std::array<Vec3, 4> g;
    ASSERT_TRUE(dihedral_angle_gradient(x[0], x[1], x[2], x[3], theta, g));
    auto th = [](const Stencil& y) {
      double a;
      dihedral_angle(y[0], y[1], y[2], y[3], a);
      return a;
    };
    EXPECT_LE(rel(g, fd(th, x, 1e-7)), 1e-6) << "trial " << t;
  }
}

TEST(DihedralBending, ZeroAtRestFiniteDifferencesAndBranchCut) {
  std::mt19937 rng(7);
  const Stencil rest = folded_hinge(0.8);
  const DihedralBendingRest r = dihedral_bending_rest(rest[0], rest[1], rest[2], rest[3]);
  EXPECT_NEAR(r.rest_angle, 0.8, 1e-12);
  EXPECT_LE(dihedral_bending_energy(r, 0.7, rest[0], rest[1], rest[2], rest[3]), 1e-28);
  for (const Vec3& g : dihedral_bending_gradient(r, 0.7, rest[0], rest[1], rest[2], rest[3]))
    EXPECT_LE(g.norm(), 1e-14);
  Stencil x = rest;
  for (int i = 0; i < 4; ++i) x[i] += 0.1 * test::random_vec3(rng);
  auto E = [&](const Stencil& y) { return dihedral_bending_energy(r, 0.7, y[0], y[1], y[2], y[3]); };
  EXPECT_LE(rel(dihedral_bending_gradient(r, 0.7, x[0], x[1], x[2], x[3]), fd(E, x, 1e-7)), 1e-6);
  // Across the branch cut: rest near +pi, current near -pi is a small difference.
  EXPECT_NEAR(wrapped_angle_difference(-PI + 0.1, PI - 0.1), 0.2, 1e-12);
  EXPECT_NEAR(wrapped_angle_difference(PI - 0.1, -PI + 0.1), -0.2, 1e-12);
}

/// Hinge energy of a closed cylinder of radius R and length L, triangulated regularly (nu
/// columns, nv rows, alternating diagonals), against a flat rest (rest angle 0 on every hinge,
/// kappa_bar from the cylinder's own triangles), and its area.
std::pair<double, double> cylinder_hinge_energy(double k_bending, double R, double L, int nu,
                                                int nv) {
  std::vector<Vec3> x;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double t = 2.0 * PI * i / nu;
      x.emplace_back(R * std::cos(t), R * std::sin(t), L * j / nv);
    }
  std::vector<std::array<int, 3>> faces;  // counter-clockwise seen from outside
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int a = j * nu + i, b = j * nu + (i + 1) % nu, c = a + nu, d = b + nu;
      if ((i + j) % 2 == 0) {
        faces.push_back({a, b, d});
        faces.push_back({a, d, c});
      } else {
        faces.push_back({a, b, c});
        faces.push_back({b, d, c});
      }
    }
  // Directed edge (u -> v) of a face -> its third vertex; a hinge is an edge used both ways.
  std::map<std::pair<int, int>, int> tip;
  double area = 0.0;
  for (const auto& f : faces) {
    for (int k = 0; k < 3; ++k) tip[{f[k], f[(k + 1) % 3]}] = f[(k + 2) % 3];
    area += 0.5 * (x[f[1]] - x[f[0]]).cross(x[f[2]] - x[f[0]]).norm();
  }
  double energy = 0.0;
  for (const auto& [edge, x2] : tip) {
    const auto other = tip.find({edge.second, edge.first});
    if (other == tip.end()) continue;  // an end of the cylinder
    const Vec3 &p0 = x[edge.first], &p1 = x[edge.second], &p2 = x[x2], &p3 = x[other->second];
    DihedralBendingRest rest = dihedral_bending_rest(p0, p1, p2, p3);
    rest.rest_angle = 0.0;  // a flat sheet rolled up
    energy += 0.5 * dihedral_bending_energy(rest, k_bending, p0, p1, p2, p3);  // each hinge twice
  }
  return {energy, area};
}

TEST(DihedralBending, CylinderMatchesPlateEnergyWithStiffnessFromYoung) {
  const double E = 1000.0, nu = 0.3, h = 0.001, R = 1.0, L = 2.0;
  const double D = E * h * h * h / (12.0 * (1.0 - nu * nu));
  const double k_b = dihedral_k_bending_from_young(E, nu, h);
  EXPECT_NEAR(k_b, D / 3.0, 1e-15 * D);
  // A plate rolled into a cylinder stores (D / 2) / R^2 per unit area; with k_B = D these hinge
  // sums are 3.001-3.010 times that (docs/math/bending-from-material.md).
  for (const auto& [nu_cols, nv_rows] :
       {std::pair{32, 10}, std::pair{64, 20}, std::pair{128, 40}}) {
    const auto [energy, area] = cylinder_hinge_energy(k_b, R, L, nu_cols, nv_rows);
    EXPECT_NEAR(energy / (0.5 * D / (R * R) * area), 1.0, 0.005) << nu_cols << " x " << nv_rows;
  }
  EXPECT_THROW(dihedral_k_bending_from_young(0.0, nu, h), UsageError);
  EXPECT_THROW(dihedral_k_bending_from_young(E, 1.0, h), UsageError);
  EXPECT_THROW(dihedral_k_bending_from_young(E, nu, std::nan("")), UsageError);
}

TEST(DihedralBending, CollapsedFaceIsSkipped) {
  Stencil x = folded_hinge(0.5);
  x[2] = 0.5 * (x[0] + x[1]);  // face A collapses onto the edge
  double theta = 1;
  std::array<Vec3, 4> g;
  EXPECT_FALSE(dihedral_angle_gradient(x[0], x[1], x[2], x[3], theta, g));
  for (const Vec3& gi : g) EXPECT_EQ(gi.norm(), 0.0);
  const DihedralBendingRest r{0.3, 1.0};
  EXPECT_EQ(dihedral_bending_energy(r, 1.0, x[0], x[1], x[2], x[3]), 0.0);
}

}  // namespace
}  // namespace shellcontract
