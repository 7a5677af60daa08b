#include "pbd/constraint_batches.hpp"

#include <algorithm>

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

/// project_membrane for StVK, four lanes at a time; each line mirrors constraint_kernels.hpp.
void membrane_batches_avx2(double mu, double lambda_lame, const MembraneBatch* batches,
                           std::size_t count, PaddedVertex* xw, const ProjectionContext& ctx,
                           double* lambda) {
  const V one = splat(1.0), half = splat(0.5), two = splat(2.0);
  const V vmu = splat(mu), two_mu = splat(2.0 * mu), vlam = splat(lambda_lame);
  const V floor = splat(ctx.energy_floor), tiny = splat(1e-300), at = splat(ctx.alpha_tilde);
  // Software pipelining: the rows of batch b + 1 are loaded before the stores of batch b when
  // the two are of the same colour (same_colour_next: they share no vertex, so the rows read are
  // the same either way), else after them. Loads that follow the previous batch's stores in
  // program order start later; measured faster on bear (BM_MembraneStvkPbdColouredOrder/batched:1,
  // lab/history.md).
  V4 next1, next2, next3;
  auto load_next = [&](const MembraneBatch& c) {
    next1 = gather(xw, c.v[0]), next2 = gather(xw, c.v[1]), next3 = gather(xw, c.v[2]);
  };
  if (count > 0) load_next(batches[0]);
  for (std::size_t b = 0; b < count; ++b) {
    const MembraneBatch& c = batches[b];
    const V4 r1 = next1, r2 = next2, r3 = next3;
    const bool early = b + 1 < count && c.same_colour_next;
    const bool late = b + 1 < count && !c.same_colour_next;
    const V3 &x1 = r1.x, &x2 = r2.x, &x3 = r3.x;
    const V w0 = r1.w, w1 = r2.w, w2 = r3.w;
    const V dm00 = _mm256_load_pd(c.dm00), dm01 = _mm256_load_pd(c.dm01);
    const V dm11 = _mm256_load_pd(c.dm11), area = _mm256_load_pd(c.rest_area);
    // C-form (math-spec 4.4): F = [e1 e2] Dm^-1, C = F^T F, S = 2 mu E + lambda tr(E) I.
    const V3 e1 = x1 - x3, e2 = x2 - x3;
    const V3 f0 = e1 * dm00;
    const V3 f1 = e1 * dm01 + e2 * dm11;
    const V e00 = half * (dot(f0, f0) - one), e11 = half * (dot(f1, f1) - one);
    const V e01 = half * dot(f0, f1);
    const V tr = e00 + e11;
    const V s00 = two_mu * e00 + vlam * tr, s11 = two_mu * e11 + vlam * tr, s01 = two_mu * e01;
    const V psi = vmu * (e00 * e00 + e11 * e11 + two * e01 * e01) + half * vlam * tr * tr;
    const V3 p0 = f0 * s00 + f1 * s01, p1 = f0 * s01 + f1 * s11;  // P3 = F S
    const V3 g0 = (p0 * dm00 + p1 * dm01) * area;                  // Abar P3 Dm^-T
    const V3 g1 = (p1 * dm11) * area;
    const V3 g2 = V3{-g0.x - g1.x, -g0.y - g1.y, -g0.z - g1.z};
    const V E = area * psi;
    const V n0 = dot(g0, g0), n1 = dot(g1, g1), n2 = dot(g2, g2);
    const V G = w0 * n0 + w1 * n1 + w2 * n2;
    // The skips of math-spec 9.1(d), per lane; padding lanes have E = 0.
    const V active = _mm256_and_pd(greater(E, floor * area), greater(G, tiny));
    if (early) load_next(batches[b + 1]);
    if (_mm256_movemask_pd(active) != 0) {
      V sigma;  // dx_i = -sigma w_i g_i
      if (lambda == nullptr) {
        sigma = E / G;
        const V a0 = sigma * w0, a1 = sigma * w1, a2 = sigma * w2;
        const V longest_sq = _mm256_max_pd(_mm256_max_pd(a0 * a0 * n0, a1 * a1 * n1), a2 * a2 * n2);
        const V max_step = _mm256_load_pd(c.max_step);
        const V clamp = greater(longest_sq, max_step * max_step);
        if (_mm256_movemask_pd(_mm256_and_pd(clamp, active)) != 0)  // the clamp is rare
          sigma = _mm256_blendv_pd(sigma, sigma * (max_step / _mm256_sqrt_pd(longest_sq)), clamp);
      } else {
        // XPBD, division-free form of math-spec 9.2 with C = sqrt(2E) (E > 0 on active lanes).
        double* lam = lambda + BATCH_LANES * b;
        const V l = _mm256_loadu_pd(lam);
        const V C = _mm256_sqrt_pd(_mm256_max_pd(two * E, _mm256_setzero_pd()));
        sigma = C * (C + at * l) / (G + at * C * C);
        _mm256_storeu_pd(lam, _mm256_blendv_pd(l, l - C * sigma, active));
      }
      scatter(xw, c.v[0], c.count, x1 - masked(g0 * (sigma * w0), active), w0);
      scatter(xw, c.v[1], c.count, x2 - masked(g1 * (sigma * w1), active), w1);
      scatter(xw, c.v[2], c.count, x3 - masked(g2 * (sigma * w2), active), w2);
    }
    if (late) load_next(batches[b + 1]);
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
    // Every stencil vertex pinned, K = 0 (inactive hinge) or a padding lane: no change.
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
  static const bool available = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
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
    membrane_batches_avx2(material.mu(), material.lambda(), batches, count, xw, ctx, lambda);
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
    isometric_batches_avx2(batches, count, k_bending, xw, ctx, lambda);
    return;
  }
#endif
  (void)isa;
  isometric_batches_scalar(batches, count, k_bending, xw, ctx, lambda);
}

}  // namespace shellcontract
