// Point-triangle and segment-segment closest points (math-spec 10.6): every Voronoi region with a
// hand-computed answer, degenerate primitives, parallel edges, and a brute-force comparison.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "collision/distance.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

constexpr double TOL = 1e-14;

std::string str(const Vec3& v) {
  return "(" + std::to_string(v.x()) + ", " + std::to_string(v.y()) + ", " + std::to_string(v.z()) + ")";
}

struct PtCase {
  const char* region;
  Vec3 p;
  Vec3 alpha;     // expected barycentric weights
  double distance;
};

TEST(PointTriangle, EveryRegionKnownAnswer) {
  // Right triangle in z = 0; the expected closest points are worked out by hand.
  const Vec3 f0(0, 0, 0), f1(1, 0, 0), f2(0, 1, 0);
  const PtCase cases[] = {
      {"face, above", Vec3(0.25, 0.25, 2.0), Vec3(0.5, 0.25, 0.25), 2.0},
      {"face, below", Vec3(0.2, 0.3, -0.5), Vec3(0.5, 0.2, 0.3), 0.5},
      {"vertex f0", Vec3(-1, -1, 0), Vec3(1, 0, 0), std::sqrt(2.0)},
      {"vertex f1", Vec3(2, -1, 1), Vec3(0, 1, 0), std::sqrt(3.0)},
      {"vertex f2", Vec3(-0.5, 2, 0), Vec3(0, 0, 1), std::sqrt(1.25)},
      {"edge f0-f1", Vec3(0.5, -1, 3), Vec3(0.5, 0.5, 0), std::sqrt(10.0)},
      {"edge f0-f2", Vec3(-1, 0.25, 0), Vec3(0.75, 0, 0.25), 1.0},
      {"edge f1-f2", Vec3(1, 1, 0), Vec3(0, 0.5, 0.5), std::sqrt(0.5)},
      {"on the triangle", Vec3(0.1, 0.1, 0), Vec3(0.8, 0.1, 0.1), 0.0},
  };
  for (const PtCase& c : cases) {
    const PointTriangleClosest r = point_triangle_closest(c.p, f0, f1, f2);
    EXPECT_NEAR(r.distance, c.distance, TOL) << c.region << " p=" << str(c.p);
    EXPECT_LT((r.alpha - c.alpha).norm(), TOL) << c.region << " alpha=" << str(r.alpha);
    EXPECT_LT((r.closest - (c.alpha[0] * f0 + c.alpha[1] * f1 + c.alpha[2] * f2)).norm(), TOL)
        << c.region;
    EXPECT_NEAR(point_triangle_distance(c.p, f0, f1, f2), c.distance, TOL) << c.region;
  }
}

TEST(PointTriangle, DegenerateTriangles) {
  // Collinear triangle: the closest point is on the segment (0,0,0)-(2,0,0).
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);
  PointTriangleClosest r = point_triangle_closest(Vec3(1.5, 1, 0), a, b, c);
  EXPECT_NEAR(r.distance, 1.0, TOL);
  EXPECT_LT((r.closest - Vec3(1.5, 0, 0)).norm(), TOL) << str(r.closest);
  EXPECT_NEAR(r.alpha.sum(), 1.0, TOL);
  EXPECT_GE(r.alpha.minCoeff(), 0.0);
  // Beyond the far end of the collinear triangle.
  r = point_triangle_closest(Vec3(3, 0, 0), a, b, c);
  EXPECT_NEAR(r.distance, 1.0, TOL);
  // Triangle collapsed to a point.
  r = point_triangle_closest(Vec3(1, 2, 2), a, a, a);
  EXPECT_NEAR(r.distance, 3.0, TOL);
  EXPECT_TRUE(std::isfinite(r.alpha.sum()));
}

TEST(PointTriangle, MatchesBruteForceOnRandomTriangles) {
  std::mt19937 rng(20240611);
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 p = test::random_vec3(rng, 2.0), f0 = test::random_vec3(rng), f1 = test::random_vec3(rng),
               f2 = test::random_vec3(rng);
    const PointTriangleClosest r = point_triangle_closest(p, f0, f1, f2);
    ASSERT_GE(r.alpha.minCoeff(), 0.0);
    ASSERT_NEAR(r.alpha.sum(), 1.0, 1e-12);
    // Brute force over a barycentric grid: no grid point may be closer than the answer, and the
    // answer must be within the grid spacing of the best grid point.
    const int n = 60;
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double a1 = double(i) / n, a2 = double(j) / n;
        best = std::min(best, (p - ((1 - a1 - a2) * f0 + a1 * f1 + a2 * f2)).norm());
      }
    const double h = ((f1 - f0).norm() + (f2 - f0).norm() + (f2 - f1).norm()) / n;
    EXPECT_LE(r.distance, best + 1e-12) << "trial " << trial;
    EXPECT_GE(r.distance, best - h) << "trial " << trial;
  }
}

