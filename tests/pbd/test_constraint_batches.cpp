// Batched projections of the Coloured order (constraint_batches.hpp).
// A batch of four constraints of one colour must give what the scalar kernels give projecting
// them one after the other: bit for bit on the scalar path, to 1e-12 of the step on the AVX2 +
// FMA path (the only difference is fused multiply-adds), including the guarded cases of
// math-spec 9.1(d) and 11 (rest state, pinned vertices, collapsed and inverted triangles,
// stationary points, the step clamp) and the padding lanes of a colour's last batch.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "bending/isometric_bending.hpp"
#include "fem/triangle_element.hpp"
#include "material/corotated.hpp"
#include "material/registry.hpp"
#include "pbd/constraint_batches.hpp"
#include "support/batch_scene.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

using test::context;
using test::expect_close_to_step;
using test::membrane_scene;
using test::MembraneScene;
using test::padded;
using test::random_rest_and_start;
using test::Scene;

// ------------------------------------------------------------------ membranes

/// Scalar reference: project_membrane over the records in order.
std::vector<double> scalar_membranes(const Stvk& m, const MembraneScene& s, std::vector<double>* lambda) {
  std::vector<double> x = s.x0;
  const ProjectionContext ctx = context(x, s.w);
  if (lambda) lambda->assign(s.records.size(), 0.0);
  for (std::size_t i = 0; i < s.records.size(); ++i)
    project_membrane(m, s.records[i], ElementMaterialData{}, 1.0, ctx, lambda ? &(*lambda)[i] : nullptr);
  return x;
}

std::vector<double> batched_membranes(const Stvk& m, const MembraneScene& s, BatchIsa isa,
                                      std::vector<double>* lambda) {
  const ColouredBatches<MembraneBatch> b = make_membrane_batches(s.records, s.colours);
  std::vector<double> x = s.x0;
  std::vector<PaddedVertex> xw = padded(s);
  const ProjectionContext ctx = context(x, s.w);
  std::vector<double> lam(BATCH_LANES * b.batches.size(), 0.0);
  project_stvk_membrane_batches(m, b.batches.data(), b.batches.size(), xw.data(), ctx,
                                lambda ? lam.data() : nullptr, isa);
  unpack_padded(xw.data(), 0, xw.size(), x.data());
  if (lambda) {  // back to constraint order: batch lanes of each colour in sequence
    lambda->clear();
    for (const MembraneBatch& batch : b.batches)
      for (int k = 0; k < batch.count; ++k) lambda->push_back(lam[BATCH_LANES * (&batch - b.batches.data()) + k]);
  }
  return x;
}

TEST(MembraneBatches, MatchTheScalarKernelPbdAndXpbd) {
  RecordProperty("avx2", batch_avx2_available() ? 1 : 0);
  std::mt19937 rng(31);
  const Stvk m(MaterialParams{1.3, 0.7});
  for (int n : {9, 13, 16}) {  // 9 and 13: padding lanes in every colour's last batch
    const MembraneScene s = membrane_scene(n, rng);
    for (bool xpbd : {false, true}) {
      std::vector<double> lam_ref, lam_scalar, lam_auto;
      const std::vector<double> ref = scalar_membranes(m, s, xpbd ? &lam_ref : nullptr);
      // Scalar path: the same kernels lane by lane, bit for bit.
      const std::vector<double> scalar = batched_membranes(m, s, BatchIsa::Scalar, xpbd ? &lam_scalar : nullptr);
      EXPECT_EQ(scalar, ref) << "n " << n << (xpbd ? " xpbd" : " pbd");
      EXPECT_EQ(lam_scalar, lam_ref);
      const std::vector<double> fast = batched_membranes(m, s, BatchIsa::Auto, xpbd ? &lam_auto : nullptr);
      expect_close_to_step(fast, ref, s.x0, xpbd ? "xpbd" : "pbd");
      for (std::size_t i = 0; i < lam_ref.size(); ++i)
        EXPECT_LE(std::abs(lam_auto[i] - lam_ref[i]), 1e-12 * std::abs(lam_ref[i])) << "lambda " << i;
      // Guarded cases of colour 0 that colour 1 does not touch: exactly unchanged.
      for (int i : {3, 4, 5}) {  // all pinned
        for (int d = 0; d < 3; ++d) EXPECT_EQ(fast[3 * i + d], s.x0[3 * i + d]) << "pinned vertex " << i;
      }
    }
  }
}

