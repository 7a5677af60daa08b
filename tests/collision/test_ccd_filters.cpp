// CCD narrow phase, the parts before root finding (math-spec 10.3-10.6 and the CCD list of 13):
// the cubic coefficients and Bernstein forms, the non-penetration filter, the swept-box and
// separating-axis culls. Times of impact are test_ccd.cpp's.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "collision/ccd.hpp"
#include "collision/ccd_test_helpers.hpp"
#include "collision/distance.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

using namespace test;  // ccd_test_helpers.hpp and the random geometry

// ------------------------------------------------------------------------------ cubic forms

TEST(CoplanarityCubic, MatchesDirectTripleProduct) {
  std::mt19937 rng(101);
  for (CcdPrimitive kind : KINDS)
    for (int trial = 0; trial < 200; ++trial) {
      CcdStencil x0, x1;
      for (int k = 0; k < 4; ++k) {
        x0[k] = test::random_vec3(rng);
        x1[k] = x0[k] + test::random_vec3(rng, 0.5);
      }
      const std::array<double, 4> c = coplanarity_cubic(kind, x0, x1);
      ASSERT_GT(std::abs(c[3]) + std::abs(c[2]), 0.0);  // a real cubic, not a constant
      for (double t : {0.0, 0.37, 1.0}) {
        const double direct = triple_product_at(kind, x0, x1, t);
        EXPECT_NEAR(power_eval(c, t), direct, 1e-13) << "t=" << t << describe(x0, x1);
      }
    }
}

TEST(CoplanarityCubic, BernsteinEqualsPowerFormAndTangForm) {
  std::mt19937 rng(202);
  for (CcdPrimitive kind : KINDS)
    for (int trial = 0; trial < 200; ++trial) {
      CcdStencil x0, x1;
      for (int k = 0; k < 4; ++k) {
        x0[k] = test::random_vec3(rng);
        x1[k] = test::random_vec3(rng);
      }
      const std::array<double, 4> from_power = bernstein_from_power(coplanarity_cubic(kind, x0, x1));
      const std::array<double, 4> blossom = coplanarity_bernstein(kind, x0, x1);
      const std::array<double, 4> tang = tang_bernstein(kind, x0, x1);
      for (int k = 0; k < 4; ++k) {
        EXPECT_NEAR(blossom[k], from_power[k], 1e-13) << "k=" << k << describe(x0, x1);
        EXPECT_NEAR(tang[k], from_power[k], 1e-13) << "k=" << k << describe(x0, x1);
      }
      // The end coefficients are the values at t = 0 and t = 1.
      EXPECT_NEAR(blossom[0], triple_product_at(kind, x0, x1, 0.0), 1e-14);
      EXPECT_NEAR(blossom[3], triple_product_at(kind, x0, x1, 1.0), 1e-14);
    }
}

// ------------------------------------------------------------------- non-penetration filter

TEST(NonpenetrationFilter, NeverCullsACaseWithARoot) {
  // 1e5 random stencils, small enough motions that many cross the plane. A sign change between
  // two dense samples of the directly evaluated triple product (each clearly nonzero) proves a
  // root; the filter must then not cull. Also the filter must cull a good share of the others,
  // so that this test can fail in both directions.
  std::mt19937 rng(303);
  int culled = 0, with_root = 0;
  const int n = 100000, samples = 32;
  for (int trial = 0; trial < n; ++trial) {
    const CcdPrimitive kind = KINDS[trial % 2];
    CcdStencil x0, x1;
    const bool flat = trial % 7 == 0;  // nearly coplanar start: the hard cases
    for (int k = 0; k < 4; ++k) {
      x0[k] = test::random_vec3(rng);
      if (flat) x0[k].z() *= 1e-9;
      x1[k] = x0[k] + test::random_vec3(rng, 0.3);
    }
    const bool culls = nonpenetration_filter_culls(kind, x0, x1);
    culled += culls;
    double prev = triple_product_at(kind, x0, x1, 0.0);
    bool root = false;
    for (int s = 1; s <= samples && !root; ++s) {
      const double cur = triple_product_at(kind, x0, x1, double(s) / samples);
      root = (prev > 1e-12 && cur < -1e-12) || (prev < -1e-12 && cur > 1e-12);
      prev = cur;
    }
    with_root += root;
    if (root) {
      ASSERT_FALSE(culls) << "trial " << trial << describe(x0, x1);
    }
  }
  EXPECT_GT(with_root, n / 20);
  EXPECT_GT(culled, n / 4);
}

