// Element-level checks of the chain rule (math-spec 4.4, 13): FD gradients in x, rest, rigid
// motion, momentum, degenerate and collapsed triangles. Uses StVK as the material; every model's
// own PK1 is checked in tests/material.
#include <gtest/gtest.h>

#include <array>
#include <random>

#include "fem/triangle_element.hpp"
#include "material/stvk.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

using Tri = std::array<Vec3, 3>;

double energy(const Stvk& m, const TriangleRest& r, const Tri& x, double s = 1.0) {
  double E;
  Vec3 g1, g2, g3;
  element_energy_gradient(m, ElementMaterialData{}, x[0], x[1], x[2], r, s, E, g1, g2, g3);
  return E;
}

std::array<Vec3, 3> gradient(const Stvk& m, const TriangleRest& r, const Tri& x, double s = 1.0) {
  double E;
  std::array<Vec3, 3> g;
  element_energy_gradient(m, ElementMaterialData{}, x[0], x[1], x[2], r, s, E, g[0], g[1], g[2]);
  return g;
}

/// Central-difference gradient with step h.
std::array<Vec3, 3> fd_gradient(const Stvk& m, const TriangleRest& r, const Tri& x, double h,
                                double s = 1.0) {
  std::array<Vec3, 3> g;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      Tri xp = x, xm = x;
      xp[i](k) += h;
      xm[i](k) -= h;
      g[i](k) = (energy(m, r, xp, s) - energy(m, r, xm, s)) / (2 * h);
    }
  return g;
}

double relative_error(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
  double num = 0, den = 0;
  for (int i = 0; i < 3; ++i) {
    num += (a[i] - b[i]).squaredNorm();
    den += b[i].squaredNorm();
  }
  return std::sqrt(num / den);
}

Tri random_triangle(std::mt19937& rng) {
  return {test::random_vec3(rng), test::random_vec3(rng), test::random_vec3(rng)};
}

const MaterialParams PARAMS{1.3, 0.7};

TEST(TriangleElement, RestFrameHasFbarIdentityAndZeroEnergy) {
  std::mt19937 rng(1);
  const Stvk m(PARAMS);
  for (int t = 0; t < 20; ++t) {
    const Tri x = random_triangle(rng);
    const TriangleRest r = triangle_rest(x[0], x[1], x[2]);
    ASSERT_FALSE(r.degenerate);
    EXPECT_NEAR(r.area, 0.5 * (x[0] - x[2]).cross(x[1] - x[2]).norm(), 1e-15);
    TriangleFrame fr;
    ASSERT_TRUE(triangle_frame(x[0], x[1], x[2], r.Dm_inv, r.area, 1.0, fr));
    EXPECT_LE((fr.F - Mat2::Identity()).norm(), 1e-12) << fr.F;
    EXPECT_LE(energy(m, r, x), 1e-24);
    const double lbar = (x[0] - x[2]).norm();
    for (const Vec3& g : gradient(m, r, x)) EXPECT_LE(g.norm(), 1e-12 * PARAMS.mu * lbar);
  }
}

TEST(TriangleElement, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(2);
  const Stvk m(PARAMS);
  for (int t = 0; t < 50; ++t) {
    const Tri rest = random_triangle(rng);
    const TriangleRest r = triangle_rest(rest[0], rest[1], rest[2]);
    // Random deformations: general, compressed to 30 %, and stretched.
    const double scale = t % 3 == 0 ? 0.3 : (t % 3 == 1 ? 1.0 : 1.7);
    Tri x;
    for (int i = 0; i < 3; ++i) x[i] = scale * rest[i] + 0.2 * test::random_vec3(rng);
    const auto g = gradient(m, r, x);
    double gnorm = 0;
    for (const Vec3& gi : g) gnorm += gi.norm();
    ASSERT_GT(gnorm, 1e-8);
    const double h = 1e-6 * (rest[0] - rest[2]).norm();
    EXPECT_LE(relative_error(g, fd_gradient(m, r, x, h)), 1e-6) << "trial " << t;
  }
}

TEST(TriangleElement, GradientMatchesFiniteDifferencesInvertedOrientation) {
  std::mt19937 rng(3);
  const Stvk m(PARAMS);
  const Tri rest = random_triangle(rng);
  const TriangleRest r = triangle_rest(rest[0], rest[1], rest[2]);
  Tri x = rest;
  x[0] += 0.3 * test::random_vec3(rng);
  const double h = 1e-6;
  EXPECT_LE(relative_error(gradient(m, r, x, -1.0), fd_gradient(m, r, x, h, -1.0)), 1e-6);
}