// Also at mu = lambda = 1e90 (the options allow 1e100): a PBD projection does not depend on the
// stiffness's scale, so the same lanes clamp. A clamp test comparing E^2 m with (max_step G)^2
// overflowed to inf = inf there and let the clamped steps through.
class MembraneBatchesAtStiffness : public ::testing::TestWithParam<double> {};

TEST_P(MembraneBatchesAtStiffness, SkippedLanesAreUntouchedAndTheClampHolds) {
  std::mt19937 rng(32);
  const Stvk m(MaterialParams{GetParam(), GetParam()});
  MembraneScene s = membrane_scene(8, rng);
  s.records.resize(8);  // colour 0 only: every result comes from one projection
  s.colours = {0, 8};
  std::vector<double> x = batched_membranes(m, s, BatchIsa::Auto, nullptr);
  // Rest, all pinned, pinned corner, F = 0. The rest triangle's skip compares E with an absolute
  // floor, which rounding-level strains pass at mu = 1e90: checked at mu = 1 only.
  for (int i : {0, 1, 2, 3, 4, 5, 6, 15, 16, 17})
    if (i > 2 || GetParam() == 1.0) {
      for (int d = 0; d < 3; ++d) EXPECT_EQ(x[3 * i + d], s.x0[3 * i + d]) << "vertex " << i;
    }
  for (int i = 18; i < 24; ++i) {  // constraints 6 and 7: clamped to max_step = 1e-3
    const double step = std::hypot(x[3 * i] - s.x0[3 * i], x[3 * i + 1] - s.x0[3 * i + 1],
                                   x[3 * i + 2] - s.x0[3 * i + 2]);
    EXPECT_LE(step, 1e-3 * (1 + 1e-12)) << "vertex " << i;
  }
  double longest = 0.0;
  for (int i = 18; i < 24; ++i)
    longest = std::max(longest, std::hypot(x[3 * i] - s.x0[3 * i], x[3 * i + 1] - s.x0[3 * i + 1],
                                           x[3 * i + 2] - s.x0[3 * i + 2]));
  EXPECT_NEAR(longest, 1e-3, 1e-15) << "the clamp must bind on the clamped constraints";
}
INSTANTIATE_TEST_SUITE_P(MembraneBatches, MembraneBatchesAtStiffness, ::testing::Values(1.0, 1e90));

TEST(PaddedVertices, PackAndUnpackRoundTripAndRowsAre32ByteAligned) {
  const std::vector<double> x{1, 2, 3, 4, 5, 6, 7, 8, 9}, w{0.5, 0.0, 2.0};
  std::vector<PaddedVertex> xw(3);
  pack_padded(x.data(), w.data(), 0, 3, xw.data());
  EXPECT_EQ(xw[1].x, 4.0);
  EXPECT_EQ(xw[1].z, 6.0);
  EXPECT_EQ(xw[2].w, 2.0);
  EXPECT_EQ(sizeof(PaddedVertex), 32u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(xw.data()) % 32, 0u) << "aligned 256-bit loads need it";
  std::vector<double> back(9, 0.0);
  unpack_padded(xw.data(), 1, 3, back.data());  // a sub-range: vertex 0 untouched
  EXPECT_EQ(back, (std::vector<double>{0, 0, 0, 4, 5, 6, 7, 8, 9}));
}

TEST(PaddedVertices, PermutedPackAndUnpackMapRowsToVertices) {
  // Row k holds vertex row_vertex[k] (the solver's breadth-first rows).
  const std::vector<double> x{1, 2, 3, 4, 5, 6, 7, 8, 9}, w{0.5, 0.0, 2.0};
  const std::vector<int> row_vertex{2, 0, 1};
  std::vector<PaddedVertex> xw(3);
  pack_padded(x.data(), w.data(), row_vertex.data(), 0, 3, xw.data());
  EXPECT_EQ(xw[0].x, 7.0);
  EXPECT_EQ(xw[0].w, 2.0);
  EXPECT_EQ(xw[1].y, 2.0);
  EXPECT_EQ(xw[2].z, 6.0);
  EXPECT_EQ(xw[2].w, 0.0);
  std::vector<double> back(9, 0.0);
  unpack_padded(xw.data(), row_vertex.data(), 1, 3, back.data());  // rows 1, 2: vertices 0, 1
  EXPECT_EQ(back, (std::vector<double>{1, 2, 3, 4, 5, 6, 0, 0, 0}));
}