TEST(NonpenetrationFilter, ToleranceKeepsNearMissesWithinTau) {
  // Vertex 1.5 tau above a static triangle, moving parallel to it: never coplanar, so the plain
  // filter culls it, and so does the filter with tolerance tau; with tolerance 2 tau it must not
  // (distance 1.5 tau < 2 tau).
  const double tau = 1e-3;
  const CcdStencil x0 = {Vec3(0.2, 0.2, 1.5 * tau), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  CcdStencil x1 = x0;
  x1[0] = Vec3(0.3, 0.2, 1.5 * tau);
  EXPECT_TRUE(nonpenetration_filter_culls(CcdPrimitive::VertexFace, x0, x1, 0.0));
  EXPECT_TRUE(nonpenetration_filter_culls(CcdPrimitive::VertexFace, x0, x1, tau));
  EXPECT_FALSE(nonpenetration_filter_culls(CcdPrimitive::VertexFace, x0, x1, 2.0 * tau));
}

TEST(NonpenetrationFilter, NeverCullsStencilsCoplanarAtTheStartWithEitherBound) {
  // The four points lie exactly on the plane x + y + z = 1 at t = 0 (coordinates in [0, 1) with
  // at most 27 fractional bits, so 1 - a - b and every difference are exact doubles), and the
  // vertex (VF) or the first edge (EE) moves off the plane: the exact cubic is f(t) = c t, so
  // b0 = 0 and the filter may not cull at tau = 0. The computed b0 is nonzero through the
  // rounding of the products for many of them, so a rounding bound smaller than that error
  // would cull. With the start lifted by 1e-6 along the normal the same motions are culled by
  // both bounds (the test can fail both ways).
  std::mt19937 rng(1717);
  std::uniform_int_distribution<int> grid(0, (1 << 26) - 1);
  std::uniform_real_distribution<double> lift(0.01, 0.2);
  auto on_plane = [&] {
    const double a = std::ldexp(grid(rng), -27), b = std::ldexp(grid(rng), -27);
    return Vec3(a, b, 1.0 - a - b);
  };
  const Vec3 normal = Vec3(1, 1, 1) / std::sqrt(3.0);
  int rounded = 0, culled_lifted = 0;
  const int n = 20000;
  for (int trial = 0; trial < n; ++trial) {
    const CcdPrimitive kind = KINDS[trial % 2];
    CcdStencil x0, x1;
    for (auto& p : x0) p = on_plane();
    x1 = x0;
    const Vec3 motion = lift(rng) * normal;
    x1[0] += motion;  // VF: the vertex; EE: both ends of edge a
    if (kind == CcdPrimitive::EdgeEdge) x1[1] += motion;
    rounded += coplanarity_bernstein(kind, x0, x1)[0] != 0.0;
    for (FilterBound bound : {FilterBound::Tight, FilterBound::Coarse})
      ASSERT_FALSE(nonpenetration_filter_culls(kind, x0, x1, 0.0, bound))
          << "trial " << trial << (bound == FilterBound::Tight ? " tight" : " coarse")
          << describe(x0, x1);
    CcdStencil y0 = x0, y1 = x1;
    const int moving = kind == CcdPrimitive::VertexFace ? 1 : 2;
    for (int k = 0; k < moving; ++k) {
      y0[k] += 1e-6 * normal;
      y1[k] += 1e-6 * normal;
    }
    culled_lifted += nonpenetration_filter_culls(kind, y0, y1, 0.0, FilterBound::Tight) &&
                     nonpenetration_filter_culls(kind, y0, y1, 0.0, FilterBound::Coarse);
  }
  EXPECT_GT(rounded, n / 10);
  EXPECT_GT(culled_lifted, n - n / 100);
  std::printf("  computed b0 nonzero in %d of %d; lifted: %d culled by both bounds\n", rounded, n,
              culled_lifted);
}

TEST(NonpenetrationFilter, CoarseBoundCullsOnlyWhatTheTightOneCulls) {
  // The coarse bound is never below the tight one (ccd.cpp, coarse_error_bound), so it may only
  // cull less. Stencils flattened to every scale from 1e-6 to 1e-17 put coefficients on both
  // sides of both bounds at tau = 0: the tight bound must cull some the coarse keeps (the test
  // reaches the region where they differ). The coarse bound ignores the flatness (its magnitude
  // is O(1) here where the tight one is O(flatness)), which costs nothing once tau is a
  // tolerance of the collision step's size (1e-4 of coordinates of size 1; on general stencils):
  // then both must cull the same stencils, up to one in a thousand.
  std::mt19937 rng(1818);
  std::uniform_real_distribution<double> flatness(-17.0, -6.0);
  int tight_only = 0, coarse = 0, with_tau = 0, coarse_with_tau = 0;
  const int n = 100000;
  for (int trial = 0; trial < n; ++trial) {
    const CcdPrimitive kind = KINDS[trial % 2];
    // Every third stencil is a general one (not flattened) with tau > 0.
    const bool with_tolerance = trial % 3 == 0;
    const double flat = with_tolerance ? 1.0 : std::pow(10.0, flatness(rng));
    CcdStencil x0, x1;
    for (int k = 0; k < 4; ++k) {
      x0[k] = test::random_vec3(rng);
      x1[k] = x0[k] + test::random_vec3(rng, 0.3);
      x0[k].z() *= flat;
      x1[k].z() *= flat;
    }
    const double tau = with_tolerance ? 1e-4 : 0.0;
    const bool by_tight = nonpenetration_filter_culls(kind, x0, x1, tau, FilterBound::Tight);
    const bool by_coarse = nonpenetration_filter_culls(kind, x0, x1, tau, FilterBound::Coarse);
    ASSERT_TRUE(by_tight || !by_coarse) << "trial " << trial << describe(x0, x1);
    tight_only += by_tight && !by_coarse;
    coarse += by_coarse;
    with_tau += tau > 0.0 && by_tight;
    coarse_with_tau += tau > 0.0 && by_coarse;
  }
  EXPECT_GT(tight_only, n / 100);
  EXPECT_GT(coarse, n / 4);
  EXPECT_GT(with_tau, n / 20);
  EXPECT_GE(coarse_with_tau, with_tau - with_tau / 1000);
  std::printf("  tight-only culls %d, coarse culls %d of %d; with tau: %d against %d\n",
              tight_only, coarse, n, coarse_with_tau, with_tau);
}

TEST(SweptBoxes, CullOnlyPairsFartherThanTauAtEverySampledTime) {
  // Random stencils with motions and tolerances of many sizes. A culled pair must be farther than
  // tau at every sampled time (the box gap bounds the distance from below); and the test must cull
  // a good share, so that it can fail in both directions.
  std::mt19937 rng(404);
  std::uniform_real_distribution<double> exponent(-4.0, 0.0);
  int culled = 0;
  const int n = 20000, samples = 16;
  for (int trial = 0; trial < n; ++trial) {
    const CcdPrimitive kind = KINDS[trial % 2];
    const double scale = std::pow(10.0, exponent(rng));
    const double tau = trial % 5 == 0 ? 0.0 : std::pow(10.0, exponent(rng)) * 0.5;
    CcdStencil x0, x1;
    const Vec3 shift = scale * test::random_vec3(rng, 2.0);
    for (int k = 0; k < 4; ++k) {
      x0[k] = scale * test::random_vec3(rng) + (k >= (kind == CcdPrimitive::VertexFace ? 1 : 2) ? shift : Vec3::Zero());
      x1[k] = x0[k] + scale * test::random_vec3(rng, 0.5);
    }
    const bool culls = swept_boxes_apart(kind, x0, x1, tau);
    culled += culls;
    if (!culls) continue;
    for (int s = 0; s <= samples; ++s)
      ASSERT_GT(distance_at(kind, x0, x1, double(s) / samples), tau) << "trial " << trial << describe(x0, x1);
  }
  EXPECT_GT(culled, n / 4);
  EXPECT_LT(culled, n - n / 10);
}

TEST(SweptBoxes, AGapOfExactlyTauIsKeptAndOneUlpMoreWithoutToleranceIsCulled) {
  // Static triangle in [0,1]^2 x {0}; the vertex moves along y at x = 1 + gap.
  const CcdStencil face = {Vec3::Zero(), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  auto stencils = [&](double x, CcdStencil& x0, CcdStencil& x1) {
    x0 = face;
    x1 = face;
    x0[0] = Vec3(x, 0.2, 0.0);
    x1[0] = Vec3(x, 0.4, 0.0);
  };
  CcdStencil x0, x1;
  const double tau = 0.25;  // 1 + tau is exact
  stencils(1.0 + tau, x0, x1);
  EXPECT_FALSE(swept_boxes_apart(CcdPrimitive::VertexFace, x0, x1, tau));  // distance exactly tau
  stencils(1.0 + tau + 1e-9, x0, x1);
  EXPECT_TRUE(swept_boxes_apart(CcdPrimitive::VertexFace, x0, x1, tau));
  stencils(1.0, x0, x1);
  EXPECT_FALSE(swept_boxes_apart(CcdPrimitive::VertexFace, x0, x1, 0.0));  // touching
  stencils(std::nextafter(1.0, 2.0), x0, x1);
  EXPECT_TRUE(swept_boxes_apart(CcdPrimitive::VertexFace, x0, x1, 0.0));
  // Edge-edge: the same gap on the z axis.
  const CcdStencil ee = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1.0 + tau), Vec3(0, 1, 1.0 + tau)};
  CcdStencil ee1 = ee;
  ee1[0].z() = ee1[1].z() = 1.0;  // edge a rises to z = 1 at t = 1: gap tau
  EXPECT_FALSE(swept_boxes_apart(CcdPrimitive::EdgeEdge, ee, ee1, tau));
  EXPECT_TRUE(swept_boxes_apart(CcdPrimitive::EdgeEdge, ee, ee1, 0.5 * tau));
}