TEST(SegmentSegment, KnownAnswers) {
  // Skew crossing segments one unit apart: closest at both midpoints.
  SegmentSegmentClosest r =
      segment_segment_closest(Vec3(-1, 0, 1), Vec3(1, 0, 1), Vec3(0, -1, 0), Vec3(0, 1, 0));
  EXPECT_NEAR(r.distance, 1.0, TOL);
  EXPECT_NEAR(r.s, 0.5, TOL);
  EXPECT_NEAR(r.r, 0.5, TOL);
  EXPECT_FALSE(r.parallel);
  // Clamped on both: the lines cross at (3, 0, 0) beyond both segments' ends.
  r = segment_segment_closest(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(3, 1, 0), Vec3(3, 2, 0));
  EXPECT_NEAR(r.s, 1.0, TOL);
  EXPECT_NEAR(r.r, 0.0, TOL);
  EXPECT_NEAR(r.distance, std::sqrt(5.0), TOL);
  // Intersecting segments: distance exactly 0 at s = 1/4, r = 1/2.
  r = segment_segment_closest(Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(1, -1, 0), Vec3(1, 1, 0));
  EXPECT_EQ(r.distance, 0.0);
  EXPECT_NEAR(r.s, 0.25, TOL);
  EXPECT_NEAR(r.r, 0.5, TOL);
}

TEST(SegmentSegment, ParallelEdges) {
  // Overlapping parallel segments 0.5 apart: every overlapping pair is closest.
  SegmentSegmentClosest r =
      segment_segment_closest(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 0.5, 0), Vec3(3, 0.5, 0));
  EXPECT_TRUE(r.parallel);
  EXPECT_NEAR(r.distance, 0.5, TOL);
  EXPECT_NEAR((r.closest_a - r.closest_b).norm(), 0.5, TOL);
  // Collinear, disjoint, opposite directions: gap of 1 between x = 2 and x = 3.
  r = segment_segment_closest(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(5, 0, 0), Vec3(3, 0, 0));
  EXPECT_TRUE(r.parallel);
  EXPECT_NEAR(r.distance, 1.0, TOL);
  EXPECT_NEAR(r.s, 1.0, TOL);
  EXPECT_NEAR(r.r, 1.0, TOL);
  // Nearly parallel (angle 1e-7, below the 1e-6 threshold) still gives the right distance.
  r = segment_segment_closest(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 1e-7), Vec3(1, 1, 0));
  EXPECT_TRUE(r.parallel);
  EXPECT_NEAR(r.distance, 1.0, 1e-12);
}

TEST(SegmentSegment, DegenerateSegments) {
  // Both points.
  SegmentSegmentClosest r =
      segment_segment_closest(Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 3), Vec3(1, 1, 3));
  EXPECT_NEAR(r.distance, 2.0, TOL);
  // One point against a segment, projecting inside.
  r = segment_segment_closest(Vec3(0.5, 1, 0), Vec3(0.5, 1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0));
  EXPECT_NEAR(r.distance, 1.0, TOL);
  EXPECT_NEAR(r.r, 0.5, TOL);
  r = segment_segment_closest(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 1, 0), Vec3(2, 1, 0));
  EXPECT_NEAR(r.distance, std::sqrt(2.0), TOL);
  EXPECT_NEAR(r.s, 1.0, TOL);
}

TEST(SegmentSegment, MatchesBruteForceOnRandomSegments) {
  std::mt19937 rng(77);
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 a0 = test::random_vec3(rng), a1 = test::random_vec3(rng), b0 = test::random_vec3(rng),
               b1 = test::random_vec3(rng);
    const SegmentSegmentClosest r = segment_segment_closest(a0, a1, b0, b1);
    ASSERT_GE(r.s, 0.0);
    ASSERT_LE(r.s, 1.0);
    ASSERT_GE(r.r, 0.0);
    ASSERT_LE(r.r, 1.0);
    const int n = 200;
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j)
        best = std::min(best, ((a0 + (a1 - a0) * (double(i) / n)) - (b0 + (b1 - b0) * (double(j) / n))).norm());
    const double h = ((a1 - a0).norm() + (b1 - b0).norm()) / n;
    EXPECT_LE(r.distance, best + 1e-12) << "trial " << trial;
    EXPECT_GE(r.distance, best - h) << "trial " << trial;
    EXPECT_NEAR(segment_segment_distance(a0, a1, b0, b1), r.distance, 0.0);
  }
}

}  // namespace
}  // namespace shellcontract