TEST(MembraneBatches, LayoutPadsEachColoursLastBatchWithLaneZero) {
  std::mt19937 rng(33);
  MembraneScene s = membrane_scene(10, rng);
  s.records.resize(10);
  const ColouredBatches<MembraneBatch> b = make_membrane_batches(s.records, {0, 5, 9, 10});
  ASSERT_EQ(b.num_colours(), 3);
  EXPECT_EQ(b.offsets, (std::vector<std::size_t>{0, 2, 3, 4}));
  ASSERT_EQ(b.batches.size(), 4u);
  EXPECT_EQ(b.batches[0].count, 4);
  EXPECT_EQ(b.batches[1].count, 1);
  EXPECT_EQ(b.batches[2].count, 4);
  EXPECT_EQ(b.batches[3].count, 1);
  const MembraneBatch& last = b.batches[1];  // record 4, then padding
  // Padding lanes are copies of lane 0, rest data included (zero rest data divided 0 by 0:
  // test_fp_exceptions.cpp).
  for (int k = 0; k < BATCH_LANES; ++k) {
    for (int j = 0; j < 3; ++j) EXPECT_EQ(last.v[j][k], s.records[4].v[j]);
    EXPECT_EQ(last.rest_area[k], s.records[4].rest_area);
    EXPECT_EQ(last.dm00[k], s.records[4].dm00);
  }
  EXPECT_EQ(b.batches[2].dm01[3], s.records[8].dm01);
  EXPECT_THROW(make_membrane_batches(s.records, {0, 5}), std::invalid_argument);
  EXPECT_THROW(make_membrane_batches(s.records, {0, 6, 5, 10}), std::invalid_argument);
}

// ------------------------------------------------------------------ isometric hinges

struct HingeScene : Scene {
  std::vector<IsometricHingeConstraint> records;
};

IsometricHingeConstraint hinge_on(const std::vector<Vec3>& rest, std::array<int, 4> v) {
  const IsometricBendingRest r =
      isometric_bending_rest(rest[v[0]], rest[v[1]], rest[v[2]], rest[v[3]]);
  return {v, r.K, 3.0 / r.area_sum, 1e9};
}

/// Hinges (4k .. 4k+3) in colour 0, then (4k+1, 4(k+1)+2, 4(k+2)+3, 4(k+3)) in colour 1. The
/// rest stencils are random (curved, so flat-rest bending has work everywhere).
HingeScene hinge_scene(int n, std::mt19937& rng) {
  HingeScene s;
  const std::vector<Vec3> rest = random_rest_and_start(s, 4 * n, 1.0, 0.1, rng);
  for (int k = 0; k < n; ++k) s.records.push_back(hinge_on(rest, {4 * k, 4 * k + 1, 4 * k + 2, 4 * k + 3}));
  s.w[0] = s.w[1] = s.w[2] = s.w[3] = 0.0;  // 0: all pinned: skipped
  s.w[5] = 0.0;                             // 1: one pinned vertex
  s.records[2].K.setZero();                 // 2: inactive hinge (K = 0): skipped
  s.records[3].max_step = 1e-4;             // 3: the clamp acts
  for (int k = 0; k < n; ++k)
    s.records.push_back(hinge_on(rest, {4 * k + 1, 4 * ((k + 1) % n) + 2, 4 * ((k + 2) % n) + 3, 4 * ((k + 3) % n)}));
  s.colours = {0, static_cast<std::size_t>(n), static_cast<std::size_t>(2 * n)};
  return s;
}

std::vector<double> scalar_hinges(const HingeScene& s, double kb, std::vector<double>* lambda) {
  std::vector<double> x = s.x0;
  const ProjectionContext ctx = context(x, s.w);
  if (lambda) lambda->assign(3 * s.records.size(), 0.0);
  for (std::size_t i = 0; i < s.records.size(); ++i)
    project_isometric_hinge(s.records[i], kb, ctx, lambda ? &(*lambda)[3 * i] : nullptr);
  return x;
}