TEST(SweptBoxes, NonFiniteInputIsNeverCulled) {
  CcdStencil x0 = {Vec3(5, 5, 5), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  CcdStencil x1 = x0;
  EXPECT_TRUE(swept_boxes_apart(CcdPrimitive::VertexFace, x0, x1, 0.0));
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    x1[0].z() = bad;
    EXPECT_FALSE(swept_boxes_apart(CcdPrimitive::VertexFace, x0, x1, 0.0));
    x1[0].z() = 5.0;
    x1[2].x() = bad;
    EXPECT_FALSE(swept_boxes_apart(CcdPrimitive::VertexFace, x0, x1, 0.0));
    x1[2].x() = 1.0;
  }
}

// ------------------------------------------------------------------- separating axes

/// A flat pair in the plane z = 0 (a rotated copy of it), moving in that plane: neighbours on a sheet,
/// which the non-penetration filter cannot cull (the points are close to coplanar all the time).
void flat_pair(std::mt19937& rng, CcdPrimitive kind, double scale, CcdStencil& x0, CcdStencil& x1) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Mat3 R = test::random_rotation(rng);
  const double angle = 3.14159 * u(rng), length = 0.5 + 0.4 * u(rng);
  const Vec3 shift(length * std::cos(angle), length * std::sin(angle), 0.0);
  for (int k = 0; k < 4; ++k) {
    const bool second = k >= (kind == CcdPrimitive::VertexFace ? 1 : 2);
    const Vec3 p(0.5 * u(rng), 0.5 * u(rng), 0.0);
    x0[k] = scale * R * (p + (second ? shift : Vec3::Zero()));
    x1[k] = x0[k] + scale * R * Vec3(0.3 * u(rng), 0.3 * u(rng), 0.0);
  }
}

