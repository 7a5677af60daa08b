// Batched anisotropic (E_A) faces (math-spec 7, 9.3): four faces of one colour at a time on the
// padded rows, each with its own fibre, k_A, orientation and frozen normal, so that the fibre
// energies take the coloured order's batched path too (constraint_batches.hpp).
#include "pbd/constraint_batches.hpp"

#include <array>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include "pbd/batch_lanes.hpp"
#include "pbd/membrane_lanes.hpp"

namespace shellcontract {
namespace {

using namespace batch_lanes;  // NOLINT(google-build-using-namespace): the shared lane code

/// A face's record for make_batches: its vertices, rest data, fibre and k_A.
struct AnisoRecord {
  std::array<int, 3> v;
  PackedMembrane rest;
  Vec2 fiber;
  double k_a;
};

/// Lane k of batch b through the solver's per-face call (the local stencil of project_lane).
template <class A>
void scalar_lane(const A& material, const AnisoBatch& c, std::size_t b, int k, PaddedVertex* xw,
                 const ProjectionContext& ctx, double* lambda, bool paper) {
  const PackedMembrane r{{0, 1, 2}, -1, c.dm00[k], c.dm01[k], c.dm11[k], c.rest_area[k], c.max_step[k]};
  ElementMaterialData data;
  data.fiber = Vec2(c.fiber[0][k], c.fiber[1][k]);
  const Vec3 n(c.normal[0][k], c.normal[1][k], c.normal[2][k]);
  ProjectionContext with_s = ctx;
  with_s.orientation = c.orientation[k];
  double* lam = lambda ? lambda + BATCH_LANES * b + k : nullptr;
  project_lane<3>(xw, c.v, k, with_s, [&](const ProjectionContext& local) {
    if (paper)
      project_anisotropic_paper(material, r, data, c.k_a[k], n, local);
    else
      project_membrane(material, r, data, 1.0, local, lam);
  });
}

template <class A>
void aniso_batches_scalar(const A& material, const AnisoBatch* batches, std::size_t count,
                          PaddedVertex* xw, const ProjectionContext& ctx, double* lambda,
                          bool paper) {
  for (std::size_t b = 0; b < count; ++b)
    for (int k = 0; k < batches[b].count; ++k)
      scalar_lane(material, batches[b], b, k, xw, ctx, lambda, paper);
}

#if SHELLCONTRACT_BATCH_AVX2
// Compiled for AVX2 + FMA like the lane code of batch_lanes.hpp (see there).
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"  // as in batch_lanes.hpp

/// The fibre a of four lanes.
struct LaneFiber {
  V a0, a1;
};

/// S = k a a^T (S(i, j) = (k a_i) a_j, as Eigen's k * a * a^T).
SC_AVX2_INLINE void outer(V k, const LaneFiber& a, LaneP& S) {
  const V ka0 = k * a.a0, ka1 = k * a.a1;
  S.p00 = ka0 * a.a0;
  S.p01 = ka0 * a.a1;
  S.p10 = ka1 * a.a0;
  S.p11 = ka1 * a.a1;
}

/// I5 = a^T C a for the C-form (a.dot(C * a)).
SC_AVX2_INLINE V i5_of(V c00, V c01, V c11, const LaneFiber& a) {
  return a.a0 * (c00 * a.a0 + c01 * a.a1) + a.a1 * (c01 * a.a0 + c11 * a.a1);
}

/// AnisotropicStvk::psi_second_pk (math-spec 7).
struct StvkFiberLanes {
  V mu;
  LaneFiber a;
  static constexpr bool cform = true;
  SC_AVX2_INLINE V operator()(V c00, V c01, V c11, LaneP& S) const {
    const V t = i5_of(c00, c01, c11, a) - splat(1.0);
    outer(splat(2.0) * mu * t, a, S);
    return splat(0.5) * mu * t * t;
  }
};

/// AnisotropicSqrt::psi_second_pk: S = 0 where |F a| < FIBER_MIN_STRETCH (math-spec 11).
struct SqrtFiberLanes {
  V mu;
  LaneFiber a;
  static constexpr bool cform = true;
  SC_AVX2_INLINE V operator()(V c00, V c01, V c11, LaneP& S) const {
    const V len = _mm256_sqrt_pd(_mm256_max_pd(i5_of(c00, c01, c11, a), _mm256_setzero_pd()));
    const V defined = _mm256_cmp_pd(len, splat(FIBER_MIN_STRETCH), _CMP_GE_OQ);  // !(len < min)
    outer(_mm256_and_pd(mu * (splat(1.0) - splat(1.0) / len), defined), a, S);
    const V t = len - splat(1.0);
    return splat(0.5) * mu * t * t;
  }
};

/// AnisotropicArap (gamma = 1) and ActiveFiber: psi = mu/2 (|F a| - gamma sign(I4))^2,
/// P = mu (1 - gamma sign / |F a|) F a a^T, 0 where |F a| < FIBER_MIN_STRETCH; with the
/// upper-triangular F of a regular frame.
struct SignedFiberLanes {
  V mu, gamma;
  LaneFiber a;
  bool unit_gamma;  ///< ARAP: gamma * sign is sign itself (no multiplication, as there)
  static constexpr bool cform = false;
  SC_AVX2_INLINE V operator()(const UpperF& F, LaneP& P) const {
    const V one = splat(1.0), abs_mask = splat(-0.0);
    const V fa0 = F.f00 * a.a0 + F.f01 * a.a1, fa1 = F.f11 * a.a1;
    const V i5 = fa0 * fa0 + fa1 * fa1;
    const V J = F.f00 * F.f11;
    const V x = i5 + J;
    // fiber_sign: +1 on a tie |x| <= 1e-12 (I5 + |J|), else the sign of x.
    const V tie = _mm256_cmp_pd(_mm256_andnot_pd(abs_mask, x),
                                splat(SIGN_TIE_RATIO) * (i5 + _mm256_andnot_pd(abs_mask, J)), _CMP_LE_OQ);
    const V negative = _mm256_andnot_pd(tie, _mm256_cmp_pd(x, _mm256_setzero_pd(), _CMP_NGT_UQ));
    const V sign = _mm256_blendv_pd(one, splat(-1.0), negative);
    const V target = unit_gamma ? sign : gamma * sign;
    const V len = _mm256_sqrt_pd(i5);
    const V defined = _mm256_cmp_pd(len, splat(FIBER_MIN_STRETCH), _CMP_GE_OQ);
    const V k = _mm256_and_pd(mu * (one - target / len), defined);
    const V kf0 = k * fa0, kf1 = k * fa1;
    P.p00 = kf0 * a.a0;
    P.p01 = kf0 * a.a1;
    P.p10 = kf1 * a.a0;
    P.p11 = kf1 * a.a1;
    const V t = len - target;
    return splat(0.5) * mu * t * t;
  }
};

/// The solver's per-face projection (see project_aniso_batches), four lanes at a time; lanes(c)
/// gives the lane material of batch c (its fibres loaded).
template <class LanesOf>
void aniso_batches_avx2(LanesOf lanes_of, const AnisoBatch* batches, std::size_t count,
                        PaddedVertex* xw, const ProjectionContext& ctx, double* lambda, bool paper) {
  const V floor = splat(ctx.energy_floor), at = splat(ctx.alpha_tilde);
  for (std::size_t b = 0; b < count; ++b) {
    const AnisoBatch& c = batches[b];
    const V4 r1 = gather(xw, c.v[0]), r2 = gather(xw, c.v[1]), r3 = gather(xw, c.v[2]);
    const LaneRest rest{_mm256_load_pd(c.dm00), _mm256_load_pd(c.dm01), _mm256_load_pd(c.dm11),
                        _mm256_load_pd(c.rest_area)};
    const auto mat = lanes_of(c);
    LaneGradient g;
    if constexpr (decltype(mat)::cform)
      g = cform_gradient(mat, r1.x, r2.x, r3.x, rest);
    else
      g = frame_gradient(mat, r1.x, r2.x, r3.x, rest, _mm256_load_pd(c.orientation));
    V3 gp[3] = {g.g0, g.g1, g.g2};
    if (paper) {  // g_i + k_A n (project_anisotropic_paper; k_A = 0 leaves g as it is)
      const V k_a = _mm256_load_pd(c.k_a);
      const V3 kn{k_a * _mm256_load_pd(c.normal[0]), k_a * _mm256_load_pd(c.normal[1]),
                  k_a * _mm256_load_pd(c.normal[2])};
      for (V3& d : gp) d = d + kn;
    }
    membrane_step(xw, c.v, c.count, r1, r2, r3, g, gp, rest.area, _mm256_load_pd(c.max_step),
                  floor, at, lambda ? lambda + BATCH_LANES * b : nullptr);
  }
}

SC_AVX2_INLINE LaneFiber fiber_of(const AnisoBatch& c) {
  return {_mm256_load_pd(c.fiber[0]), _mm256_load_pd(c.fiber[1])};
}

void run_avx2(const AnisotropicStvk& m, const AnisoBatch* batches, std::size_t count,
              PaddedVertex* xw, const ProjectionContext& ctx, double* lambda, bool paper) {
  const V mu = splat(m.mu());
  aniso_batches_avx2([&](const AnisoBatch& c) { return StvkFiberLanes{mu, fiber_of(c)}; }, batches,
                     count, xw, ctx, lambda, paper);
}
void run_avx2(const AnisotropicSqrt& m, const AnisoBatch* batches, std::size_t count,
              PaddedVertex* xw, const ProjectionContext& ctx, double* lambda, bool paper) {
  const V mu = splat(m.mu());
  aniso_batches_avx2([&](const AnisoBatch& c) { return SqrtFiberLanes{mu, fiber_of(c)}; }, batches,
                     count, xw, ctx, lambda, paper);
}
void run_avx2(const AnisotropicArap& m, const AnisoBatch* batches, std::size_t count,
              PaddedVertex* xw, const ProjectionContext& ctx, double* lambda, bool paper) {
  const V mu = splat(m.mu());
  aniso_batches_avx2(
      [&](const AnisoBatch& c) { return SignedFiberLanes{mu, splat(1.0), fiber_of(c), true}; },
      batches, count, xw, ctx, lambda, paper);
}
void run_avx2(const ActiveFiber& m, const AnisoBatch* batches, std::size_t count,
              PaddedVertex* xw, const ProjectionContext& ctx, double* lambda, bool paper) {
  const V mu = splat(m.mu()), gamma = splat(m.fiber_target());
  aniso_batches_avx2(
      [&](const AnisoBatch& c) { return SignedFiberLanes{mu, gamma, fiber_of(c), false}; },
      batches, count, xw, ctx, lambda, paper);
}

#pragma GCC diagnostic pop
#pragma GCC pop_options
#endif  // SHELLCONTRACT_BATCH_AVX2

}  // namespace

ColouredBatches<AnisoBatch> make_aniso_batches(const std::vector<PackedMembrane>& records,
                                               const std::vector<ElementMaterialData>& data,
                                               const std::vector<double>& k_a,
                                               const std::vector<std::size_t>& colour_offsets) {
  if (data.size() != records.size() || k_a.size() != records.size())
    throw std::invalid_argument("make_aniso_batches: one fibre and one k_A per face");
  std::vector<AnisoRecord> r;
  r.reserve(records.size());
  for (std::size_t i = 0; i < records.size(); ++i)
    r.push_back({records[i].v, records[i], data[i].fiber, k_a[i]});
  return make_batches<AnisoBatch>(r, colour_offsets, [](AnisoBatch& b, int k, const AnisoRecord& a) {
    b.dm00[k] = a.rest.dm00;
    b.dm01[k] = a.rest.dm01;
    b.dm11[k] = a.rest.dm11;
    b.rest_area[k] = a.rest.rest_area;
    b.max_step[k] = a.rest.max_step;
    b.fiber[0][k] = a.fiber.x();
    b.fiber[1][k] = a.fiber.y();
    b.k_a[k] = a.k_a;
    b.orientation[k] = 1.0;
  });
}

template <class A>
void project_aniso_batches(const A& material, const AnisoBatch* batches, std::size_t count,
                           PaddedVertex* xw, const ProjectionContext& ctx, double* lambda,
                           bool paper, BatchIsa isa) {
#if SHELLCONTRACT_BATCH_AVX2
  if (isa == BatchIsa::Auto && batch_avx2_available()) {
    const HeldFpExceptions held;
    run_avx2(material, batches, count, xw, ctx, paper ? nullptr : lambda, paper);
    return;
  }
#endif
  (void)isa;
  aniso_batches_scalar(material, batches, count, xw, ctx, paper ? nullptr : lambda, paper);
}

template void project_aniso_batches(const AnisotropicArap&, const AnisoBatch*, std::size_t,
                                    PaddedVertex*, const ProjectionContext&, double*, bool, BatchIsa);
template void project_aniso_batches(const AnisotropicStvk&, const AnisoBatch*, std::size_t,
                                    PaddedVertex*, const ProjectionContext&, double*, bool, BatchIsa);
template void project_aniso_batches(const AnisotropicSqrt&, const AnisoBatch*, std::size_t,
                                    PaddedVertex*, const ProjectionContext&, double*, bool, BatchIsa);
template void project_aniso_batches(const ActiveFiber&, const AnisoBatch*, std::size_t,
                                    PaddedVertex*, const ProjectionContext&, double*, bool, BatchIsa);

}  // namespace shellcontract
