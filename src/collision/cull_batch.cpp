#include "collision/cull_batch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/kernels.hpp"

// The AVX2 path needs GCC's vector operators on __m256d, its target pragma and x86-64 (as
// pbd/constraint_batches.cpp); other compilers get the scalar functions.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define SHELLCONTRACT_CULL_AVX2 1
#include <immintrin.h>
#else
#define SHELLCONTRACT_CULL_AVX2 0
#endif

namespace shellcontract {
namespace {

/// The scalar path: the functions themselves.
void cull_scalar(CcdPrimitive kind, const double* x0, const double* x1, const std::array<int, 4>* v,
                 int count, double tolerance, std::uint8_t* culled, std::uint8_t* axes) {
  for (int k = 0; k < count; ++k) {
    CcdStencil s0, s1;
    for (int j = 0; j < 4; ++j) {
      const std::ptrdiff_t r = 3 * static_cast<std::ptrdiff_t>(v[k][static_cast<std::size_t>(j)]);
      s0[static_cast<std::size_t>(j)] = Vec3(x0[r], x0[r + 1], x0[r + 2]);
      s1[static_cast<std::size_t>(j)] = Vec3(x1[r], x1[r + 1], x1[r + 2]);
    }
    culled[k] = swept_boxes_apart(kind, s0, s1, tolerance) ||
                nonpenetration_filter_culls(kind, s0, s1, tolerance, FilterBound::Coarse);
    if (axes != nullptr) axes[k] = separating_axes_culls(kind, s0, s1, tolerance);
  }
}

#if SHELLCONTRACT_CULL_AVX2
// AVX2 without FMA, and both files compiled with -ffp-contract=off (CMakeLists.txt): the scalar
// code rounds every product and sum on its own, and so must this, for the answers to be the
// same bit for bit. Every expression below mirrors one in ccd/ (bounds.hpp: relative_vectors,
// det3, bernstein_with_bound, coarse_error_bound, normal_length_bound, one_sign; filters.cpp:
// swept_boxes_apart, separating_axes_culls with separation_gaps, differences and axes_separate)
// and Eigen's evaluation order for 3-vectors (cross: y z - z y, z x - x z, x y - y x; dot and sum:
// (a0 + a1) + a2; norm: sqrt of the squared norm).
#pragma GCC push_options
#pragma GCC target("avx2")

using V = __m256d;
#define SC_CULL_INLINE inline __attribute__((always_inline))

struct V3 {
  V x, y, z;
};

SC_CULL_INLINE V3 operator-(const V3& a, const V3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
SC_CULL_INLINE V vabs(V a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
/// std::max(a, b) = a < b ? b : a, and std::min(a, b) = b < a ? b : a, lane by lane, NaN and
/// signed zeros included (lanes with a non-finite input are masked out at the end anyway).
SC_CULL_INLINE V vmax(V a, V b) { return _mm256_blendv_pd(a, b, _mm256_cmp_pd(a, b, _CMP_LT_OQ)); }
SC_CULL_INLINE V vmin(V a, V b) { return _mm256_blendv_pd(a, b, _mm256_cmp_pd(b, a, _CMP_LT_OQ)); }

SC_CULL_INLINE V dot(const V3& a, const V3& b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
SC_CULL_INLINE V3 cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
SC_CULL_INLINE V det3(const V3& a, const V3& b, const V3& c) { return dot(cross(a, b), c); }
SC_CULL_INLINE V inf_norm(const V3& a) { return vmax(vmax(vabs(a.x), vabs(a.y)), vabs(a.z)); }
SC_CULL_INLINE V one_norm(const V3& a) { return (vabs(a.x) + vabs(a.y)) + vabs(a.z); }
SC_CULL_INLINE V norm(const V3& a) { return _mm256_sqrt_pd(dot(a, a)); }

/// Point j of the four stencils at one time, lanes 0..3: one load per lane of the point's x, y, z
/// (the fourth element masked off, so the last vertex's row never reads past the array), then a
/// 4 x 3 transpose. Moves the same doubles as scalar loads would, without the store-to-load
/// forwarding stalls of assembling vectors through memory.
SC_CULL_INLINE V3 load_point(const double* x, const std::array<int, 4>* v, int count, int j) {
  const __m256i xyz = _mm256_set_epi64x(0, -1, -1, -1);
  V r[4];
  for (int k = 0; k < 4; ++k) {
    // Lanes past count repeat lane 0 (their answers are not written).
    const std::ptrdiff_t row =
        3 * static_cast<std::ptrdiff_t>(v[k < count ? k : 0][static_cast<std::size_t>(j)]);
    r[k] = _mm256_maskload_pd(x + row, xyz);
  }
  const V t0 = _mm256_unpacklo_pd(r[0], r[1]);  // x0 x1 z0 z1
  const V t1 = _mm256_unpackhi_pd(r[0], r[1]);  // y0 y1 .  .
  const V t2 = _mm256_unpacklo_pd(r[2], r[3]);  // x2 x3 z2 z3
  const V t3 = _mm256_unpackhi_pd(r[2], r[3]);  // y2 y3 .  .
  return {_mm256_permute2f128_pd(t0, t2, 0x20), _mm256_permute2f128_pd(t1, t3, 0x20),
          _mm256_permute2f128_pd(t0, t2, 0x31)};
}

void cull_avx2(CcdPrimitive kind, const double* x0, const double* x1, const std::array<int, 4>* v,
               int count, double tolerance, std::uint8_t* culled, std::uint8_t* axes) {
  constexpr double U = std::numeric_limits<double>::epsilon() / 2.0;
  constexpr double UNDERFLOW_FLOOR = 1e-300;  // as ccd/bounds.hpp
  V3 p0[4], p1[4];
  for (int j = 0; j < 4; ++j) {
    p0[j] = load_point(x0, v, count, j);
    p1[j] = load_point(x1, v, count, j);
  }
  const V zero = _mm256_setzero_pd();
  // swept_boxes_apart's finiteness probe: sum over k of (x0[k].sum() + x1[k].sum()) * 0.
  V probe = zero;
  for (int k = 0; k < 4; ++k) {
    const V s0 = (p0[k].x + p0[k].y) + p0[k].z, s1 = (p1[k].x + p1[k].y) + p1[k].z;
    probe = probe + (s0 + s1) * zero;
  }
  // The box test's probe is 0 iff no sum overflowed and every coordinate is finite; the filter
  // asks only the latter (allFinite: x - x == 0 exactly for finite x).
  const V box_ok = _mm256_cmp_pd(probe, zero, _CMP_EQ_OQ);
  V all_finite = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  for (int k = 0; k < 4; ++k)
    for (const V3* p : {&p0[k], &p1[k]})
      all_finite = _mm256_and_pd(
          all_finite, _mm256_and_pd(_mm256_cmp_pd(p->x - p->x, zero, _CMP_EQ_OQ),
                                    _mm256_and_pd(_mm256_cmp_pd(p->y - p->y, zero, _CMP_EQ_OQ),
                                                  _mm256_cmp_pd(p->z - p->z, zero, _CMP_EQ_OQ))));
  const double tau = tolerance > 0.0 ? tolerance : 0.0;
  // Box cull (swept_boxes_apart): A = points [0, split), B = [split, 4).
  const V limit = _mm256_set1_pd(tau * (1.0 + 4.0 * U));
  const bool vf = kind == CcdPrimitive::VertexFace;
  V apart = zero;
  for (int d = 0; d < 3; ++d) {
    V lo[4], hi[4];
    for (int k = 0; k < 4; ++k) {
      const V a = d == 0 ? p0[k].x : d == 1 ? p0[k].y : p0[k].z;
      const V c = d == 0 ? p1[k].x : d == 1 ? p1[k].y : p1[k].z;
      lo[k] = vmin(a, c);
      hi[k] = vmax(a, c);
    }
    // std::min({a, b, c}) keeps the first of equal minima: min(min(a, b), c) in that order.
    const V alo = vf ? lo[0] : vmin(lo[0], lo[1]);
    const V ahi = vf ? hi[0] : vmax(hi[0], hi[1]);
    const V blo = vf ? vmin(vmin(lo[1], lo[2]), lo[3]) : vmin(lo[2], lo[3]);
    const V bhi = vf ? vmax(vmax(hi[1], hi[2]), hi[3]) : vmax(hi[2], hi[3]);
    apart = _mm256_or_pd(apart, _mm256_or_pd(_mm256_cmp_pd(blo - ahi, limit, _CMP_GT_OQ),
                                             _mm256_cmp_pd(alo - bhi, limit, _CMP_GT_OQ)));
  }
  // Non-penetration filter (bernstein_with_bound, normal_length_bound, one_sign).
  const int o = vf ? 1 : 0, a = vf ? 2 : 1, b = vf ? 3 : 2, c = vf ? 0 : 3;
  const V3 u0 = p0[a] - p0[o], v0 = p0[b] - p0[o], w0 = p0[c] - p0[o];
  const V3 u1 = p1[a] - p1[o], v1 = p1[b] - p1[o], w1 = p1[c] - p1[o];
  const V three = _mm256_set1_pd(3.0);
  const V b0 = det3(u0, v0, w0);
  const V b1 = ((det3(u1, v0, w0) + det3(u0, v1, w0)) + det3(u0, v0, w1)) / three;
  const V b2 = ((det3(u1, v1, w0) + det3(u1, v0, w1)) + det3(u0, v1, w1)) / three;
  const V b3 = det3(u1, v1, w1);
  // coarse_error_bound (FilterBound::Coarse): 16 u (mu mv) (mw + mw).
  const V mu = vmax(inf_norm(u0), inf_norm(u1)), mv = vmax(inf_norm(v0), inf_norm(v1));
  const V mw = vmax(one_norm(w0), one_norm(w1));
  const V mag = (mu * mv) * (mw + mw);
  const V err = _mm256_set1_pd(16.0 * U) * mag + _mm256_set1_pd(UNDERFLOW_FLOOR);
  V m = err;
  if (tau > 0.0) {
    // VF: |f1 - f0| and |f2 - f0| (u and v); EE: |a1 - a0| (u) and |b1 - b0|.
    const V la = vmax(norm(p0[a] - p0[o]), norm(p1[a] - p1[o]));
    const V lb = vf ? vmax(norm(p0[3] - p0[1]), norm(p1[3] - p1[1]))
                    : vmax(norm(p0[3] - p0[2]), norm(p1[3] - p1[2]));
    const V nlb = la * lb * _mm256_set1_pd(1.0 + 16.0 * U);
    m = err + _mm256_set1_pd(tau) * nlb * _mm256_set1_pd(1.0 + 4.0 * U);
  }
  const V neg = zero - m;
  const V all_above = _mm256_and_pd(
      _mm256_and_pd(_mm256_cmp_pd(b0, m, _CMP_GT_OQ), _mm256_cmp_pd(b1, m, _CMP_GT_OQ)),
      _mm256_and_pd(_mm256_cmp_pd(b2, m, _CMP_GT_OQ), _mm256_cmp_pd(b3, m, _CMP_GT_OQ)));
  const V all_below = _mm256_and_pd(
      _mm256_and_pd(_mm256_cmp_pd(b0, neg, _CMP_LT_OQ), _mm256_cmp_pd(b1, neg, _CMP_LT_OQ)),
      _mm256_and_pd(_mm256_cmp_pd(b2, neg, _CMP_LT_OQ), _mm256_cmp_pd(b3, neg, _CMP_LT_OQ)));
  const V cull = _mm256_or_pd(_mm256_and_pd(box_ok, apart),
                              _mm256_and_pd(all_finite, _mm256_or_pd(all_above, all_below)));
  const int bits = _mm256_movemask_pd(cull);
  for (int k = 0; k < count; ++k) culled[k] = static_cast<std::uint8_t>((bits >> k) & 1);
  if (axes == nullptr) return;
  // separating_axes_culls: M = the largest |coordinate| (max is exact: any order gives it),
  // separation_gaps' axis gap, the vertex differences (VF: p - f_i; EE: a_i - b_j) at both ends.
  V M = zero;
  for (int k = 0; k < 4; ++k) M = vmax(M, vmax(inf_norm(p0[k]), inf_norm(p1[k])));
  const V gap =
      (_mm256_set1_pd(tau) + _mm256_set1_pd(16.0 * U) * M) * _mm256_set1_pd(1.0 + 4.0 * U) +
      _mm256_set1_pd(UNDERFLOW_FLOOR);
  const V neg_gap = zero - gap;
  V3 d[8];
  int nd = 0;
  for (const V3* p : {p0, p1}) {
    if (vf) {
      for (int j = 1; j < 4; ++j) d[nd++] = p[0] - p[j];
    } else {
      for (int i = 0; i < 2; ++i)
        for (int j = 2; j < 4; ++j) d[nd++] = p[i] - p[j];
    }
  }
  V separated = zero;
  for (int ax = 0; ax < 3; ++ax) {
    auto coordinate = [ax](const V3& q) { return ax == 0 ? q.x : ax == 1 ? q.y : q.z; };
    V lo = coordinate(d[0]), hi = lo;
    for (int k = 1; k < nd; ++k) {
      lo = vmin(lo, coordinate(d[k]));
      hi = vmax(hi, coordinate(d[k]));
    }
    separated = _mm256_or_pd(separated, _mm256_or_pd(_mm256_cmp_pd(lo, gap, _CMP_GT_OQ),
                                                     _mm256_cmp_pd(hi, neg_gap, _CMP_LT_OQ)));
  }
  const int axis_bits = _mm256_movemask_pd(_mm256_and_pd(all_finite, separated));
  for (int k = 0; k < count; ++k) axes[k] = static_cast<std::uint8_t>((axis_bits >> k) & 1);
}

#undef SC_CULL_INLINE
#pragma GCC pop_options
#endif  // SHELLCONTRACT_CULL_AVX2

}  // namespace

bool cull_batch_avx2_available() {
#if SHELLCONTRACT_CULL_AVX2
  static const bool available = detail::vector_kernels_allowed() && __builtin_cpu_supports("avx2");
  return available;
#else
  return false;
#endif
}

void cull_batch(CcdPrimitive kind, const double* x0, const double* x1,
                const std::array<int, 4>* v, int count, double tolerance, std::uint8_t* culled,
                [[maybe_unused]] CullIsa isa, std::uint8_t* axes) {
  count = std::clamp(count, 0, CULL_LANES);
  if (count == 0) return;
#if SHELLCONTRACT_CULL_AVX2
  if (isa == CullIsa::Auto && cull_batch_avx2_available()) {
    cull_avx2(kind, x0, x1, v, count, tolerance, culled, axes);
    return;
  }
#endif
  cull_scalar(kind, x0, x1, v, count, tolerance, culled, axes);
}

}  // namespace shellcontract