TEST(SeparatingAxis, CullsOnlyPairsFartherThanTauThatTheIntervalSearchAlsoRejects) {
  // Flat neighbour pairs of many sizes and tolerances. A culled pair must be farther than tau at
  // every sampled time and be a miss for the interval search (ccd.hpp promises the same answer);
  // the test must cull many pairs that the box test and the filter keep, and keep some.
  std::mt19937 rng(808);
  std::uniform_real_distribution<double> exponent(-4.0, 0.0);
  int culled = 0, beyond_filter = 0, by_axes = 0, by_direction_only = 0;
  const int n = 20000, samples = 16;
  for (int trial = 0; trial < n; ++trial) {
    const CcdPrimitive kind = KINDS[trial % 2];
    const double scale = std::pow(10.0, exponent(rng));
    const double tau = trial % 5 == 0 ? 0.0 : scale * std::pow(10.0, exponent(rng)) * 0.2;
    CcdStencil x0, x1;
    flat_pair(rng, kind, scale, x0, x1);
    const bool culls = separating_axis_culls(kind, x0, x1, tau);
    // Its two halves (the collision step runs the axes in its filter stage, the direction in
    // the narrow phase): it culls iff one of them does.
    const bool axes = separating_axes_culls(kind, x0, x1, tau);
    const bool direction = separating_direction_culls(kind, x0, x1, tau);
    ASSERT_EQ(culls, axes || direction) << "trial " << trial << describe(x0, x1);
    by_axes += axes;
    by_direction_only += direction && !axes;
    if (!culls) continue;
    ++culled;
    beyond_filter += !swept_boxes_apart(kind, x0, x1, tau) &&
                     !nonpenetration_filter_culls(kind, x0, x1, tau);
    for (int s = 0; s <= samples; ++s)
      ASSERT_GT(distance_at(kind, x0, x1, double(s) / samples), tau)
          << "trial " << trial << describe(x0, x1);
    CcdOptions o;
    o.tolerance = tau;
    ASSERT_FALSE(primitive_ccd(kind, x0, x1, o).hit) << "trial " << trial << describe(x0, x1);
  }
  EXPECT_GT(culled, n / 4);
  EXPECT_LT(culled, n - n / 10);
  EXPECT_GT(beyond_filter, n / 10);
  std::printf("  culled %d of %d, %d of them kept by the box test and the filter\n", culled, n,
              beyond_filter);
  EXPECT_GT(by_axes, n / 4);
  EXPECT_GT(by_direction_only, n / 40);
  std::printf("  by the axes %d, by the direction alone %d\n", by_axes, by_direction_only);
}

