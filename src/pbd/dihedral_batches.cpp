// The dihedral hinge (the default bending, math-spec 8.3) projected four hinges of one colour at
// a time, on the padded rows of the coloured order (constraint_batches.hpp).
#include "shellcontract/pbd/constraint_batches.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "pbd/batch_lanes.hpp"

namespace shellcontract {
namespace {

using namespace batch_lanes;  // NOLINT(google-build-using-namespace): the shared lane code

DihedralHingeConstraint lane_record(const DihedralBatch& b, int k) {
  DihedralHingeConstraint c;
  c.v = {b.v[0][k], b.v[1][k], b.v[2][k], b.v[3][k]};
  c.rest.rest_angle = b.rest_angle[k];
  c.rest.kappa = b.kappa[k];
  c.max_step = b.max_step[k];
  return c;
}

void dihedral_batches_scalar(const DihedralBatch* batches, std::size_t count, double k_bending,
                             PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
  for (std::size_t b = 0; b < count; ++b)
    for (int k = 0; k < batches[b].count; ++k) {
      DihedralHingeConstraint c = lane_record(batches[b], k);
      c.v = {0, 1, 2, 3};  // the local stencil of project_lane
      double* lam = lambda ? lambda + BATCH_LANES * b + k : nullptr;
      project_lane<4>(xw, batches[b].v, k, ctx, [&](const ProjectionContext& local) {
        project_dihedral_hinge(c, k_bending, local, lam);
      });
    }
}

#if SHELLCONTRACT_BATCH_AVX2
// Compiled for AVX2 + FMA like the lane code of batch_lanes.hpp (see there).
#pragma GCC push_options
#pragma GCC target("avx2,fma")

SC_AVX2_INLINE V3 cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// a where mask is set, else b.
SC_AVX2_INLINE V3 select(V mask, const V3& a, const V3& b) {
  return {_mm256_blendv_pd(b.x, a.x, mask), _mm256_blendv_pd(b.y, a.y, mask),
          _mm256_blendv_pd(b.z, a.z, mask)};
}
SC_AVX2_INLINE V both(V a, V b) { return _mm256_and_pd(a, b); }
/// -a, the sign bit flipped (as the scalar unary minus).
SC_AVX2_INLINE V neg(V a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
SC_AVX2_INLINE V3 neg(const V3& a) { return {neg(a.x), neg(a.y), neg(a.z)}; }

/// project_dihedral_hinge and dihedral_angle_gradient (dihedral_bending.cpp), four lanes at a
/// time; each line mirrors the scalar one, except that the angle comes from atan2_lanes (a few
/// ulp from std::atan2, which had been four libm calls per batch and most of its time) and that
/// the divisions by |e|, |N_A|^2 and |N_B|^2 are multiplications by one reciprocal each (nine
/// divisions fewer; the results change by rounding only).
void dihedral_batches_avx2(const DihedralBatch* batches, std::size_t count, double k_bending,
                           PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
  constexpr double PI = 3.14159265358979323846;
  const V zero = _mm256_setzero_pd(), one = splat(1.0), two = splat(2.0);
  const V pi = splat(PI), minus_pi = splat(-PI), two_pi = splat(2.0 * PI);
  const V floor_factor = splat(1e-24), tiny = splat(1e-300);
  const V kb = splat(k_bending), at = splat(ctx.alpha_tilde);
  for (std::size_t b = 0; b < count; ++b) {
    const DihedralBatch& c = batches[b];
    // Inactive hinges (kappa = 0) and padding lanes: no change.
    const V kappa = _mm256_load_pd(c.kappa);
    const V live = greater(kappa, zero);
    if (_mm256_movemask_pd(live) == 0) continue;
    V3 xs[4];
    V ws[4];
    for (int j = 0; j < 4; ++j) {
      const V4 r = gather(xw, c.v[j]);
      xs[j] = r.x;
      ws[j] = r.w;
    }
    // The hinge (edge, unnormalized normals) and its collapse test, compared in squares.
    const V3 e = xs[1] - xs[0];
    const V3 NA = cross(e, xs[2] - xs[0]);
    const V3 NB = cross(xs[0] - xs[1], xs[3] - xs[1]);
    const V e_sq = dot(e, e), a_sq = dot(NA, NA), b_sq = dot(NB, NB);
    const V floor_sq = floor_factor * e_sq * e_sq;
    const V ok = both(both(live, greater(e_sq, zero)),
                      both(_mm256_cmp_pd(a_sq, floor_sq, _CMP_GE_OQ),
                           _mm256_cmp_pd(b_sq, floor_sq, _CMP_GE_OQ)));
    if (_mm256_movemask_pd(ok) == 0) continue;
    const V L = _mm256_sqrt_pd(e_sq);
    const V3 e_hat = e * (one / L);
    // theta = atan2((NA x NB) . e_hat, NA . NB).
    const V theta = atan2_lanes(dot(cross(NA, NB), e_hat), dot(NA, NB));
    const V3 aA = NA * (one / a_sq);
    const V3 aB = NB * (one / b_sq);
    V3 g[4];
    g[2] = aA * neg(L);
    g[3] = aB * neg(L);
    g[0] = neg(aA * dot(xs[2] - xs[1], e_hat) + aB * dot(xs[3] - xs[1], e_hat));
    g[1] = aA * dot(xs[2] - xs[0], e_hat) + aB * dot(xs[3] - xs[0], e_hat);
    // wrapped_angle_difference: into (-pi, pi].
    V d = theta - _mm256_load_pd(c.rest_angle);
    d = _mm256_blendv_pd(d, d - two_pi, greater(d, pi));
    d = _mm256_blendv_pd(d, d + two_pi, _mm256_cmp_pd(d, minus_pi, _CMP_LE_OQ));
    V n[4];
    for (int j = 0; j < 4; ++j) n[j] = dot(g[j], g[j]);
    const V wg = ws[0] * n[0] + ws[1] * n[1] + ws[2] * n[2] + ws[3] * n[3];
    // The scalar kernel's !(wg > 1e-300) || d == 0 (a NaN d is not 0: it goes on, as there).
    const V active =
        both(both(ok, greater(wg, tiny)), _mm256_cmp_pd(d, zero, _CMP_NEQ_UQ));
    if (_mm256_movemask_pd(active) == 0) continue;
    const V max_step = _mm256_load_pd(c.max_step);
    // kernel_parts::step_clamp_factor for the step scale * w_j * g_j: max_pd(value, longest)
    // keeps longest where value is NaN, as std::max(longest, value) does. The square root and
    // the division only when a lane clamps (rare).
    auto clamp_factor = [&](V scale) {
      V longest_sq = zero;
      for (int j = 0; j < 4; ++j) {
        const V s = scale * ws[j];
        longest_sq = _mm256_max_pd(s * s * n[j], longest_sq);
      }
      const V clamp = greater(longest_sq, max_step * max_step);
      if (_mm256_movemask_pd(_mm256_and_pd(clamp, active)) == 0) return one;
      return _mm256_blendv_pd(one, max_step / _mm256_sqrt_pd(longest_sq), clamp);
    };
    if (lambda == nullptr) {
      // PBD: dx_j = -k_B d / (2 wg) w_j g_j, clamped (kernel_parts::apply_step).
      V scale = kb * d / (two * wg);
      scale = scale * clamp_factor(scale);
      for (int j = 0; j < 4; ++j)
        scatter(xw, c.v[j], c.count, select(active, xs[j] - g[j] * (scale * ws[j]), xs[j]), ws[j]);
      continue;
    }
    // XPBD: C = sqrt(2 k_B kappa) d.
    double* lam = lambda + BATCH_LANES * b;
    const V l = _mm256_loadu_pd(lam);
    const V root = _mm256_sqrt_pd(two * kb * kappa);
    const V C = root * d;
    V dlam = (neg(C) - at * l) / (root * root * wg + at);
    dlam = dlam * clamp_factor(root * dlam);
    _mm256_storeu_pd(lam, _mm256_blendv_pd(l, l + dlam, active));
    for (int j = 0; j < 4; ++j)
      scatter(xw, c.v[j], c.count, select(active, xs[j] + g[j] * (ws[j] * root * dlam), xs[j]),
              ws[j]);
  }
}

#pragma GCC pop_options
#endif  // SHELLCONTRACT_BATCH_AVX2

}  // namespace

ColouredBatches<DihedralBatch> make_dihedral_batches(
    const std::vector<DihedralHingeConstraint>& records,
    const std::vector<std::size_t>& colour_offsets) {
  return make_batches<DihedralBatch>(records, colour_offsets,
                                     [](DihedralBatch& b, int k, const DihedralHingeConstraint& r) {
                                       b.rest_angle[k] = r.rest.rest_angle;
                                       b.kappa[k] = r.rest.kappa;
                                       b.max_step[k] = r.max_step;
                                     });
}

#if SHELLCONTRACT_BATCH_AVX2
#pragma GCC push_options
#pragma GCC target("avx2,fma")
namespace {
void atan2_avx2(const double* y, const double* x, double* theta, std::size_t n) {
  alignas(32) double ys[BATCH_LANES], xs[BATCH_LANES], out[BATCH_LANES];
  for (std::size_t i = 0; i < n; i += BATCH_LANES) {
    const std::size_t m = std::min<std::size_t>(BATCH_LANES, n - i);
    for (std::size_t k = 0; k < BATCH_LANES; ++k) {
      ys[k] = k < m ? y[i + k] : 0.0;
      xs[k] = k < m ? x[i + k] : 1.0;
    }
    _mm256_store_pd(out, atan2_lanes(_mm256_load_pd(ys), _mm256_load_pd(xs)));
    for (std::size_t k = 0; k < m; ++k) theta[i + k] = out[k];
  }
}
}  // namespace
#pragma GCC pop_options
#endif

bool batch_atan2(const double* y, const double* x, double* theta, std::size_t n) {
#if SHELLCONTRACT_BATCH_AVX2
  if (!batch_avx2_available()) return false;
  atan2_avx2(y, x, theta, n);
  return true;
#else
  (void)y, (void)x, (void)theta, (void)n;
  return false;
#endif
}

void project_dihedral_hinge_batches(const DihedralBatch* batches, std::size_t count,
                                    double k_bending, PaddedVertex* xw,
                                    const ProjectionContext& ctx, double* lambda, BatchIsa isa) {
#if SHELLCONTRACT_BATCH_AVX2
  if (isa == BatchIsa::Auto && batch_avx2_available()) {
    dihedral_batches_avx2(batches, count, k_bending, xw, ctx, lambda);
    return;
  }
#endif
  (void)isa;
  dihedral_batches_scalar(batches, count, k_bending, xw, ctx, lambda);
}

}  // namespace shellcontract