std::vector<double> batched_hinges(const HingeScene& s, double kb, BatchIsa isa, std::vector<double>* lambda) {
  const ColouredBatches<IsometricBatch> b = make_isometric_batches(s.records, s.colours);
  std::vector<double> x = s.x0;
  std::vector<PaddedVertex> xw = padded(s);
  const ProjectionContext ctx = context(x, s.w);
  std::vector<double> lam(3 * BATCH_LANES * b.batches.size(), 0.0);
  project_isometric_hinge_batches(b.batches.data(), b.batches.size(), kb, xw.data(), ctx,
                                  lambda ? lam.data() : nullptr, isa);
  unpack_padded(xw.data(), 0, xw.size(), x.data());
  if (lambda) {
    lambda->clear();
    for (std::size_t j = 0; j < b.batches.size(); ++j)
      for (int k = 0; k < b.batches[j].count; ++k)
        for (int d = 0; d < 3; ++d) lambda->push_back(lam[3 * (BATCH_LANES * j + k) + d]);
  }
  return x;
}

TEST(IsometricBatches, MatchTheScalarKernelPbdAndXpbd) {
  std::mt19937 rng(34);
  for (int n : {7, 12, 15}) {
    const HingeScene s = hinge_scene(n, rng);
    for (double kb : {0.01, 1.0}) {
      for (bool xpbd : {false, true}) {
        std::vector<double> lam_ref, lam_scalar, lam_auto;
        const std::vector<double> ref = scalar_hinges(s, kb, xpbd ? &lam_ref : nullptr);
        const std::vector<double> scalar = batched_hinges(s, kb, BatchIsa::Scalar, xpbd ? &lam_scalar : nullptr);
        EXPECT_EQ(scalar, ref) << "n " << n << " k_B " << kb << (xpbd ? " xpbd" : " pbd");
        EXPECT_EQ(lam_scalar, lam_ref);
        const std::vector<double> fast = batched_hinges(s, kb, BatchIsa::Auto, xpbd ? &lam_auto : nullptr);
        expect_close_to_step(fast, ref, s.x0, xpbd ? "xpbd" : "pbd");
        for (std::size_t i = 0; i < lam_ref.size(); ++i)
          EXPECT_LE(std::abs(lam_auto[i] - lam_ref[i]), 1e-12 * std::abs(lam_ref[i])) << "lambda " << i;
      }
    }
  }
}

TEST(IsometricBatches, SkippedLanesAreUntouchedAndTheClampHolds) {
  std::mt19937 rng(35);
  HingeScene s = hinge_scene(6, rng);
  s.records.resize(6);
  s.colours = {0, 6};
  const std::vector<double> x = batched_hinges(s, 1.0, BatchIsa::Auto, nullptr);
  for (int i : {0, 1, 2, 3, 5, 8, 9, 10, 11})  // all pinned, the pinned corner, K = 0
    for (int d = 0; d < 3; ++d) EXPECT_EQ(x[3 * i + d], s.x0[3 * i + d]) << "vertex " << i;
  double longest = 0.0;
  for (int i = 12; i < 16; ++i)
    longest = std::max(longest, std::hypot(x[3 * i] - s.x0[3 * i], x[3 * i + 1] - s.x0[3 * i + 1],
                                           x[3 * i + 2] - s.x0[3 * i + 2]));
  EXPECT_NEAR(longest, 1e-4, 1e-15) << "hinge 3 is clamped to max_step";
}

TEST(BatchedKernels, EveryRegisteredMaterialAndFibreEnergyHasOne) {
  // The coloured order's fast path is chosen by the material trait, not by a type test: a
  // material without a BatchedMembraneProjection specialization builds and runs, but on the
  // per-constraint kernels and without the regional order (pbd/solver.cpp). No option may fall
  // off the fast path (docs/design/batched-kernels.md), so every registered model needs one;
  // the registry is walked, not listed, so a new material is held to it without editing this.
  const MaterialParams params;
  for (const std::string& name : material_names()) {
    const bool batched = with_material(parse_material_kind(name), params, [](const auto& m) {
      return BatchedMembraneProjection<std::decay_t<decltype(m)>>::value;
    });
    EXPECT_TRUE(batched) << "membrane material '" << name
                         << "' has no BatchedMembraneProjection (src/pbd/constraint_batches.hpp)";
  }
  for (const std::string& name : aniso_names()) {
    const AnisoKind kind = parse_aniso_kind(name);
    if (kind == AnisoKind::None) continue;  // no E_A constraints are built
    const bool batched = with_aniso(kind, params, [](const auto& m) {
      return BatchedAnisoProjection<std::decay_t<decltype(m)>>::value;
    });
    EXPECT_TRUE(batched) << "fibre energy '" << name
                         << "' has no BatchedAnisoProjection (src/pbd/constraint_batches.hpp)";
  }
}

}  // namespace
}  // namespace shellcontract