TEST(SeparatingAxis, CoplanarForTheWholeStep) {
  // Everything in the plane z = 0 for the whole step: the filter sees f == 0 and cannot cull.
  const CcdStencil face = {Vec3::Zero(), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  CcdStencil x0 = face, x1 = face;
  // The vertex slides along the hypotenuse's outside at distance 0.1: culled up to tau < 0.1.
  const Vec3 out = Vec3(1, 1, 0).normalized() * 0.1;
  x0[0] = Vec3(0.8, 0.2, 0) + out;
  x1[0] = Vec3(0.2, 0.8, 0) + out;
  EXPECT_FALSE(nonpenetration_filter_culls(CcdPrimitive::VertexFace, x0, x1, 0.0));
  EXPECT_TRUE(separating_axis_culls(CcdPrimitive::VertexFace, x0, x1, 0.0));
  EXPECT_TRUE(separating_axis_culls(CcdPrimitive::VertexFace, x0, x1, 0.09));
  EXPECT_FALSE(separating_axis_culls(CcdPrimitive::VertexFace, x0, x1, 0.11));
  // The vertex crosses into the triangle in its plane: a real contact, never culled.
  x1[0] = Vec3(0.2, 0.2, 0);
  EXPECT_FALSE(separating_axis_culls(CcdPrimitive::VertexFace, x0, x1, 0.0));
  // Coplanar edges: parallel at distance 0.5, then crossing.
  const CcdStencil e0 = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0.5, 0), Vec3(1, 0.5, 0)};
  EXPECT_TRUE(separating_axis_culls(CcdPrimitive::EdgeEdge, e0, e0, 0.4));
  EXPECT_FALSE(separating_axis_culls(CcdPrimitive::EdgeEdge, e0, e0, 0.6));
  CcdStencil e1 = e0;
  e1[2] = Vec3(0.5, -0.5, 0);
  EXPECT_FALSE(separating_axis_culls(CcdPrimitive::EdgeEdge, e0, e1, 0.0));
}

