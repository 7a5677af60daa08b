// Batched dihedral hinges (constraint_batches.hpp, dihedral_batches.cpp): four hinges of one
// colour must give what project_dihedral_hinge gives projecting them one after the other: bit for
// bit on the scalar path, to 1e-12 of the step on the AVX2 + FMA path, including the cases its
// guards skip (inactive hinge, every vertex pinned, a collapsed face), the step clamp, the angle
// wrapped across +-pi, and the padding lanes of a colour's last batch.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "bending/dihedral_bending.hpp"
#include "pbd/constraint_batches.hpp"
#include "support/batch_scene.hpp"

namespace shellcontract {
namespace {

using namespace test;  // NOLINT(google-build-using-namespace): the batch scenes' helpers

constexpr double PI = 3.14159265358979323846;

struct DihedralScene : Scene {
  std::vector<DihedralHingeConstraint> records;  ///< grouped by colour
};

DihedralHingeConstraint dihedral_on(const std::vector<Vec3>& rest, std::array<int, 4> v) {
  return {v, dihedral_bending_rest(rest[v[0]], rest[v[1]], rest[v[2]], rest[v[3]]), 1e9};
}

Vec3 point(const std::vector<double>& x, int i) {
  return Vec3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
}
Vec3 point(const Scene& s, int i) { return point(s.x0, i); }

/// How far vertex i moved from the scene's start.
double moved(const std::vector<double>& x, const Scene& s, int i) {
  return (point(x, i) - point(s, i)).norm();
}

/// Hinges (4k .. 4k+3) in colour 0, then (4k+1, 4(k+1)+2, 4(k+2)+3, 4(k+3)) in colour 1 (indices
/// mod 4n): no two of a colour share a vertex, colour 1 reads colour 0's results. The random rest
/// stencils are bent; the start state moves every vertex by up to 0.1. Colour 0 begins with the
/// special cases named below.
DihedralScene dihedral_scene(int n, std::mt19937& rng) {
  if (n < 6) throw std::invalid_argument("dihedral_scene: the special cases need n >= 6");
  DihedralScene s;
  const std::vector<Vec3> rest = random_rest_and_start(s, 4 * n, 1.0, 0.1, rng);
  for (int k = 0; k < n; ++k)
    s.records.push_back(dihedral_on(rest, {4 * k, 4 * k + 1, 4 * k + 2, 4 * k + 3}));
  s.w[0] = s.w[1] = s.w[2] = s.w[3] = 0.0;  // 0: all pinned (wg = 0): skipped
  s.w[5] = 0.0;                             // 1: one pinned vertex
  s.records[2].rest.kappa = 0.0;            // 2: inactive hinge: skipped
  s.records[3].max_step = 1e-4;             // 3: the clamp acts
  {  // 4: face (16, 17, 18) collapsed, |N| < 1e-12 |e|^2 but not 0 (math-spec 11): skipped
    const Vec3 near_mid = 0.5 * (point(s, 16) + point(s, 17)) + Vec3(0.0, 0.0, 1e-14);
    for (int d = 0; d < 3; ++d) s.x0[3 * 18 + d] = near_mid(d);
  }
  {  // 5: the angle's change crosses +-pi, so the difference is wrapped
    double theta = 0.0;
    if (!dihedral_angle(point(s, 20), point(s, 21), point(s, 22), point(s, 23), theta))
      throw std::logic_error("hinge 5 must not be collapsed");
    s.records[5].rest.rest_angle = theta >= 0.0 ? theta - PI - 0.3 : theta + PI + 0.3;
  }
  for (int k = 0; k < n; ++k)
    s.records.push_back(dihedral_on(
        rest, {4 * k + 1, 4 * ((k + 1) % n) + 2, 4 * ((k + 2) % n) + 3, 4 * ((k + 3) % n)}));
  s.colours = {0, static_cast<std::size_t>(n), static_cast<std::size_t>(2 * n)};
  return s;
}

/// Reference: project_dihedral_hinge over the records in order.
std::vector<double> scalar_dihedral(const DihedralScene& s, double kb,
                                    std::vector<double>* lambda) {
  std::vector<double> x = s.x0;
  const ProjectionContext ctx = context(x, s.w);
  if (lambda) lambda->assign(s.records.size(), 0.0);
  for (std::size_t i = 0; i < s.records.size(); ++i)
    project_dihedral_hinge(s.records[i], kb, ctx, lambda ? &(*lambda)[i] : nullptr);
  return x;
}

std::vector<double> batched_dihedral(const DihedralScene& s, double kb, BatchIsa isa,
                                     std::vector<double>* lambda) {
  const ColouredBatches<DihedralBatch> b = make_dihedral_batches(s.records, s.colours);
  std::vector<double> x = s.x0;
  std::vector<PaddedVertex> xw = padded(s);
  const ProjectionContext ctx = context(x, s.w);
  std::vector<double> lam(BATCH_LANES * b.batches.size(), 0.0);
  project_dihedral_hinge_batches(b.batches.data(), b.batches.size(), kb, xw.data(), ctx,
                                 lambda ? lam.data() : nullptr, isa);
  unpack_padded(xw.data(), 0, xw.size(), x.data());
  if (lambda) {
    lambda->clear();
    for (std::size_t j = 0; j < b.batches.size(); ++j)
      for (int k = 0; k < b.batches[j].count; ++k) lambda->push_back(lam[BATCH_LANES * j + k]);
  }
  return x;
}

TEST(DihedralBatches, MatchTheScalarKernelPbdAndXpbd) {
  std::mt19937 rng(36);
  for (int n : {7, 12, 15}) {  // 15: every colour ends in a batch with one padding lane
    const DihedralScene s = dihedral_scene(n, rng);
    for (double kb : {0.01, 1.0}) {
      for (bool xpbd : {false, true}) {
        std::vector<double> lam_ref, lam_scalar, lam_auto;
        const std::vector<double> ref = scalar_dihedral(s, kb, xpbd ? &lam_ref : nullptr);
        const std::vector<double> scalar =
            batched_dihedral(s, kb, BatchIsa::Scalar, xpbd ? &lam_scalar : nullptr);
        EXPECT_EQ(scalar, ref) << "n " << n << " k_B " << kb << (xpbd ? " xpbd" : " pbd");
        EXPECT_EQ(lam_scalar, lam_ref);
        const std::vector<double> fast =
            batched_dihedral(s, kb, BatchIsa::Auto, xpbd ? &lam_auto : nullptr);
        expect_close_to_step(fast, ref, s.x0, xpbd ? "xpbd" : "pbd");
        ASSERT_EQ(lam_auto.size(), lam_ref.size());
        for (std::size_t i = 0; i < lam_ref.size(); ++i)
          EXPECT_LE(std::abs(lam_auto[i] - lam_ref[i]), 1e-12 * std::abs(lam_ref[i]))
              << "lambda " << i;
      }
    }
  }
}

TEST(DihedralBatches, SkippedLanesAreUntouchedAndTheClampHolds) {
  std::mt19937 rng(37);
  DihedralScene s = dihedral_scene(6, rng);
  s.records.resize(6);
  s.colours = {0, 6};
  for (BatchIsa isa : {BatchIsa::Scalar, BatchIsa::Auto})
    for (bool xpbd : {false, true}) {
      // XPBD's compliance makes its steps smaller (alpha_tilde = 1e4): a tighter clamp.
      const double clamp = xpbd ? 1e-6 : 1e-4;
      s.records[3].max_step = clamp;
      std::vector<double> lambda;
      const std::vector<double> x = batched_dihedral(s, 1.0, isa, xpbd ? &lambda : nullptr);
      // All pinned, kappa = 0, the collapsed face's hinge.
      for (int i : {0, 1, 2, 3, 8, 9, 10, 11, 16, 17, 18, 19})
        for (int d = 0; d < 3; ++d) EXPECT_EQ(x[3 * i + d], s.x0[3 * i + d]) << "vertex " << i;
      EXPECT_EQ(moved(x, s, 5), 0.0) << "the pinned corner";
      for (int i : {4, 12, 20}) EXPECT_GT(moved(x, s, i), 0.0) << "vertex " << i;
      double longest = 0.0;
      for (int i = 12; i < 16; ++i) longest = std::max(longest, moved(x, s, i));
      EXPECT_NEAR(longest, clamp, 1e-15) << "hinge 3 is clamped to max_step";
      if (xpbd) {
        for (int k : {0, 2, 4}) EXPECT_EQ(lambda[k], 0.0) << "skipped hinge " << k;
        EXPECT_NE(lambda[1], 0.0);
      }
    }
}

TEST(DihedralBatches, WrappedAngleDifferenceTurnsTheShortWay) {
  // Hinge 5's rest angle is pi + 0.3 away from its start angle, so the wrapped difference is
  // pi - 0.3 the other way: the step must close that gap, not the long one.
  std::mt19937 rng(38);
  DihedralScene s = dihedral_scene(6, rng);
  s.records = {s.records[5]};
  s.colours = {0, 1};
  for (BatchIsa isa : {BatchIsa::Scalar, BatchIsa::Auto}) {
    const std::vector<double> x = batched_dihedral(s, 0.01, isa, nullptr);
    double before = 0.0, after = 0.0;
    ASSERT_TRUE(dihedral_angle(point(s, 20), point(s, 21), point(s, 22), point(s, 23), before));
    ASSERT_TRUE(dihedral_angle(point(x, 20), point(x, 21), point(x, 22), point(x, 23), after));
    const double rest = s.records[0].rest.rest_angle;
    EXPECT_LT(std::abs(wrapped_angle_difference(after, rest)),
              std::abs(wrapped_angle_difference(before, rest)));
    EXPECT_NEAR(std::abs(wrapped_angle_difference(before, rest)), PI - 0.3, 1e-12);
  }
}

TEST(DihedralBatches, LayoutPadsEachColoursLastBatchWithLaneZero) {
  std::mt19937 rng(39);
  DihedralScene s = dihedral_scene(6, rng);
  const ColouredBatches<DihedralBatch> b = make_dihedral_batches(s.records, s.colours);
  ASSERT_EQ(b.batches.size(), 4u);
  EXPECT_EQ(b.offsets, (std::vector<std::size_t>{0, 2, 4}));
  EXPECT_EQ(b.batches[0].count, 4);
  EXPECT_EQ(b.batches[1].count, 2);
  const DihedralBatch& last = b.batches[1];  // hinges 4 and 5, then two padding lanes
  // Padding lanes are copies of lane 0, rest data included (test_fp_exceptions.cpp).
  for (int k = 0; k < BATCH_LANES; ++k) {
    const DihedralHingeConstraint& r = s.records[k < 2 ? 4 + k : 4];
    for (int j = 0; j < 4; ++j) EXPECT_EQ(last.v[j][k], r.v[j]) << "lane " << k;
    EXPECT_EQ(last.kappa[k], r.rest.kappa) << "lane " << k;
    EXPECT_EQ(last.rest_angle[k], r.rest.rest_angle) << "lane " << k;
  }
  EXPECT_GT(last.kappa[1], 0.0);
  EXPECT_EQ(last.rest_angle[1], s.records[5].rest.rest_angle);
  EXPECT_EQ(b.batches[3].rest_angle[0], s.records[10].rest.rest_angle);
  EXPECT_EQ(b.batches[0].max_step[3], 1e-4);  // hinge 3's clamp
  EXPECT_EQ(b.batches[2].max_step[3], s.records[9].max_step);
  EXPECT_THROW(make_dihedral_batches(s.records, {0, 5}), std::invalid_argument);
}

}  // namespace
}  // namespace shellcontract
