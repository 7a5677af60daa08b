// Batched membranes of the frame-based materials (corotated, linear, Mooney-Rivlin;
// src/pbd/membrane_batches.cpp): four membranes of one colour must give what project_membrane
// gives projecting them one after the other: bit for bit on the scalar path, to 1e-12 of the step
// on the AVX2 + FMA path, including the guarded cases (rest state, pinned vertices, a collinear
// and a point-collapsed triangle without a regular frame, an inverted one, the clamp, padding
// lanes) and both orientations s; and a nearly collinear triangle inside Mooney-Rivlin's |J|
// clamp, to the accuracy its conditioning allows.
// A wrong PK1 entry, frame axis or lift term moves the steps by far more than the tolerance
// (checked by dropping the p01 term of the linear PK1, and the t2 part of g1: each fails).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "pbd/constraint_batches.hpp"
#include "support/batch_scene.hpp"

namespace shellcontract {
namespace {

using test::context;
using test::expect_close_to_step;
using test::membrane_scene;
using test::MembraneScene;
using test::padded;

/// Scalar reference: project_membrane over the records in order, orientation s.
template <class M>
std::vector<double> scalar_membranes(const M& m, const MembraneScene& sc, double s,
                                     std::vector<double>* lambda) {
  std::vector<double> x = sc.x0;
  ProjectionContext ctx = context(x, sc.w);
  ctx.orientation = s;
  if (lambda) lambda->assign(sc.records.size(), 0.0);
  for (std::size_t i = 0; i < sc.records.size(); ++i)
    project_membrane(m, sc.records[i], ElementMaterialData{}, 1.0, ctx, lambda ? &(*lambda)[i] : nullptr);
  return x;
}

template <class M>
std::vector<double> batched_membranes(const M& m, const MembraneScene& sc, double s, BatchIsa isa,
                                      std::vector<double>* lambda) {
  const ColouredBatches<MembraneBatch> b = make_membrane_batches(sc.records, sc.colours);
  std::vector<double> x = sc.x0;
  std::vector<PaddedVertex> xw = padded(sc);
  ProjectionContext ctx = context(x, sc.w);
  ctx.orientation = s;
  std::vector<double> lam(BATCH_LANES * b.batches.size(), 0.0);
  double* l = lambda ? lam.data() : nullptr;
  if constexpr (std::is_same_v<M, Linear>)
    project_linear_membrane_batches(m, b.batches.data(), b.batches.size(), xw.data(), ctx, l, isa);
  else if constexpr (std::is_same_v<M, Corotated>)
    project_corotated_membrane_batches(m, b.batches.data(), b.batches.size(), xw.data(), ctx, l, isa);
  else
    project_mooney_rivlin_membrane_batches(m, b.batches.data(), b.batches.size(), xw.data(), ctx, l, isa);
  unpack_padded(xw.data(), 0, xw.size(), x.data());
  if (lambda) {  // back to constraint order: batch lanes of each colour in sequence
    lambda->clear();
    for (std::size_t j = 0; j < b.batches.size(); ++j)
      for (int k = 0; k < b.batches[j].count; ++k) lambda->push_back(lam[BATCH_LANES * j + k]);
  }
  return x;
}

template <class M>
void expect_batches_match(const M& m, const char* name) {
  std::mt19937 rng(58);
  for (int n : {9, 13, 16}) {  // 9 and 13: padding lanes in every colour's last batch
    const MembraneScene sc = membrane_scene(n, rng);
    for (double s : {1.0, -1.0})
      for (bool xpbd : {false, true}) {
        const std::string what = std::string(name) + " n " + std::to_string(n) + " s " +
                                 std::to_string(s) + (xpbd ? " xpbd" : " pbd");
        std::vector<double> lam_ref, lam_scalar, lam_auto;
        const std::vector<double> ref = scalar_membranes(m, sc, s, xpbd ? &lam_ref : nullptr);
        const std::vector<double> scalar =
            batched_membranes(m, sc, s, BatchIsa::Scalar, xpbd ? &lam_scalar : nullptr);
        EXPECT_EQ(scalar, ref) << what;
        EXPECT_EQ(lam_scalar, lam_ref) << what;
        const std::vector<double> fast =
            batched_membranes(m, sc, s, BatchIsa::Auto, xpbd ? &lam_auto : nullptr);
        expect_close_to_step(fast, ref, sc.x0, what.c_str());
        ASSERT_EQ(lam_auto.size(), lam_ref.size());
        for (std::size_t i = 0; i < lam_ref.size(); ++i)
          EXPECT_LE(std::abs(lam_auto[i] - lam_ref[i]), 1e-12 * std::abs(lam_ref[i]))
              << what << " lambda " << i;
        for (int i : {3, 4, 5})  // all pinned: exactly unchanged
          for (int d = 0; d < 3; ++d) EXPECT_EQ(fast[3 * i + d], sc.x0[3 * i + d]) << what << " vertex " << i;
      }
  }
}

TEST(FrameMembraneBatches, LinearMatchesTheScalarKernel) {
  RecordProperty("avx2", batch_avx2_available() ? 1 : 0);
  expect_batches_match(Linear(MaterialParams{1.3, 0.7}), "linear");
}

TEST(FrameMembraneBatches, CorotatedMatchesTheScalarKernel) {
  expect_batches_match(Corotated(MaterialParams{1.3, 0.7}), "corotated");
}

TEST(FrameMembraneBatches, MooneyRivlinMatchesTheScalarKernel) {
  MaterialParams p;
  p.c10 = 0.6;
  p.c01 = 0.2;  // both terms of the energy
  expect_batches_match(MooneyRivlin(p), "mooney-rivlin");
}

/// The frame-dependent materials skip a triangle without a regular frame; Mooney-Rivlin
/// projects the collinear one on its collapsed frame (the scalar lane fallback) and leaves the
/// point-collapsed one (no frame at all) alone.
TEST(FrameMembraneBatches, TrianglesWithoutARegularFrame) {
  std::mt19937 rng(59);
  MembraneScene sc = membrane_scene(8, rng);
  sc.records.resize(8);  // colour 0 only: each result comes from one projection
  sc.colours = {0, 8};
  auto moved = [&](const std::vector<double>& x, int i) {
    return std::hypot(x[3 * i] - sc.x0[3 * i], x[3 * i + 1] - sc.x0[3 * i + 1], x[3 * i + 2] - sc.x0[3 * i + 2]);
  };
  const std::vector<double> lin = batched_membranes(Linear(MaterialParams{}), sc, 1.0, BatchIsa::Auto, nullptr);
  const std::vector<double> cor = batched_membranes(Corotated(MaterialParams{}), sc, 1.0, BatchIsa::Auto, nullptr);
  const std::vector<double> mr = batched_membranes(MooneyRivlin(MaterialParams{}), sc, 1.0, BatchIsa::Auto, nullptr);
  for (int i : {9, 10, 11, 15, 16, 17}) {  // constraint 3 collinear, 5 collapsed to a point
    EXPECT_EQ(moved(lin, i), 0.0) << "linear vertex " << i;
    EXPECT_EQ(moved(cor, i), 0.0) << "corotated vertex " << i;
  }
  for (int i : {15, 16, 17}) EXPECT_EQ(moved(mr, i), 0.0) << "mooney-rivlin vertex " << i;
  EXPECT_GT(moved(mr, 11), 0.0) << "mooney-rivlin pushes the collinear triangle open";
}


/// A triangle 1e-9 from collinear (A / Abar about 1e-9: a regular frame, but inside
/// Mooney-Rivlin's clamp |J| < 1e-6, math-spec 11), in a colour of its own. Its normal
/// N = e1 x e2 is known only to eps |e1| |e2| / |N| = eps kappa relative, in the scalar kernel as
/// in the batched one (which fuses the cross product's multiply-adds), and the step inherits
/// that: the two must agree to a small multiple of eps kappa, not to 1e-12.
TEST(FrameMembraneBatches, MooneyRivlinInsideTheJClampToItsConditioning) {
  if (!batch_avx2_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  std::mt19937 rng(60);
  MembraneScene sc = membrane_scene(10, rng);
  sc.records = {sc.records[8]};  // vertices 24, 25, 26
  sc.colours = {0, 1};
  auto at = [&](int i) { return Vec3(sc.x0[3 * i], sc.x0[3 * i + 1], sc.x0[3 * i + 2]); };
  const Vec3 edge = at(25) - at(24);
  const Vec3 p = 0.5 * (at(24) + at(25)) + 1e-9 * edge.cross(Vec3(0.3, 0.5, 0.8)).normalized();
  for (int d = 0; d < 3; ++d) sc.x0[3 * 26 + d] = p(d);
  const Vec3 e1 = at(24) - at(26), e2 = at(25) - at(26);
  const double kappa = e1.norm() * e2.norm() / e1.cross(e2).norm();
  ASSERT_GT(kappa, 1e8);
  MaterialParams params;
  params.c10 = 0.6;
  params.c01 = 0.2;
  const MooneyRivlin m(params);
  const std::vector<double> ref = scalar_membranes(m, sc, 1.0, nullptr);
  const std::vector<double> fast = batched_membranes(m, sc, 1.0, BatchIsa::Auto, nullptr);
  const double eps = std::numeric_limits<double>::epsilon();
  for (int i = 24; i < 27; ++i) {
    const Vec3 ref_step = Vec3(ref[3 * i], ref[3 * i + 1], ref[3 * i + 2]) - at(i);
    const Vec3 diff = Vec3(fast[3 * i], fast[3 * i + 1], fast[3 * i + 2]) -
                      Vec3(ref[3 * i], ref[3 * i + 1], ref[3 * i + 2]);
    EXPECT_GT(ref_step.norm(), 0.0) << "vertex " << i << " must move";
    EXPECT_LE(diff.norm(), 64 * eps * kappa * ref_step.norm()) << "vertex " << i;
  }
}

}  // namespace
}  // namespace shellcontract
