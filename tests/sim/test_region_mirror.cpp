// The mirrored dimple (sim/region_mirror.hpp, docs/math/region-mirror.md): the reflection is an
// isometry, the similarity fit recovers a known transform, a cap with a flat rim mirrors into a
// dent of the same volume and edge lengths wherever its rim has gone, and the degenerate regions
// fall back to the volume projection with a named reason.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <set>
#include <utility>

#include "sim/region_mirror.hpp"
#include "support/flat_rim_cap.hpp"
#include "support/icosphere_cap.hpp"

namespace shellcontract {
namespace {

using test::FlatRimCap;
using test::flat_rim_cap;

/// The undirected edges of some faces.
std::set<std::pair<int, int>> edges_of(const Faces& f) {
  std::set<std::pair<int, int>> e;
  for (Eigen::Index j = 0; j < f.rows(); ++j)
    for (int k = 0; k < 3; ++k) {
      const int a = f(j, k), b = f(j, (k + 1) % 3);
      e.insert({std::min(a, b), std::max(a, b)});
    }
  return e;
}

Similarity known_similarity() {
  Similarity s;
  s.rotation = Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
  s.scale = 1.7;
  s.translation = Vec3(0.3, -2.0, 5.0);
  return s;
}

TEST(RegionMirror, ReflectionKeepsEveryEdgeLengthAndFlipsTheCapVolume) {
  // An invariant of any plane: on a perturbed icosphere cap, every edge keeps its length, a second
  // reflection gives the point back, and the cap's volume (fan from the rim's centroid, which the
  // reflection carries along) changes sign: a bump becomes a dent of the same size.
  // Fails with a reflection that does not double the normal component (p - (p.n) n: a projection).
  const test::CapScene s = test::icosphere_cap(3, 0.3, 0.02, 5);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 4; ++trial) {
    MirrorPlane plane;
    plane.point = Vec3(u(rng), u(rng), u(rng));
    plane.normal = Vec3(u(rng), u(rng), u(rng)).normalized();
    Positions y = s.m.x;
    for (Eigen::Index i = 0; i < y.rows(); ++i) y.row(i) = reflect(s.m.x.row(i), plane).transpose();
    for (const auto& [a, b] : edges_of(s.m.faces))
      EXPECT_NEAR((y.row(a) - y.row(b)).norm(), (s.m.x.row(a) - s.m.x.row(b)).norm(), 1e-13);
    for (Eigen::Index i = 0; i < y.rows(); ++i)
      EXPECT_NEAR((reflect(y.row(i), plane) - Vec3(s.m.x.row(i))).norm(), 0.0, 1e-13);
    const RegionCap cap = make_region_cap(s.m.faces, s.region);
    EXPECT_NEAR(cap_volume(y, cap), -cap_volume(s.m.x, cap), 1e-13);
  }
}

TEST(RegionMirror, SimilarityFitRecoversAKnownRotationScaleAndTranslation) {
  // From points in general position and from a flat ring (a flat rim, where the cross-covariance
  // is of rank 2 and the SVD may return a reflection): the fit gives the transform back.
  // Fails without the determinant correction (the flat ring then comes back mirrored).
  const Similarity truth = known_similarity();
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> cloud, ring;
  for (int i = 0; i < 9; ++i) cloud.emplace_back(u(rng), u(rng), u(rng));
  for (int i = 0; i < 11; ++i) ring.emplace_back(std::cos(0.57 * i), std::sin(0.57 * i), 0.4);
  for (const std::vector<Vec3>* from : {&cloud, &ring}) {
    std::vector<Vec3> to;
    for (const Vec3& p : *from) to.push_back(truth(p));
    const std::optional<Similarity> fit = fit_similarity(*from, to);
    ASSERT_TRUE(fit.has_value());
    EXPECT_NEAR((fit->rotation - truth.rotation).norm(), 0.0, 1e-12);
    EXPECT_NEAR(fit->rotation.determinant(), 1.0, 1e-12);
    EXPECT_NEAR(fit->scale, truth.scale, 1e-12);
    EXPECT_NEAR((fit->translation - truth.translation).norm(), 0.0, 1e-11);
  }
}

TEST(RegionMirror, AFlatRimCapBecomesADentOfTheSameShapeCarriedByItsRim) {
  // The cap of a sphere with a flat rim, its rim moved by a known similarity: one full step (beta
  // 1) puts every interior vertex on the similarity's image of its reflection through the rest
  // rim's plane z = cos theta, so every edge is the rest edge times the scale, the rim stays, and
  // the cap volume is minus the rest one times scale^3. Fails with the plane through the origin
  // (the sphere's centre) instead of the rim's centroid, with the rest frame for the rim's, or
  // without the fit's determinant correction.
  const FlatRimCap c = flat_rim_cap();
  const RegionCap cap = make_region_cap(c.faces, c.region);
  const RegionMirror m = make_region_mirror(c.x, cap);
  ASSERT_EQ(m.fallback, MirrorFallback::None) << mirror_fallback_name(m.fallback);
  EXPECT_NEAR((m.plane.normal - Vec3::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_EQ(m.moved.size(), cap.vertices.size() - cap.rim.size());
  const Similarity frame = known_similarity();
  Positions x = c.x;
  for (Eigen::Index i = 0; i < x.rows(); ++i) x.row(i) = frame(c.x.row(i)).transpose();
  const Positions before = x;
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(x.rows());
  ASSERT_TRUE(apply_region_mirror(x, cap, m, w, {}, 1.0));
  for (int r : cap.rim) EXPECT_EQ(x.row(cap.vertices[r]), before.row(cap.vertices[r]));
  const double rim_z = c.x(cap.vertices[cap.rim.front()], 2);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    Vec3 mirrored = c.x.row(i);
    mirrored.z() = 2.0 * rim_z - mirrored.z();
    EXPECT_NEAR((Vec3(x.row(i)) - frame(mirrored)).norm(), 0.0, 1e-12) << "vertex " << i;
  }
  for (const auto& [a, b] : edges_of(c.faces))
    EXPECT_NEAR((x.row(a) - x.row(b)).norm(), frame.scale * (c.x.row(a) - c.x.row(b)).norm(),
                1e-12);
  const double rest_volume = cap_volume(c.x, cap);
  ASSERT_GT(rest_volume, 0.0);
  EXPECT_NEAR(cap_volume(x, cap), -std::pow(frame.scale, 3) * rest_volume, 1e-12);
}

TEST(RegionMirror, HalfAStepMovesHalfWayAndHeldVerticesStay) {
  const FlatRimCap c = flat_rim_cap();
  const RegionCap cap = make_region_cap(c.faces, c.region);
  const RegionMirror m = make_region_mirror(c.x, cap);
  Positions full = c.x, half = c.x;
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(c.x.rows());
  std::vector<char> held(static_cast<std::size_t>(c.x.rows()), 0);
  held[0] = 1;  // the apex
  ASSERT_TRUE(apply_region_mirror(full, cap, m, w, {}, 1.0));
  ASSERT_TRUE(apply_region_mirror(half, cap, m, w, held, 0.5));
  EXPECT_EQ(half.row(0), c.x.row(0));
  for (Eigen::Index i = 1; i < c.x.rows(); ++i)
    EXPECT_NEAR((half.row(i) - 0.5 * (c.x.row(i) + full.row(i))).norm(), 0.0, 1e-14);
}

TEST(RegionMirror, DegenerateRegionsFallBackWithANamedReason) {
  auto check = [&](const Positions& x, const Faces& faces, const std::vector<int>& region,
                   MirrorFallback expected) {
    const RegionCap cap = make_region_cap(faces, region);
    const RegionMirror m = make_region_mirror(x, cap);
    EXPECT_EQ(m.fallback, expected) << mirror_fallback_name(m.fallback);
    Positions y = x;
    EXPECT_FALSE(apply_region_mirror(y, cap, m, Eigen::VectorXd::Ones(x.rows()), {}, 1.0));
    EXPECT_EQ(y, x);  // nothing moved: the caller keeps the volume projection
  };
  // A single face: all three corners on the rim, nothing to mirror.
  Positions tri(3, 3);
  tri << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  Faces one(1, 3);
  one << 0, 1, 2;
  check(tri, one, {0}, MirrorFallback::NoInteriorVertex);
  // No face at all (or only ids outside the mesh): no rim.
  check(tri, one, {}, MirrorFallback::NoRim);
  check(tri, one, {7}, MirrorFallback::NoRim);
  // A fan over four rim points on the x axis (a cap squashed flat onto a line): no plane.
  Positions line(5, 3);
  line << 0, 0, 1, -1, 0, 0, -0.3, 0, 0, 1, 0, 0, 0.3, 0, 0;
  Faces fan(4, 3);
  fan << 0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1;
  check(line, fan, {0, 1, 2, 3}, MirrorFallback::CollinearRim);
  // An open tube (a band around z): two rims whose vector areas cancel, so no side to sink to.
  const int n = 4;
  Positions tube(2 * n, 3);
  Faces band(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const double p = 2.0 * M_PI * i / n;
    tube.row(i) << std::cos(p), std::sin(p), 0.0;
    tube.row(n + i) << std::cos(p), std::sin(p), 1.0;
    band.row(2 * i) << i, (i + 1) % n, n + (i + 1) % n;
    band.row(2 * i + 1) << i, n + (i + 1) % n, n + i;
  }
  check(tube, band, {0, 1, 2, 3, 4, 5, 6, 7}, MirrorFallback::NoArea);
}

TEST(RegionMirror, ARimCollapsedOntoALineGivesNoFrameAndMovesNothing) {
  // The rest cap is fine, but the current rim lies on a line: the rotation about it is not
  // determined, so the step is left to the volume projection.
  const FlatRimCap c = flat_rim_cap();
  const RegionCap cap = make_region_cap(c.faces, c.region);
  const RegionMirror m = make_region_mirror(c.x, cap);
  ASSERT_EQ(m.fallback, MirrorFallback::None);
  Positions x = c.x;
  for (int r : cap.rim) x(cap.vertices[r], 1) = x(cap.vertices[r], 2) = 0.0;
  const Positions before = x;
  EXPECT_FALSE(apply_region_mirror(x, cap, m, Eigen::VectorXd::Ones(x.rows()), {}, 1.0));
  EXPECT_EQ(x, before);
  std::vector<Vec3> from, to;
  for (int r : cap.rim)
    from.push_back(c.x.row(cap.vertices[r])), to.push_back(x.row(cap.vertices[r]));
  EXPECT_FALSE(fit_similarity(from, to).has_value());
  EXPECT_FALSE(fit_similarity(to, from).has_value());
  EXPECT_FALSE(fit_similarity({from[0], from[1]}, {to[0], to[1]}).has_value());
}

}  // namespace
}  // namespace shellcontract
