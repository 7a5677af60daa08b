#include "pbd/constraint_batches.hpp"

#include <algorithm>

#include "core/kernels.hpp"
#include "pbd/batch_lanes.hpp"

namespace shellcontract {
namespace {

using namespace batch_lanes;  // NOLINT(google-build-using-namespace): the shared lane code

PackedMembrane lane_record(const MembraneBatch& b, int k) {
  return PackedMembrane{{b.v[0][k], b.v[1][k], b.v[2][k]}, -1, b.dm00[k], b.dm01[k], b.dm11[k],
                        b.rest_area[k], b.max_step[k]};
}

IsometricHingeConstraint lane_record(const IsometricBatch& b, int k) {
  IsometricHingeConstraint c;
  c.v = {b.v[0][k], b.v[1][k], b.v[2][k], b.v[3][k]};
  c.K << b.K[0][k], b.K[1][k], b.K[2][k], b.K[3][k];
  c.three_over_area = b.three_over_area[k];
  c.max_step = b.max_step[k];
  return c;
}

void membrane_batches_scalar(const Stvk& material, const MembraneBatch* batches, std::size_t count,
                             PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
  const ElementMaterialData isotropic{};
  for (std::size_t b = 0; b < count; ++b)
    for (int k = 0; k < batches[b].count; ++k) {
      PackedMembrane c = lane_record(batches[b], k);
      c.v = {0, 1, 2};  // the local stencil of project_lane
      double* lam = lambda ? lambda + BATCH_LANES * b + k : nullptr;
      project_lane<3>(xw, batches[b].v, k, ctx, [&](const ProjectionContext& local) {
        project_membrane(material, c, isotropic, 1.0, local, lam);
      });
    }
}

void isometric_batches_scalar(const IsometricBatch* batches, std::size_t count, double k_bending,
                              PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
  for (std::size_t b = 0; b < count; ++b)
    for (int k = 0; k < batches[b].count; ++k) {
      IsometricHingeConstraint c = lane_record(batches[b], k);
      c.v = {0, 1, 2, 3};
      double* lam = lambda ? lambda + 3 * (BATCH_LANES * b + k) : nullptr;
      project_lane<4>(xw, batches[b].v, k, ctx, [&](const ProjectionContext& local) {
        project_isometric_hinge(c, k_bending, local, lam);
      });
    }
}

#if SHELLCONTRACT_BATCH_AVX2
// Compiled for AVX2 + FMA like the lane code of batch_lanes.hpp (see there).
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"  // as in batch_lanes.hpp

/// Lane k reads row k of a 4 by 3 block (the XPBD hinge multipliers of one batch).
constexpr int LANE_IDS[BATCH_LANES] = {0, 1, 2, 3};

/// Rows of the first `count` lanes (all four when Full) moved by -d, w unchanged. The rows are
/// read again here rather than kept in registers from the gather (no other lane of the batch
/// writes them): fewer values live across the arithmetic. Padding lanes are never written.
template <bool Full>
SC_AVX2_INLINE void move_rows(PaddedVertex* xw, const int* v, int count, const V3& d) {
  const V zero = _mm256_setzero_pd();
  const V xy02 = _mm256_unpacklo_pd(d.x, d.y), xy13 = _mm256_unpackhi_pd(d.x, d.y);
  const V z02 = _mm256_unpacklo_pd(d.z, zero), z13 = _mm256_unpackhi_pd(d.z, zero);
  const V rows[BATCH_LANES] = {_mm256_permute2f128_pd(xy02, z02, 0x20), _mm256_permute2f128_pd(xy13, z13, 0x20),
                               _mm256_permute2f128_pd(xy02, z02, 0x31), _mm256_permute2f128_pd(xy13, z13, 0x31)};
  for (int k = 0; k < BATCH_LANES; ++k) {
    if (!Full && k > 0 && k >= count) break;
    double* p = &xw[v[k]].x;
    _mm256_store_pd(p, _mm256_load_pd(p) - rows[k]);
  }
}

/// A pair of batches (BatchPair) whose rows are moved by their steps.
struct MembranePair : BatchPair<MembraneBatch> {
  /// Moves vertex j's rows by -d[j]; one test for the common case of two full batches.
  void move(PaddedVertex* xw, const L3<W> (&d)[3]) const {
    if (second && c0->count == BATCH_LANES && c1->count == BATCH_LANES) {
      for (int j = 0; j < 3; ++j) move_rows<true>(xw, c0->v[j], BATCH_LANES, V3{d[j].x.a, d[j].y.a, d[j].z.a});
      for (int j = 0; j < 3; ++j) move_rows<true>(xw, c1->v[j], BATCH_LANES, V3{d[j].x.b, d[j].y.b, d[j].z.b});
      return;
    }
    for (int j = 0; j < 3; ++j) move_rows<false>(xw, c0->v[j], c0->count, V3{d[j].x.a, d[j].y.a, d[j].z.a});
    if (second)
      for (int j = 0; j < 3; ++j) move_rows<false>(xw, c1->v[j], c1->count, V3{d[j].x.b, d[j].y.b, d[j].z.b});
  }
};

/// The material's and the context's constants, as lanes of W.
struct StvkLanes {
  W one, quarter, two, mu, half_lam, floor, tiny, at;
};

/// project_membrane for StVK on the lanes of a pair of batches (math-spec 4.4, 9.1, 9.2). The
/// quantities are the scalar kernel's, arranged for fewer instructions: the energy from S:D,
/// the gradients as combinations of the columns of F, the third from translation invariance.
/// The results differ from constraint_kernels.hpp's by rounding only.
/// @param lam  XPBD: the pair's multipliers (lambda + 4 b); unused for PBD
template <bool Xpbd>
SC_AVX2_INLINE void membrane_lanes(const MembranePair& c, PaddedVertex* xw, const StvkLanes& k,
                                   double* lam) {
  L3<W> x1, x2, x3;
  W w0, w1, w2;
  c.rows(xw, 0, x1, w0);
  c.rows(xw, 1, x2, w1);
  c.rows(xw, 2, x3, w2);
  const W dm00 = c.load(&MembraneBatch::dm00), dm01 = c.load(&MembraneBatch::dm01);
  const W dm11 = c.load(&MembraneBatch::dm11), area = c.load(&MembraneBatch::rest_area);
  // F = [e1 e2] Dm^-1 = [f0 f1] (Dm^-1 upper triangular), C = F^T F, D = C - I = 2 E, and
  // S = 2 mu E + lambda tr(E) I = mu D + (lambda / 2) tr(D) I.
  const L3<W> e1 = x1 - x3, e2 = x2 - x3;
  const L3<W> f0 = e1 * dm00;
  const L3<W> f1 = e1 * dm01 + e2 * dm11;
  const W d00 = f0.z * f0.z + (f0.y * f0.y + fmsub(f0.x, f0.x, k.one));
  const W d11 = f1.z * f1.z + (f1.y * f1.y + fmsub(f1.x, f1.x, k.one));
  const W c01 = dot(f0, f1);
  const W t = k.half_lam * (d00 + d11);
  const W s00 = k.mu * d00 + t, s11 = k.mu * d11 + t, s01 = k.mu * c01;
  // psi = S:E / 2 = S:D / 4 (S:E = 2 mu E:E + lambda tr(E)^2 = 2 psi).
  const W E = (area * k.quarter) * (s00 * d00 + s11 * d11 + (s01 + s01) * c01);
  // Abar P3 Dm^-T with P3 = F S: the gradients for x1 and x2 are f0 a_i + f1 b_i, the one for x3
  // is -(g0 + g1), computed as h = g0 + g1 from the summed coefficients.
  const W ad00 = area * dm00, ad01 = area * dm01, ad11 = area * dm11;
  const W a0 = s00 * ad00 + s01 * ad01, b0 = s01 * ad00 + s11 * ad01;
  const W a1 = s01 * ad11, b1 = s11 * ad11;
  const L3<W> g0 = f0 * a0 + f1 * b0, g1 = f0 * a1 + f1 * b1, h = f0 * (a0 + a1) + f1 * (b0 + b1);
  const W n0 = dot(g0, g0), n1 = dot(g1, g1), n2 = dot(h, h);
  const W G = w0 * n0 + w1 * n1 + w2 * n2;
  // The skips of math-spec 9.1(d), per lane (skipped lanes divide freely: HeldFpExceptions).
  const W active = vand(cmp_gt(E, k.floor * area), cmp_gt(G, k.tiny));
  const int bits = lane_bits(active);
  if (bits == 0) return;
  W sigma;  // dx_i = -sigma w_i g_i
  if (!Xpbd) {
    sigma = E / G;
    // The clamp: the longest step sigma^2 max(w_i^2 n_i) against max_step^2; a clamped lane's
    // step is then max_step / sqrt(m) (the clamp is rare). Compared through sigma, which is
    // scale-free under PBD: E^2 m against (max_step G)^2 overflows to inf = inf, and so skips
    // the clamp, once mu is above about 1e75 (the options allow 1e100).
    const W m = vmax(vmax(w0 * w0 * n0, w1 * w1 * n1), w2 * w2 * n2);
    const W max_step = c.load(&MembraneBatch::max_step);
    const W clamp = cmp_gt(sigma * sigma * m, max_step * max_step);
    if (lane_bits(vand(clamp, active)) != 0) sigma = blend(sigma, max_step / vsqrt(m), clamp);
  } else {
    // Division-free form of math-spec 9.2 with C = sqrt(2E) (E > 0 on active lanes).
    const W l = c.load_lambda(lam);
    const W C = vsqrt(vmax(k.two * E, lanes_splat<W>(0.0)));
    sigma = C * (C + k.at * l) / (G + k.at * C * C);
    c.store_lambda(lam, blend(l, l - C * sigma, active));
  }
  const W s0 = sigma * w0, s1 = sigma * w1, s2 = vxor(sigma * w2, lanes_splat<W>(-0.0));
  L3<W> d[3] = {g0 * s0, g1 * s1, h * s2};  // h (-s2) = -h s2 = g2 s2
  // Inactive lanes move by +0 whatever their g (inf or NaN included), so x - d == x exactly;
  // with every lane active that mask is the identity.
  if (bits != (1 << (2 * BATCH_LANES)) - 1)
    for (L3<W>& dj : d) dj = {vand(dj.x, active), vand(dj.y, active), vand(dj.z, active)};
  c.move(xw, d);
}

/// Batches in pairs where two consecutive ones are of one colour, else one at a time (see
/// MembranePair).
template <bool Xpbd>
void membrane_batches_avx2(double mu, double lambda_lame, const MembraneBatch* batches,
                           std::size_t count, PaddedVertex* xw, const ProjectionContext& ctx,
                           double* lambda) {
  const auto s = [](double a) { return lanes_splat<W>(a); };
  const StvkLanes k{s(1.0), s(0.25), s(2.0), s(mu), s(0.5 * lambda_lame), s(ctx.energy_floor),
                    s(1e-300), s(ctx.alpha_tilde)};
  for (std::size_t b = 0; b < count;) {
    const bool pair = b + 1 < count && batches[b].same_colour_next;
    membrane_lanes<Xpbd>(MembranePair{{batches + b, batches + (pair ? b + 1 : b), pair}}, xw, k,
                         Xpbd ? lambda + BATCH_LANES * b : nullptr);
    b += pair ? 2 : 1;
  }
}

/// project_isometric_hinge, four lanes at a time (math-spec 8.2).
void isometric_batches_avx2(const IsometricBatch* batches, std::size_t count, double k_bending,
                            PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
  const V one = splat(1.0), tiny = splat(1e-300), at = splat(ctx.alpha_tilde);
  const V kb = splat(k_bending), two = splat(2.0);
  const V sign = splat(-0.0);
  for (std::size_t b = 0; b < count; ++b) {
    const IsometricBatch& c = batches[b];
    V3 xs[4];
    V ws[4], K[4];
    for (int j = 0; j < 4; ++j) {
      const V4 r = gather(xw, c.v[j]);
      xs[j] = r.x;
      ws[j] = r.w;
      K[j] = _mm256_load_pd(c.K[j]);
    }
    const V3 h = xs[0] * K[0] + xs[1] * K[1] + xs[2] * K[2] + xs[3] * K[3];
    const V wK2 = ws[0] * K[0] * K[0] + ws[1] * K[1] * K[1] + ws[2] * K[2] * K[2] + ws[3] * K[3] * K[3];
    // Every stencil vertex pinned or K = 0 (an inactive hinge): no change.
    const V active = greater(wK2, tiny);
    if (_mm256_movemask_pd(active) == 0) continue;
    if (lambda == nullptr) {
      // PBD closed form: dx_i = -k_B w_i K_i h / (2 sum w K^2), clamped (math-spec 9.1d).
      const V3 base = h * (kb / (two * wK2));
      V longest = _mm256_andnot_pd(sign, ws[0] * K[0]);
      for (int j = 1; j < 4; ++j) longest = _mm256_max_pd(longest, _mm256_andnot_pd(sign, ws[j] * K[j]));
      // longest |dx_i| = longest * |base|; compared squared so that the common, unclamped case
      // needs neither the square root nor the division (the clamp is rare).
      const V max_step = _mm256_load_pd(c.max_step);
      const V base_sq = dot(base, base);
      const V clamp = greater(longest * longest * base_sq, max_step * max_step);
      V shrink = one;
      if (_mm256_movemask_pd(_mm256_and_pd(clamp, active)) != 0) {
        longest = longest * _mm256_sqrt_pd(base_sq);
        shrink = _mm256_blendv_pd(one, max_step / longest, greater(longest, max_step));
      }
      for (int j = 0; j < 4; ++j)
        scatter(xw, c.v[j], c.count, xs[j] - masked(base * (shrink * ws[j] * K[j]), active), ws[j]);
      continue;
    }
    // XPBD vector form: C = sqrt(beta) h, beta = 3 k_B / (A0 + A1) (math-spec 8.2).
    double* lam = lambda + 3 * BATCH_LANES * b;
    const V3 l = gather3(lam, LANE_IDS);
    const V beta = kb * _mm256_load_pd(c.three_over_area);
    const V sqrt_beta = _mm256_sqrt_pd(_mm256_max_pd(beta, _mm256_setzero_pd()));
    const V denom = beta * wK2 + at;
    const V3 dlam{(-sqrt_beta * h.x - at * l.x) / denom, (-sqrt_beta * h.y - at * l.y) / denom,
                  (-sqrt_beta * h.z - at * l.z) / denom};
    scatter3(lam, LANE_IDS, l + masked(dlam, active));
    for (int j = 0; j < 4; ++j)
      scatter(xw, c.v[j], c.count, xs[j] + masked(dlam * (ws[j] * sqrt_beta * K[j]), active), ws[j]);
  }
}

#pragma GCC diagnostic pop
#pragma GCC pop_options
#endif  // SHELLCONTRACT_BATCH_AVX2

}  // namespace

ColouredBatches<MembraneBatch> make_membrane_batches(const std::vector<PackedMembrane>& records,
                                                     const std::vector<std::size_t>& colour_offsets) {
  return make_batches<MembraneBatch>(records, colour_offsets,
                                     [](MembraneBatch& b, int k, const PackedMembrane& r) {
                                       b.dm00[k] = r.dm00;
                                       b.dm01[k] = r.dm01;
                                       b.dm11[k] = r.dm11;
                                       b.rest_area[k] = r.rest_area;
                                       b.max_step[k] = r.max_step;
                                     });
}

ColouredBatches<IsometricBatch> make_isometric_batches(
    const std::vector<IsometricHingeConstraint>& records,
    const std::vector<std::size_t>& colour_offsets) {
  return make_batches<IsometricBatch>(records, colour_offsets,
                                      [](IsometricBatch& b, int k, const IsometricHingeConstraint& r) {
                                        for (int j = 0; j < 4; ++j) b.K[j][k] = r.K(j);
                                        b.three_over_area[k] = r.three_over_area;
                                        b.max_step[k] = r.max_step;
                                      });
}

bool batch_avx2_available() {
#if SHELLCONTRACT_BATCH_AVX2
  // Checked once: libgcc's cpuid test, which also requires the OS to save the YMM registers.
  static const bool available = detail::vector_kernels_allowed() &&
                                __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return available;
#else
  return false;
#endif
}

void pack_padded(const double* x, const double* w, std::size_t begin, std::size_t end, PaddedVertex* xw) {
  for (std::size_t i = begin; i < end; ++i) xw[i] = PaddedVertex{x[3 * i], x[3 * i + 1], x[3 * i + 2], w[i]};
}

void unpack_padded(const PaddedVertex* xw, std::size_t begin, std::size_t end, double* x) {
  for (std::size_t i = begin; i < end; ++i) {
    x[3 * i] = xw[i].x;
    x[3 * i + 1] = xw[i].y;
    x[3 * i + 2] = xw[i].z;
  }
}

void pack_padded(const double* x, const double* w, const int* row_vertex, std::size_t begin,
                 std::size_t end, PaddedVertex* xw) {
  for (std::size_t k = begin; k < end; ++k) {
    const std::size_t i = static_cast<std::size_t>(row_vertex[k]);
    xw[k] = PaddedVertex{x[3 * i], x[3 * i + 1], x[3 * i + 2], w[i]};
  }
}

void unpack_padded(const PaddedVertex* xw, const int* row_vertex, std::size_t begin,
                   std::size_t end, double* x) {
  for (std::size_t k = begin; k < end; ++k) {
    const std::size_t i = static_cast<std::size_t>(row_vertex[k]);
    x[3 * i] = xw[k].x;
    x[3 * i + 1] = xw[k].y;
    x[3 * i + 2] = xw[k].z;
  }
}

void project_stvk_membrane_batches(const Stvk& material, const MembraneBatch* batches,
                                   std::size_t count, PaddedVertex* xw,
                                   const ProjectionContext& ctx, double* lambda, BatchIsa isa) {
#if SHELLCONTRACT_BATCH_AVX2
  if (isa == BatchIsa::Auto && batch_avx2_available()) {
    const HeldFpExceptions held;
    if (lambda)
      membrane_batches_avx2<true>(material.mu(), material.lambda(), batches, count, xw, ctx, lambda);
    else
      membrane_batches_avx2<false>(material.mu(), material.lambda(), batches, count, xw, ctx, nullptr);
    return;
  }
#endif
  (void)isa;
  membrane_batches_scalar(material, batches, count, xw, ctx, lambda);
}

void project_isometric_hinge_batches(const IsometricBatch* batches, std::size_t count,
                                     double k_bending, PaddedVertex* xw,
                                     const ProjectionContext& ctx, double* lambda, BatchIsa isa) {
#if SHELLCONTRACT_BATCH_AVX2
  if (isa == BatchIsa::Auto && batch_avx2_available()) {
    const HeldFpExceptions held;
    isometric_batches_avx2(batches, count, k_bending, xw, ctx, lambda);
    return;
  }
#endif
  (void)isa;
  isometric_batches_scalar(batches, count, k_bending, xw, ctx, lambda);
}

}  // namespace shellcontract
