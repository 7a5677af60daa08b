// Batched anisotropic faces (src/pbd/aniso_batches.cpp): four E_A faces of one colour, each with
// its own fibre, k_A, orientation s and frozen normal, must give what the solver's per-face calls
// give one after the other (project_anisotropic_paper in the paper's PBD mode, project_membrane
// in plain PBD and XPBD): bit for bit on the scalar path, to 1e-12 of the step on the AVX2 + FMA
// path, for every fibre energy, both orientations (the sign of I4 flips with s, math-spec 5) and
// the guarded cases of membrane_scene. A wrong fibre term, sign rule or k_A term moves the steps
// far more than that (checked by dropping the k_A n term and by taking sign(I4) = +1: both fail).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
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

/// membrane_scene with a random unit fibre, k_A (every third one 0), orientation and unit normal
/// per face.
struct AnisoScene : MembraneScene {
  std::vector<ElementMaterialData> data;
  std::vector<double> k_a, s;
  std::vector<Vec3> n;
};

AnisoScene aniso_scene(int n, std::mt19937& rng) {
  AnisoScene sc;
  static_cast<MembraneScene&>(sc) = membrane_scene(n, rng);
  std::uniform_real_distribution<double> angle(-3.14159, 3.14159), k(0.05, 0.5);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (std::size_t i = 0; i < sc.records.size(); ++i) {
    const double a = angle(rng);
    ElementMaterialData d;
    d.fiber = Vec2(std::cos(a), std::sin(a));
    sc.data.push_back(d);
    sc.k_a.push_back(i % 3 == 0 ? 0.0 : k(rng));
    sc.s.push_back(i % 2 == 0 ? 1.0 : -1.0);
    sc.n.push_back(Vec3(normal(rng), normal(rng), normal(rng)).normalized());
  }
  return sc;
}

enum class Mode { Paper, Pbd, Xpbd };

template <class A>
std::vector<double> scalar_aniso(const A& m, const AnisoScene& sc, Mode mode, std::vector<double>* lambda) {
  std::vector<double> x = sc.x0;
  if (lambda) lambda->assign(sc.records.size(), 0.0);
  for (std::size_t i = 0; i < sc.records.size(); ++i) {
    ProjectionContext ctx = context(x, sc.w);
    ctx.orientation = sc.s[i];
    if (mode == Mode::Paper)
      project_anisotropic_paper(m, sc.records[i], sc.data[i], sc.k_a[i], sc.n[i], ctx);
    else
      project_membrane(m, sc.records[i], sc.data[i], 1.0, ctx, lambda ? &(*lambda)[i] : nullptr);
  }
  return x;
}

template <class A>
std::vector<double> batched_aniso(const A& m, const AnisoScene& sc, Mode mode, BatchIsa isa,
                                  std::vector<double>* lambda) {
  ColouredBatches<AnisoBatch> b = make_aniso_batches(sc.records, sc.data, sc.k_a, sc.colours);
  // The per-solve data, lane by lane in colour order (as the solver writes it).
  for (std::size_t c = 0; c + 1 < sc.colours.size(); ++c)
    for (std::size_t i = sc.colours[c]; i < sc.colours[c + 1]; ++i) {
      const std::size_t j = i - sc.colours[c];
      AnisoBatch& batch = b.batches[b.offsets[c] + j / BATCH_LANES];
      batch.orientation[j % BATCH_LANES] = sc.s[i];
      for (int d = 0; d < 3; ++d) batch.normal[d][j % BATCH_LANES] = sc.n[i](d);
    }
  std::vector<double> x = sc.x0;
  std::vector<PaddedVertex> xw = padded(sc);
  const ProjectionContext ctx = context(x, sc.w);
  std::vector<double> lam(BATCH_LANES * b.batches.size(), 0.0);
  project_aniso_batches(m, b.batches.data(), b.batches.size(), xw.data(), ctx,
                        lambda ? lam.data() : nullptr, mode == Mode::Paper, isa);
  unpack_padded(xw.data(), 0, xw.size(), x.data());
  if (lambda) {
    lambda->clear();
    for (std::size_t j = 0; j < b.batches.size(); ++j)
      for (int k = 0; k < b.batches[j].count; ++k) lambda->push_back(lam[BATCH_LANES * j + k]);
  }
  return x;
}

template <class A>
void expect_batches_match(const A& m, const char* name) {
  std::mt19937 rng(61);
  for (int n : {9, 13, 16}) {
    const AnisoScene sc = aniso_scene(n, rng);
    for (Mode mode : {Mode::Paper, Mode::Pbd, Mode::Xpbd}) {
      const bool xpbd = mode == Mode::Xpbd;
      const std::string what = std::string(name) + " n " + std::to_string(n) + " mode " +
                               std::to_string(static_cast<int>(mode));
      std::vector<double> lam_ref, lam_scalar, lam_auto;
      const std::vector<double> ref = scalar_aniso(m, sc, mode, xpbd ? &lam_ref : nullptr);
      const std::vector<double> scalar = batched_aniso(m, sc, mode, BatchIsa::Scalar, xpbd ? &lam_scalar : nullptr);
      EXPECT_EQ(scalar, ref) << what;
      EXPECT_EQ(lam_scalar, lam_ref) << what;
      const std::vector<double> fast = batched_aniso(m, sc, mode, BatchIsa::Auto, xpbd ? &lam_auto : nullptr);
      expect_close_to_step(fast, ref, sc.x0, what.c_str());
      ASSERT_EQ(lam_auto.size(), lam_ref.size());
      for (std::size_t i = 0; i < lam_ref.size(); ++i)
        EXPECT_LE(std::abs(lam_auto[i] - lam_ref[i]), 1e-12 * std::abs(lam_ref[i])) << what << " lambda " << i;
      for (int i : {3, 4, 5})  // all pinned: exactly unchanged
        for (int d = 0; d < 3; ++d) EXPECT_EQ(fast[3 * i + d], sc.x0[3 * i + d]) << what << " vertex " << i;
    }
  }
}

MaterialParams fibre_params() {
  MaterialParams p;
  p.mu_aniso = 1.7;
  p.fiber_target = 0.7;
  return p;
}

TEST(AnisoBatches, ArapMatchesTheScalarKernels) {
  RecordProperty("avx2", batch_avx2_available() ? 1 : 0);
  expect_batches_match(AnisotropicArap(fibre_params()), "arap");
}
TEST(AnisoBatches, StvkMatchesTheScalarKernels) {
  expect_batches_match(AnisotropicStvk(fibre_params()), "stvk");
}
TEST(AnisoBatches, SqrtMatchesTheScalarKernels) {
  expect_batches_match(AnisotropicSqrt(fibre_params()), "sqrt");
}
TEST(AnisoBatches, ActiveFiberMatchesTheScalarKernels) {
  expect_batches_match(ActiveFiber(fibre_params()), "active-fiber");
}

}  // namespace
}  // namespace shellcontract