TEST(SeparatingAxis, TouchingZeroMotionAndTheToleranceBoundary) {
  // Static vertex above the triangle's interior at height h: distance h the whole step.
  const CcdStencil face = {Vec3(0.25, 0.25, 0.5), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  EXPECT_TRUE(separating_axis_culls(CcdPrimitive::VertexFace, face, face, 0.0));
  EXPECT_TRUE(separating_axis_culls(CcdPrimitive::VertexFace, face, face, 0.49));
  EXPECT_FALSE(separating_axis_culls(CcdPrimitive::VertexFace, face, face, 0.5));  // exactly tau
  // Touching at t = 0 or at t = 1 is never culled.
  CcdStencil x1 = face;
  x1[0].z() = 0.0;
  EXPECT_FALSE(separating_axis_culls(CcdPrimitive::VertexFace, face, x1, 0.0));
  EXPECT_FALSE(separating_axis_culls(CcdPrimitive::VertexFace, x1, face, 0.0));
  // A degenerate (zero-area) triangle and zero-length edges at distance 1 are still culled.
  const CcdStencil sliver = {Vec3(0, 0, 1), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  EXPECT_TRUE(separating_axis_culls(CcdPrimitive::VertexFace, sliver, sliver, 0.5));
  const CcdStencil points = {Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 1, 0)};
  EXPECT_TRUE(separating_axis_culls(CcdPrimitive::EdgeEdge, points, points, 0.5));
  EXPECT_FALSE(separating_axis_culls(CcdPrimitive::EdgeEdge, points, points, 1.0));
}

TEST(SeparatingAxis, NonFiniteInputIsNeverCulled) {
  CcdStencil x0 = {Vec3(5, 5, 5), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  CcdStencil x1 = x0;
  ASSERT_TRUE(separating_axis_culls(CcdPrimitive::VertexFace, x0, x1, 0.0));
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    x1[3].y() = bad;
    EXPECT_FALSE(separating_axis_culls(CcdPrimitive::VertexFace, x0, x1, 0.0));
    EXPECT_FALSE(separating_axes_culls(CcdPrimitive::VertexFace, x0, x1, 0.0));
    EXPECT_FALSE(separating_direction_culls(CcdPrimitive::VertexFace, x0, x1, 0.0));
    x1[3].y() = 1.0;
  }
}

}  // namespace
}  // namespace shellcontract