TEST(TriangleElement, NearDegenerateCurrentTriangleGradientIsExact) {
  // A sliver that is almost a segment (area 1e-7 of the rest area) and an exactly collinear
  // one (frame not regular): StVK depends only on C, so the gradient must stay exact.
  const Stvk m(PARAMS);
  const Tri rest{Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 0)};
  const TriangleRest r = triangle_rest(rest[0], rest[1], rest[2]);
  for (double lift : {1e-4, 0.0}) {
    const Tri x{Vec3(1, 0, 0), Vec3(0.5, lift, 0), Vec3(0, 0, 0)};
    TriangleFrame fr;
    ASSERT_TRUE(triangle_frame(x[0], x[1], x[2], r.Dm_inv, r.area, 1.0, fr));
    EXPECT_EQ(fr.regular, lift != 0.0);
    EXPECT_LE(relative_error(gradient(m, r, x), fd_gradient(m, r, x, 1e-7)), 1e-6) << lift;
  }
}

TEST(TriangleElement, AllVerticesCoincidentContributesNothing) {
  const Stvk m(PARAMS);
  const Tri rest{Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 0)};
  const TriangleRest r = triangle_rest(rest[0], rest[1], rest[2]);
  double E = -1;
  Vec3 g1, g2, g3;
  EXPECT_FALSE(element_energy_gradient(m, ElementMaterialData{}, Vec3::Ones(), Vec3::Ones(),
                                       Vec3::Ones(), r, 1.0, E, g1, g2, g3));
  EXPECT_EQ(E, 0.0);
  EXPECT_EQ(g1.norm() + g2.norm() + g3.norm(), 0.0);
}

TEST(TriangleElement, DegenerateRestTriangleIsFlaggedAndInactive) {
  const Stvk m(PARAMS);
  // Collinear and nearly collinear (2A = 1e-12 < 1e-10 lbar^2) rest triangles.
  for (double lift : {0.0, 1e-12}) {
    const Tri rest{Vec3(0, 0, 0), Vec3(1, lift, 0), Vec3(2, 0, 0)};
    const TriangleRest r = triangle_rest(rest[0], rest[1], rest[2]);
    EXPECT_TRUE(r.degenerate) << lift;
    Tri x = rest;
    x[1].y() = 0.5;
    EXPECT_EQ(energy(m, r, x), 0.0);
  }
  EXPECT_TRUE(triangle_rest(Vec3::Zero(), Vec3::Zero(), Vec3::Zero()).degenerate);
}

TEST(TriangleElement, RigidMotionInvarianceAndMomentum) {
  std::mt19937 rng(4);
  const Stvk m(PARAMS);
  for (int t = 0; t < 20; ++t) {
    const Tri rest = random_triangle(rng);
    const TriangleRest r = triangle_rest(rest[0], rest[1], rest[2]);
    Tri x;
    for (int i = 0; i < 3; ++i) x[i] = 0.8 * rest[i] + 0.3 * test::random_vec3(rng);
    const Mat3 Q = test::random_rotation(rng);
    const Vec3 shift = test::random_vec3(rng, 5.0);
    Tri y;
    for (int i = 0; i < 3; ++i) y[i] = Q * x[i] + shift;
    const double E = energy(m, r, x);
    EXPECT_NEAR(energy(m, r, y), E, 1e-12 * E);
    const auto gx = gradient(m, r, x);
    const auto gy = gradient(m, r, y);
    double gscale = 0;
    for (int i = 0; i < 3; ++i) gscale = std::max(gscale, gx[i].norm());
    const Vec3 n = (x[0] - x[2]).cross(x[1] - x[2]).normalized();
    Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
    for (int i = 0; i < 3; ++i) {
      EXPECT_LE((gy[i] - Q * gx[i]).norm(), 1e-12 * gscale);
      EXPECT_LE(std::abs(gx[i].dot(n)), 1e-12 * gscale) << "membrane force must be in-plane";
      force += gx[i];
      torque += x[i].cross(gx[i]);
    }
    EXPECT_LE(force.norm(), 1e-12 * gscale);
    EXPECT_LE(torque.norm(), 1e-11 * gscale);
  }
}

}  // namespace
}  // namespace shellcontract
