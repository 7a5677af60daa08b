// What the batched membrane kernels of the frame-based and the fibre materials share
// (membrane_batches.cpp, aniso_batches.cpp): the energy and vertex gradients of four triangles
// through the current edge-aligned frame (math-spec 4.2-4.4) or through C = F^T F (the C-form of
// 4.4), and the PBD / XPBD step with its stores. Each line mirrors the scalar kernel
// (constraint_kernels.hpp, fem/triangle_element.hpp); the results differ by rounding only (fused
// multiply-adds, and a reciprocal multiplied where the scalar code divides). Private to src/pbd.
#pragma once

#include "fem/triangle_element.hpp"
#include "pbd/batch_lanes.hpp"

namespace shellcontract {
namespace batch_lanes {

#if SHELLCONTRACT_BATCH_AVX2
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"  // as in batch_lanes.hpp

SC_AVX2_INLINE V3 cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// Fbar of a regular frame on four lanes: upper triangular, F(1, 0) = 0 (math-spec 4.3).
struct UpperF {
  V f00, f01, f11;
};
/// A 2x2 PK1 (or, for the C-form, the symmetric S with p01 = p10) on four lanes.
struct LaneP {
  V p00, p01, p10, p11;
};

/// Energy and vertex gradients of four triangles; `valid` marks the lanes that have them.
struct LaneGradient {
  V3 g0, g1, g2;
  V E;
  V valid;
};

/// The rest data of four triangles (PackedMembrane's fields).
struct LaneRest {
  V dm00, dm01, dm11, area;
};

/// kernel_parts::membrane_energy_gradient's frame branch for a frame-based material: triangle_frame
/// (regular frames only: `valid` = regular), mat(F, P) -> psi, and lift_gradient.
/// @param s  orientation of each lane (math-spec 4.2)
template <class Lanes>
SC_AVX2_INLINE LaneGradient frame_gradient(const Lanes& mat, const V3& x1, const V3& x2,
                                           const V3& x3, const LaneRest& r, V s) {
  const V half = splat(0.5), one = splat(1.0), zero = _mm256_setzero_pd();
  const V3 e1 = x1 - x3, e2 = x2 - x3;
  const V3 N = cross(e1, e2);
  const V twice_area = _mm256_sqrt_pd(dot(N, N));
  const V len1 = _mm256_sqrt_pd(dot(e1, e1));
  LaneGradient out;
  out.valid = _mm256_and_pd(
      _mm256_cmp_pd(half * twice_area, splat(FRAME_AREA_RATIO) * r.area, _CMP_GE_OQ),
      greater(len1, zero));
  const V inv_len1 = one / len1;
  const V3 t1 = e1 * inv_len1;
  const V3 t2 = cross(N, t1) * (s / twice_area);  // (s n) x t1
  const V p01 = dot(e2, t1), p11 = s * twice_area * inv_len1;  // pDs = [[len1, p01], [0, p11]]
  const UpperF F{len1 * r.dm00, len1 * r.dm01 + p01 * r.dm11, p11 * r.dm11};
  LaneP P;
  const V psi = mat(F, P);
  // lift_gradient: H = Abar P Dm^-T, [g1 g2] = p^T H, g3 = -g1 - g2.
  const V h00 = (r.area * P.p00) * r.dm00 + (r.area * P.p01) * r.dm01;
  const V h01 = (r.area * P.p01) * r.dm11;
  const V h10 = (r.area * P.p10) * r.dm00 + (r.area * P.p11) * r.dm01;
  const V h11 = (r.area * P.p11) * r.dm11;
  out.g0 = t1 * h00 + t2 * h10;
  out.g1 = t1 * h01 + t2 * h11;
  out.g2 = V3{zero - out.g0.x - out.g1.x, zero - out.g0.y - out.g1.y, zero - out.g0.z - out.g1.z};
  out.E = r.area * psi;
  return out;
}

/// membrane_energy_gradient_cform: C = F^T F, mat(C, S) -> psi with S symmetric (p01 = p10),
/// P3 = F S, [g1 g2] = Abar P3 Dm^-T. Every lane is valid (no frame).
template <class Lanes>
SC_AVX2_INLINE LaneGradient cform_gradient(const Lanes& mat, const V3& x1, const V3& x2,
                                           const V3& x3, const LaneRest& r) {
  const V zero = _mm256_setzero_pd();
  const V3 e1 = x1 - x3, e2 = x2 - x3;
  const V3 f0 = e1 * r.dm00;
  const V3 f1 = e1 * r.dm01 + e2 * r.dm11;
  LaneP S;
  const V psi = mat(dot(f0, f0), dot(f0, f1), dot(f1, f1), S);
  const V3 p0 = f0 * S.p00 + f1 * S.p10;
  const V3 p1 = f0 * S.p01 + f1 * S.p11;
  LaneGradient out;
  out.g0 = (p0 * r.dm00 + p1 * r.dm01) * r.area;
  out.g1 = (p1 * r.dm11) * r.area;
  out.g2 = V3{zero - out.g0.x - out.g1.x, zero - out.g0.y - out.g1.y, zero - out.g0.z - out.g1.z};
  out.E = r.area * psi;
  out.valid = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  return out;
}

/// The step of project_membrane for the lanes that pass its skips (valid, E > floor Abar,
/// G > 1e-300), written to the padded rows: PBD dx_i = -(E / G) w_i g_i, clamped to max_step
/// (math-spec 9.1d); XPBD (lam != nullptr, four multipliers) the division-free sigma of 9.2.
/// @param gp  the step's directions (g, or g + k_A n for the paper's E_A projection)
SC_AVX2_INLINE void membrane_step(PaddedVertex* xw, const int (&v)[3][BATCH_LANES], int count,
                                  const V4& r1, const V4& r2, const V4& r3, const LaneGradient& g,
                                  const V3 (&gp)[3], V area, V max_step, V floor, V alpha_tilde,
                                  double* lam) {
  const V w0 = r1.w, w1 = r2.w, w2 = r3.w;
  const V n0 = dot(gp[0], gp[0]), n1 = dot(gp[1], gp[1]), n2 = dot(gp[2], gp[2]);
  const V G = w0 * n0 + w1 * n1 + w2 * n2;
  const V active = _mm256_and_pd(
      g.valid, _mm256_and_pd(greater(g.E, floor * area), greater(G, splat(1e-300))));
  if (_mm256_movemask_pd(active) == 0) return;
  V sigma;  // dx_i = -sigma w_i gp_i
  if (lam == nullptr) {
    sigma = g.E / G;
    const V a0 = sigma * w0, a1 = sigma * w1, a2 = sigma * w2;
    const V longest_sq = _mm256_max_pd(_mm256_max_pd(a0 * a0 * n0, a1 * a1 * n1), a2 * a2 * n2);
    const V clamp = greater(longest_sq, max_step * max_step);
    if (_mm256_movemask_pd(_mm256_and_pd(clamp, active)) != 0)  // the clamp is rare
      sigma = _mm256_blendv_pd(sigma, sigma * (max_step / _mm256_sqrt_pd(longest_sq)), clamp);
  } else {
    const V l = _mm256_loadu_pd(lam);
    const V C = _mm256_sqrt_pd(_mm256_max_pd(splat(2.0) * g.E, _mm256_setzero_pd()));
    sigma = C * (C + alpha_tilde * l) / (G + alpha_tilde * C * C);
    _mm256_storeu_pd(lam, _mm256_blendv_pd(l, l - C * sigma, active));
  }
  scatter(xw, v[0], count, r1.x - masked(gp[0] * (sigma * w0), active), w0);
  scatter(xw, v[1], count, r2.x - masked(gp[1] * (sigma * w1), active), w1);
  scatter(xw, v[2], count, r3.x - masked(gp[2] * (sigma * w2), active), w2);
}

#pragma GCC diagnostic pop
#pragma GCC pop_options
#endif  // SHELLCONTRACT_BATCH_AVX2

}  // namespace batch_lanes
}  // namespace shellcontract
