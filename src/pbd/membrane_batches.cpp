// Batched membrane projections of the materials without the C-form (corotated, linear,
// Mooney-Rivlin, math-spec 6.2-6.4): four membranes of one colour at a time on the padded rows,
// through the current edge-aligned frame and the lift of the 2x2 PK1 (math-spec 4.2-4.4), so
// that every material takes the coloured order's batched path (constraint_batches.hpp).
#include "pbd/constraint_batches.hpp"

#include <cstddef>

#include "pbd/batch_lanes.hpp"
#include "pbd/membrane_lanes.hpp"

namespace shellcontract {
namespace {

using namespace batch_lanes;  // NOLINT(google-build-using-namespace): the shared lane code

PackedMembrane lane_record(const MembraneBatch& b, int k) {
  return PackedMembrane{{0, 1, 2}, -1, b.dm00[k], b.dm01[k], b.dm11[k], b.rest_area[k], b.max_step[k]};
}

/// Lane k of batch b through project_membrane (the local stencil of project_lane).
template <class M>
void scalar_lane(const M& material, const MembraneBatch* batches, std::size_t b, int k,
                 PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
  const PackedMembrane c = lane_record(batches[b], k);
  const ElementMaterialData isotropic{};
  double* lam = lambda ? lambda + BATCH_LANES * b + k : nullptr;
  project_lane<3>(xw, batches[b].v, k, ctx, [&](const ProjectionContext& local) {
    project_membrane(material, c, isotropic, 1.0, local, lam);
  });
}

/// The scalar path: every lane through project_membrane (bit-identical to it).
template <class M>
void membrane_batches_scalar(const M& material, const MembraneBatch* batches, std::size_t count,
                             PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
  for (std::size_t b = 0; b < count; ++b)
    for (int k = 0; k < batches[b].count; ++k) scalar_lane(material, batches, b, k, xw, ctx, lambda);
}

#if SHELLCONTRACT_BATCH_AVX2
// Compiled for AVX2 + FMA like the lane code of batch_lanes.hpp (see there).
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"  // as in batch_lanes.hpp

/// Linear::psi and pk1 (math-spec 6.3) with F(1, 0) = 0.
struct LinearLanes {
  V mu, lam;
  static constexpr bool frame_dependent = true;
  SC_AVX2_INLINE V operator()(const UpperF& F, LaneP& P) const {
    const V one = splat(1.0), two = splat(2.0), half = splat(0.5);
    const V e00 = F.f00 - one, e11 = F.f11 - one, e01 = half * F.f01;  // eps = sym F - I
    const V tr = e00 + e11;
    const V tr_f = F.f00 + F.f11 - two;
    P.p00 = mu * (two * F.f00 - two) + lam * tr_f;
    P.p11 = mu * (two * F.f11 - two) + lam * tr_f;
    P.p01 = P.p10 = mu * F.f01;
    return mu * (e00 * e00 + e11 * e11 + two * e01 * e01) + half * lam * tr * tr;
  }
};

/// Corotated::psi and pk1 with polar2 (math-spec 5, 6.2) and F(1, 0) = 0.
struct CorotatedLanes {
  V mu, lam;
  static constexpr bool frame_dependent = true;
  SC_AVX2_INLINE V operator()(const UpperF& F, LaneP& P) const {
    const V one = splat(1.0), two = splat(2.0), half = splat(0.5), zero = _mm256_setzero_pd();
    const V c = F.f00 + F.f11;
    const V d = zero - F.f01;  // F(1, 0) - F(0, 1)
    const V rho = _mm256_sqrt_pd(c * c + d * d);
    const V norm_f = _mm256_sqrt_pd(F.f00 * F.f00 + F.f01 * F.f01 + F.f11 * F.f11);
    // polar2's guard: rho <= 1e-12 |F| gives R = I.
    const V degenerate = _mm256_cmp_pd(rho, splat(POLAR_DEGENERACY_RATIO) * norm_f, _CMP_LE_OQ);
    const V inv = one / rho;
    const V r00 = _mm256_blendv_pd(c * inv, one, degenerate);  // R = [[c, -d], [d, c]] / rho
    const V r10 = _mm256_blendv_pd(d * inv, zero, degenerate);
    const V a00 = F.f00 - r00, a01 = F.f01 + r10, a10 = zero - r10, a11 = F.f11 - r00;  // F - R
    const V t = rho - two;
    const V lt = lam * t;
    P.p00 = two * mu * a00 + lt * r00;
    P.p01 = two * mu * a01 - lt * r10;
    P.p10 = two * mu * a10 + lt * r10;
    P.p11 = two * mu * a11 + lt * r00;
    return mu * (a00 * a00 + a01 * a01 + a10 * a10 + a11 * a11) + half * lam * t * t;
  }
};

/// MooneyRivlin::psi and pk1 (math-spec 6.4, its |J| clamp) with F(1, 0) = 0: the
/// cancellation-free form of mooney_rivlin.hpp, and the written form for the lanes in the clamp.
struct MooneyRivlinLanes {
  V c10, c01;
  static constexpr bool frame_dependent = false;
  SC_AVX2_INLINE V operator()(const UpperF& F, LaneP& P) const {
    const V one = splat(1.0), two = splat(2.0), zero = _mm256_setzero_pd();
    constexpr double J0 = MOONEY_RIVLIN_MIN_ABS_J;
    const V J = F.f00 * F.f11;
    const V u = _mm256_andnot_pd(splat(-0.0), J);
    const V eta = _mm256_blendv_pd(one, splat(-1.0), _mm256_cmp_pd(J, zero, _CMP_LT_OQ));
    // Delta = I_C - 2 u = t^2 + F01^2; F - eta cof F = [[t, F01], [eta F01, -eta t]] and
    // cof F = [[F11, 0], [-F01, F00]].
    const V t = F.f00 - eta * F.f11;
    const V delta = t * t + F.f01 * F.f01;
    const V inv_u = one / u;
    const V inv_u2 = inv_u * inv_u;
    const V m = u - one;
    const V q = m * (u * u + u + one);  // u^3 - 1
    V a = two * (c10 + c01 * inv_u2);
    V b = (two * eta * inv_u2 * inv_u) * (c10 * q + c01 * (q * u - delta));
    P.p00 = a * t + b * F.f11;
    P.p01 = a * F.f01;
    P.p10 = (a * eta - b) * F.f01;
    P.p11 = b * F.f00 - a * eta * t;
    V psi = c10 * (delta + m * m * (two * u + one) * inv_u2) +
            c01 * (delta * inv_u2 + m * m * (u + two) * inv_u);
    const V barrier_side = _mm256_cmp_pd(u, splat(J0), _CMP_GE_OQ);
    if (_mm256_movemask_pd(barrier_side) != 0xF) {
      // A lane in the clamp (a nearly collapsed triangle): the written form with the linear
      // continuation g of J^-2 (sign(0) = +1), as MooneyRivlin does there.
      const V IC = F.f00 * F.f00 + F.f01 * F.f01 + F.f11 * F.f11;
      const V g = splat(3.0 / (J0 * J0)) - two * u / splat(J0 * J0 * J0);
      const V dg = _mm256_blendv_pd(splat(-2.0 / (J0 * J0 * J0)), splat(2.0 / (J0 * J0 * J0)),
                                    _mm256_cmp_pd(J, zero, _CMP_LT_OQ));
      a = two * (c10 + c01 * g);
      b = c10 * dg + two * c01 * J + c01 * IC * dg;
      // P = a F + b cof F.
      P.p00 = _mm256_blendv_pd(a * F.f00 + b * F.f11, P.p00, barrier_side);
      P.p01 = _mm256_blendv_pd(a * F.f01, P.p01, barrier_side);
      P.p10 = _mm256_blendv_pd(zero - b * F.f01, P.p10, barrier_side);
      P.p11 = _mm256_blendv_pd(a * F.f11 + b * F.f00, P.p11, barrier_side);
      psi = _mm256_blendv_pd(c10 * (IC + g - splat(3.0)) + c01 * (J * J + IC * g - splat(3.0)), psi,
                             barrier_side);
    }
    return psi;
  }
};

/// project_membrane through the frame (kernel_parts::membrane_energy_gradient's F-form branch),
/// four lanes at a time, for a material's lane form `mat`. Lanes whose frame is not regular are
/// skipped by frame-dependent materials, as there; Mooney-Rivlin's take the scalar kernel (its
/// collapsed frame, rare and branchy).
template <class Lanes, class M>
void frame_membrane_batches_avx2(const Lanes& mat, const M& material, const MembraneBatch* batches,
                                 std::size_t count, PaddedVertex* xw, const ProjectionContext& ctx,
                                 double* lambda) {
  const V floor = splat(ctx.energy_floor), at = splat(ctx.alpha_tilde);
  const V s = splat(ctx.orientation);
  for (std::size_t b = 0; b < count; ++b) {
    const MembraneBatch& c = batches[b];
    const V4 r1 = gather(xw, c.v[0]), r2 = gather(xw, c.v[1]), r3 = gather(xw, c.v[2]);
    const LaneRest rest{_mm256_load_pd(c.dm00), _mm256_load_pd(c.dm01), _mm256_load_pd(c.dm11),
                        _mm256_load_pd(c.rest_area)};
    const LaneGradient g = frame_gradient(mat, r1.x, r2.x, r3.x, rest, s);
    const V3 gp[3] = {g.g0, g.g1, g.g2};
    membrane_step(xw, c.v, c.count, r1, r2, r3, g, gp, rest.area, _mm256_load_pd(c.max_step),
                  floor, at, lambda ? lambda + BATCH_LANES * b : nullptr);
    if constexpr (!Lanes::frame_dependent) {
      // Lanes without a regular frame: the scalar kernel, after the vector lanes' stores (the
      // lanes share no vertex: the order between them is free).
      const int irregular = ~_mm256_movemask_pd(g.valid) & ((1 << c.count) - 1);
      if (irregular != 0)
        for (int k = 0; k < c.count; ++k)
          if ((irregular >> k) & 1) scalar_lane(material, batches, b, k, xw, ctx, lambda);
    }
  }
}

void linear_avx2(const Linear& m, const MembraneBatch* batches, std::size_t count,
                 PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
  frame_membrane_batches_avx2(LinearLanes{splat(m.mu()), splat(m.lambda())}, m, batches, count, xw,
                              ctx, lambda);
}
void corotated_avx2(const Corotated& m, const MembraneBatch* batches, std::size_t count,
                    PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
  frame_membrane_batches_avx2(CorotatedLanes{splat(m.mu()), splat(m.lambda())}, m, batches, count,
                              xw, ctx, lambda);
}
void mooney_rivlin_avx2(const MooneyRivlin& m, const MembraneBatch* batches, std::size_t count,
                        PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
  frame_membrane_batches_avx2(MooneyRivlinLanes{splat(m.c10()), splat(m.c01())}, m, batches, count,
                              xw, ctx, lambda);
}

#pragma GCC diagnostic pop
#pragma GCC pop_options
#define SC_AVX2_KERNEL(kernel)                                \
  if (isa == BatchIsa::Auto && batch_avx2_available()) {      \
    const HeldFpExceptions held;                              \
    return kernel(material, batches, count, xw, ctx, lambda); \
  }
#else
#define SC_AVX2_KERNEL(kernel) (void)isa
#endif  // SHELLCONTRACT_BATCH_AVX2

}  // namespace

void project_linear_membrane_batches(const Linear& material, const MembraneBatch* batches,
                                     std::size_t count, PaddedVertex* xw,
                                     const ProjectionContext& ctx, double* lambda, BatchIsa isa) {
  SC_AVX2_KERNEL(linear_avx2);
  membrane_batches_scalar(material, batches, count, xw, ctx, lambda);
}

void project_corotated_membrane_batches(const Corotated& material, const MembraneBatch* batches,
                                        std::size_t count, PaddedVertex* xw,
                                        const ProjectionContext& ctx, double* lambda,
                                        BatchIsa isa) {
  SC_AVX2_KERNEL(corotated_avx2);
  membrane_batches_scalar(material, batches, count, xw, ctx, lambda);
}

void project_mooney_rivlin_membrane_batches(const MooneyRivlin& material,
                                            const MembraneBatch* batches, std::size_t count,
                                            PaddedVertex* xw, const ProjectionContext& ctx,
                                            double* lambda, BatchIsa isa) {
  SC_AVX2_KERNEL(mooney_rivlin_avx2);
  membrane_batches_scalar(material, batches, count, xw, ctx, lambda);
}

#undef SC_AVX2_KERNEL

}  // namespace shellcontract
