// What the batched projections share (constraint_batches.cpp, dihedral_batches.cpp): the batch
// layout's builder, the scalar path's lane-by-lane call, and the AVX2 lanes' loads, stores and
// arithmetic. Private to src/pbd.
#pragma once

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <tuple>
#include <type_traits>
#include <vector>

#include "pbd/constraint_batches.hpp"

// The AVX2 path needs GCC's vector operators on __m256d, its target pragma and x86-64 (the
// project's compiler is g++ 12; others get the scalar path).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define SHELLCONTRACT_BATCH_AVX2 1
#include <immintrin.h>
#else
#define SHELLCONTRACT_BATCH_AVX2 0
#endif

namespace shellcontract {
namespace batch_lanes {

inline void check_colour_offsets(const std::vector<std::size_t>& offsets, std::size_t size) {
  if (offsets.empty() || offsets.front() != 0 || offsets.back() != size ||
      !std::is_sorted(offsets.begin(), offsets.end()))
    throw std::invalid_argument("constraint batches: colour offsets do not cover the records");
}

/// Fills batches colour by colour; fill(batch, lane, record) copies one record's rest data.
/// Padding lanes are copies of lane 0 (its vertex ids and rest data), so that every lane computes
/// what a real constraint does: zero rest data made a padding lane divide 0 by 0 (its result
/// discarded), which a host that traps FE_INVALID took as SIGFPE and any other host found as a
/// sticky FE_INVALID flag. Padding lanes' positions are never written.
template <class Batch, class Record, class Fill>
ColouredBatches<Batch> make_batches(const std::vector<Record>& records,
                                    const std::vector<std::size_t>& colour_offsets, Fill fill) {
  check_colour_offsets(colour_offsets, records.size());
  constexpr int N = static_cast<int>(std::tuple_size<decltype(Record::v)>::value);
  ColouredBatches<Batch> out;
  std::size_t total = 0;
  for (std::size_t c = 0; c + 1 < colour_offsets.size(); ++c)
    total += (colour_offsets[c + 1] - colour_offsets[c] + BATCH_LANES - 1) / BATCH_LANES;
  out.batches.reserve(total);
  for (std::size_t c = 0; c + 1 < colour_offsets.size(); ++c) {
    const std::size_t end = colour_offsets[c + 1];
    for (std::size_t first = colour_offsets[c]; first < end; first += BATCH_LANES) {
      Batch b{};
      b.count = static_cast<int>(std::min<std::size_t>(BATCH_LANES, end - first));
      // The StVK membrane and the dihedral kernels project such pairs together (loading early
      // did not pay for the isometric hinges).
      if constexpr (std::is_same_v<Batch, MembraneBatch> || std::is_same_v<Batch, DihedralBatch>)
        b.same_colour_next = first + BATCH_LANES < end;
      for (int k = 0; k < BATCH_LANES; ++k) {
        const Record& r = records[first + (k < b.count ? k : 0)];
        for (int j = 0; j < N; ++j) b.v[j][k] = r.v[j];
        fill(b, k, r);
      }
      out.batches.push_back(b);
    }
    out.offsets.push_back(out.batches.size());
  }
  return out;
}

/// One lane through the scalar kernel: its stencil is copied out of xw into a local (x, w) pair
/// (vertices 0..N-1), projected, and copied back, so the arithmetic is the kernel's own.
template <int N, class Project>
inline void project_lane(PaddedVertex* xw, const int (&v)[N][BATCH_LANES], int k,
                         const ProjectionContext& ctx, Project project) {
  double x[3 * N], w[N];
  for (int j = 0; j < N; ++j) {
    const PaddedVertex& p = xw[v[j][k]];
    x[3 * j] = p.x, x[3 * j + 1] = p.y, x[3 * j + 2] = p.z;
    w[j] = p.w;
  }
  ProjectionContext local = ctx;
  local.x = x;
  local.w = w;
  project(local);
  for (int j = 0; j < N; ++j) {
    PaddedVertex& p = xw[v[j][k]];
    p.x = x[3 * j], p.y = x[3 * j + 1], p.z = x[3 * j + 2];
  }
}

#if SHELLCONTRACT_BATCH_AVX2
/// While alive, every SSE/AVX floating-point exception is masked and its flags are clear; when it
/// ends, the caller's MXCSR (exception masks, flags, rounding mode) is back as it was. The AVX2
/// kernels compute every lane of a batch and discard the skipped ones (padding lanes, hinges and
/// faces at rest, pinned or unclamped lanes), whose divisions may be 0 / 0 or 1 / 0: a host that
/// traps FE_INVALID or FE_DIVBYZERO (feenableexcept) would take SIGFPE there, and any host would
/// find a flag it did not raise. Holding the exceptions once per call costs nothing measurable;
/// guarding every such division by its lane's mask put the mask's compares in front of each
/// division and slowed the kernels (lab/kernels/fp_hold.md). The dispatchers hold it around a
/// call into the AVX2 code, which is compiled for another target and so never inlined across the
/// two MXCSR writes. The kernels use no x87 instruction, so MXCSR is the whole environment.
class HeldFpExceptions {
 public:
  HeldFpExceptions() : saved_(_mm_getcsr()) { _mm_setcsr((saved_ | MASK_ALL) & ~FLAGS); }
  ~HeldFpExceptions() { _mm_setcsr(saved_); }
  HeldFpExceptions(const HeldFpExceptions&) = delete;
  HeldFpExceptions& operator=(const HeldFpExceptions&) = delete;

 private:
  static constexpr unsigned MASK_ALL = 0x1F80u;  // MXCSR bits 7-12: the six exception masks
  static constexpr unsigned FLAGS = 0x3Fu;       // bits 0-5: the six sticky exception flags
  unsigned saved_;
};

// Everything from here to pop_options is compiled for AVX2 + FMA and only called after
// batch_avx2_available(). Arithmetic is written with GCC's vector operators on __m256d (what
// the _mm256_add_pd family expands to), so the compiler contracts a * b + c into FMAs. A file
// that calls these opens the same target region around its kernels.
#pragma GCC push_options
#pragma GCC target("avx2,fma")
// L3<V> and the lane-generic templates take __m256d as a template argument, whose alignment
// attribute GCC says it ignores there (it keeps the type's own alignment: harmless).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"

using V = __m256d;

#define SC_AVX2_INLINE inline __attribute__((always_inline))

/// A 3-vector of lane vectors T (T = V: four lanes; the dihedral kernel also uses a pair of V).
template <class T>
struct L3 {
  T x, y, z;
};
/// Four lanes of a 3-vector: x, y and z of lanes 0..3.
using V3 = L3<V>;

SC_AVX2_INLINE V splat(double a) { return _mm256_set1_pd(a); }
template <class T>
SC_AVX2_INLINE L3<T> operator-(const L3<T>& a, const L3<T>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class T>
SC_AVX2_INLINE L3<T> operator*(const L3<T>& a, T s) { return {a.x * s, a.y * s, a.z * s}; }
template <class T>
SC_AVX2_INLINE L3<T> operator+(const L3<T>& a, const L3<T>& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class T>
SC_AVX2_INLINE T dot(const L3<T>& a, const L3<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
/// a where mask is set, else +0 (so that x - masked(d) == x exactly even when d is inf or NaN).
SC_AVX2_INLINE V3 masked(const V3& a, V mask) {
  return {_mm256_and_pd(a.x, mask), _mm256_and_pd(a.y, mask), _mm256_and_pd(a.z, mask)};
}
/// Ordered a > b: false on NaN, like the scalar kernels' !(a > b) guards.
SC_AVX2_INLINE V greater(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }

// The operations the lane-generic code (atan2_lanes, the dihedral kernel) uses besides the
// arithmetic operators, for T = V; dihedral_batches.cpp adds them for a pair of V.
template <class T>
SC_AVX2_INLINE T lanes_splat(double a);
template <>
SC_AVX2_INLINE V lanes_splat<V>(double a) { return _mm256_set1_pd(a); }
SC_AVX2_INLINE V vand(V a, V b) { return _mm256_and_pd(a, b); }
SC_AVX2_INLINE V vandnot(V a, V b) { return _mm256_andnot_pd(a, b); }
SC_AVX2_INLINE V vor(V a, V b) { return _mm256_or_pd(a, b); }
SC_AVX2_INLINE V vxor(V a, V b) { return _mm256_xor_pd(a, b); }
SC_AVX2_INLINE V vmin(V a, V b) { return _mm256_min_pd(a, b); }
SC_AVX2_INLINE V vmax(V a, V b) { return _mm256_max_pd(a, b); }
SC_AVX2_INLINE V vsqrt(V a) { return _mm256_sqrt_pd(a); }
/// b where the sign bit of mask is set, else a (_mm256_blendv_pd).
SC_AVX2_INLINE V blend(V a, V b, V mask) { return _mm256_blendv_pd(a, b, mask); }
SC_AVX2_INLINE V cmp_gt(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
SC_AVX2_INLINE V cmp_ge(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_GE_OQ); }
SC_AVX2_INLINE V cmp_le(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
SC_AVX2_INLINE V cmp_eq(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
SC_AVX2_INLINE V cmp_neq_uq(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_NEQ_UQ); }
/// a b - c with one rounding.
SC_AVX2_INLINE V fmsub(V a, V b, V c) { return _mm256_fmsub_pd(a, b, c); }
/// One bit per lane (the lane's sign bit).
SC_AVX2_INLINE int lane_bits(V a) { return _mm256_movemask_pd(a); }

/// Four lanes of a padded vertex: the position and the inverse mass w.
struct V4 {
  V3 x;
  V w;
};

/// Rows xw[v[k]] of the four lanes, transposed to (X, Y, Z, W) registers: four 128-bit loads
/// into the low halves, four into the high halves (lanes 2 and 3), four unpacks.
SC_AVX2_INLINE V4 gather(const PaddedVertex* xw, const int* v) {
  const double* p0 = &xw[v[0]].x;
  const double* p1 = &xw[v[1]].x;
  const double* p2 = &xw[v[2]].x;
  const double* p3 = &xw[v[3]].x;
  const V xy02 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_load_pd(p0)), _mm_load_pd(p2), 1);
  const V xy13 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_load_pd(p1)), _mm_load_pd(p3), 1);
  const V zw02 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_load_pd(p0 + 2)), _mm_load_pd(p2 + 2), 1);
  const V zw13 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_load_pd(p1 + 2)), _mm_load_pd(p3 + 2), 1);
  return {{_mm256_unpacklo_pd(xy02, xy13), _mm256_unpackhi_pd(xy02, xy13), _mm256_unpacklo_pd(zw02, zw13)},
          _mm256_unpackhi_pd(zw02, zw13)};
}

/// Inverse of gather for the first `count` lanes, one aligned 256-bit store per vertex (w is
/// written back unchanged). Padding lanes are never written.
SC_AVX2_INLINE void scatter(PaddedVertex* xw, const int* v, int count, const V3& a, V w) {
  const V xy02 = _mm256_unpacklo_pd(a.x, a.y);  // x0 y0 x2 y2
  const V xy13 = _mm256_unpackhi_pd(a.x, a.y);  // x1 y1 x3 y3
  const V zw02 = _mm256_unpacklo_pd(a.z, w);    // z0 w0 z2 w2
  const V zw13 = _mm256_unpackhi_pd(a.z, w);    // z1 w1 z3 w3
  _mm256_store_pd(&xw[v[0]].x, _mm256_permute2f128_pd(xy02, zw02, 0x20));
  if (count > 1) _mm256_store_pd(&xw[v[1]].x, _mm256_permute2f128_pd(xy13, zw13, 0x20));
  if (count > 2) _mm256_store_pd(&xw[v[2]].x, _mm256_permute2f128_pd(xy02, zw02, 0x31));
  if (count > 3) _mm256_store_pd(&xw[v[3]].x, _mm256_permute2f128_pd(xy13, zw13, 0x31));
}

/// Rows x[3 v[k] .. 3 v[k] + 2] of a 3-stride array (the XPBD hinge multipliers).
SC_AVX2_INLINE V3 gather3(const double* x, const int* v) {
  const double* p0 = x + 3 * static_cast<std::ptrdiff_t>(v[0]);
  const double* p1 = x + 3 * static_cast<std::ptrdiff_t>(v[1]);
  const double* p2 = x + 3 * static_cast<std::ptrdiff_t>(v[2]);
  const double* p3 = x + 3 * static_cast<std::ptrdiff_t>(v[3]);
  const V xy02 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p0)), _mm_loadu_pd(p2), 1);
  const V xy13 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p1)), _mm_loadu_pd(p3), 1);
  const __m128d z01 = _mm_loadh_pd(_mm_load_sd(p0 + 2), p1 + 2);
  const __m128d z23 = _mm_loadh_pd(_mm_load_sd(p2 + 2), p3 + 2);
  return {_mm256_unpacklo_pd(xy02, xy13), _mm256_unpackhi_pd(xy02, xy13),
          _mm256_insertf128_pd(_mm256_castpd128_pd256(z01), z23, 1)};
}

/// Inverse of gather3 (all four rows).
SC_AVX2_INLINE void scatter3(double* x, const int* v, const V3& a) {
  const V xy02 = _mm256_unpacklo_pd(a.x, a.y);
  const V xy13 = _mm256_unpackhi_pd(a.x, a.y);
  const __m128d z01 = _mm256_castpd256_pd128(a.z);
  const __m128d z23 = _mm256_extractf128_pd(a.z, 1);
  double* p0 = x + 3 * static_cast<std::ptrdiff_t>(v[0]);
  double* p1 = x + 3 * static_cast<std::ptrdiff_t>(v[1]);
  double* p2 = x + 3 * static_cast<std::ptrdiff_t>(v[2]);
  double* p3 = x + 3 * static_cast<std::ptrdiff_t>(v[3]);
  _mm_storeu_pd(p0, _mm256_castpd256_pd128(xy02));
  _mm_store_sd(p0 + 2, z01);
  _mm_storeu_pd(p1, _mm256_castpd256_pd128(xy13));
  _mm_storeh_pd(p1 + 2, z01);
  _mm_storeu_pd(p2, _mm256_extractf128_pd(xy02, 1));
  _mm_store_sd(p2 + 2, z23);
  _mm_storeu_pd(p3, _mm256_extractf128_pd(xy13, 1));
  _mm_storeh_pd(p3 + 2, z23);
}

/// Two batches' lanes side by side (eight hinges of one colour): every operation is two 256-bit
/// instructions next to each other, so that the two batches' long dependency chains (the angle's
/// two divisions and its polynomial) overlap instead of waiting in turn for the reorder window.
struct W {
  V a, b;
};
SC_AVX2_INLINE W operator+(W p, W q) { return {p.a + q.a, p.b + q.b}; }
SC_AVX2_INLINE W operator-(W p, W q) { return {p.a - q.a, p.b - q.b}; }
SC_AVX2_INLINE W operator*(W p, W q) { return {p.a * q.a, p.b * q.b}; }
SC_AVX2_INLINE W operator/(W p, W q) { return {p.a / q.a, p.b / q.b}; }
template <>
SC_AVX2_INLINE W lanes_splat<W>(double x) { return {_mm256_set1_pd(x), _mm256_set1_pd(x)}; }
#define SC_W2(name) \
  SC_AVX2_INLINE W name(W p, W q) { return {name(p.a, q.a), name(p.b, q.b)}; }
SC_W2(vand)
SC_W2(vandnot)
SC_W2(vor)
SC_W2(vxor)
SC_W2(vmin)
SC_W2(vmax)
SC_W2(cmp_gt)
SC_W2(cmp_ge)
SC_W2(cmp_le)
SC_W2(cmp_eq)
SC_W2(cmp_neq_uq)
#undef SC_W2
SC_AVX2_INLINE W vsqrt(W p) { return {vsqrt(p.a), vsqrt(p.b)}; }
SC_AVX2_INLINE W blend(W p, W q, W m) { return {blend(p.a, q.a, m.a), blend(p.b, q.b, m.b)}; }
SC_AVX2_INLINE W fmsub(W p, W q, W r) { return {fmsub(p.a, q.a, r.a), fmsub(p.b, q.b, r.b)}; }
SC_AVX2_INLINE int lane_bits(W p) { return lane_bits(p.a) | lane_bits(p.b) << BATCH_LANES; }

/// Two batches of one colour (they share no vertex, so their lanes are independent as a batch's
/// are), their rest data and vertex rows as lanes of W, for the kernels that pair batches
/// (dihedral, StVK membrane: the two dependency chains interleave). A batch without a partner
/// goes through the same code with itself as the second, whose results are dropped: every batch
/// is then computed by the same instructions whether it is paired or not (the two halves of W
/// round alike, a lone V path might contract multiply-adds differently), so the result does not
/// depend on where the threads' chunks cut a colour. Each kernel adds its own write-back.
template <class Batch>
struct BatchPair {
  const Batch* c0;
  const Batch* c1;  ///< of c0's colour, or c0 itself when `second` is false
  bool second;      ///< c1 is a batch of its own (store its results)
  using T = W;
  W load(const double (Batch::*f)[BATCH_LANES]) const {
    return {_mm256_load_pd(c0->*f), _mm256_load_pd(c1->*f)};
  }
  void rows(const PaddedVertex* xw, int j, L3<W>& x, W& w) const {
    const V4 r0 = gather(xw, c0->v[j]), r1 = gather(xw, c1->v[j]);
    x = {{r0.x.x, r1.x.x}, {r0.x.y, r1.x.y}, {r0.x.z, r1.x.z}};
    w = {r0.w, r1.w};
  }
  W load_lambda(const double* lam) const {
    return {_mm256_loadu_pd(lam), _mm256_loadu_pd(second ? lam + BATCH_LANES : lam)};
  }
  void store_lambda(double* lam, W l) const {
    _mm256_storeu_pd(lam, l.a);
    if (second) _mm256_storeu_pd(lam + BATCH_LANES, l.b);
  }
};

/// atan2(y, x) on four lanes, within a few ulp of std::atan2 (tests/pbd/test_lane_math.cpp), so
/// that the dihedral kernel needs no libm call per lane. Branch-free: the quotient
/// t = min(|x|, |y|) / max(|x|, |y|) in [0, 1] is reduced to |u| <= 0.66 by u = (t - 1) / (t + 1)
/// above 0.66 (one division either way: the difference of the two magnitudes is exact there),
/// atan(u) is Cephes' rational approximation (atan.c: P / Q of degrees 4 and 5 in u^2, accurate to
/// about one ulp on |u| <= 0.66), and the octant is put back as
/// |atan2| = k pi/4 + sgn atan(u), k in 0..4 and sgn = +-1 from the swap, the sign of x and the
/// reduction, with k pi/4 as a double plus its rounding error, so that the sum rounds once.
/// Signed zeros as std::atan2: atan2(+-0, -0) = +-pi, atan2(+-0, +0) = +-0. NaN in, NaN out.
template <class T>
SC_AVX2_INLINE T atan2_lanes(T y, T x) {
  const T sign_bit = lanes_splat<T>(-0.0);
  const T zero = lanes_splat<T>(0.0), one = lanes_splat<T>(1.0), two = lanes_splat<T>(2.0);
  const T ax = vandnot(sign_bit, x), ay = vandnot(sign_bit, y);
  const T swap = cmp_gt(ay, ax);
  const T num = vmin(ax, ay), den = vmax(ax, ay);
  // num > 0.66 den: u = (num - den) / (num + den) and atan(t) = pi/4 + atan(u).
  const T upper = cmp_gt(num, lanes_splat<T>(0.66) * den);
  const T top = blend(num, num - den, upper);
  // Both magnitudes zero: u = 0 (atan2(+-0, +-0) is then set by the signs below).
  const T bottom = blend(blend(den, num + den, upper), one, cmp_eq(den, zero));
  const T u = top / bottom;
  const T z = u * u;
  T p = lanes_splat<T>(-8.750608600031904122785e-1);
  p = p * z + lanes_splat<T>(-1.615753718733365076637e1);
  p = p * z + lanes_splat<T>(-7.500855792314704667340e1);
  p = p * z + lanes_splat<T>(-1.228866684490136173410e2);
  p = p * z + lanes_splat<T>(-6.485021904942025371773e1);
  T q = z + lanes_splat<T>(2.485846490142306297962e1);
  q = q * z + lanes_splat<T>(1.650270098316988542046e2);
  q = q * z + lanes_splat<T>(4.328810604912902668951e2);
  q = q * z + lanes_splat<T>(4.853903996359136964868e2);
  q = q * z + lanes_splat<T>(1.945506571482613964425e2);
  const T a = u * z * (p / q) + u;  // atan(u)
  // |atan2| = off + s atan(t) with off = 0, pi/2 or pi and s = -1 where exactly one of swap and
  // x < 0 (or -0) holds; atan(t) = pi/4 + atan(u) on the upper lanes. So k = 2 off / (pi/2) + s
  // upper.
  const T negative_x = blend(zero, cmp_eq(zero, zero), x);  // all ones where x's sign bit is set
  const T flip = vxor(swap, negative_x);
  const T off = blend(blend(zero, two + two, negative_x), two, swap);
  const T k = off + vand(upper, blend(one, zero - one, flip));
  // k pi/4 = hi + lo: hi rounded, lo its rounding error (exact by the FMA) plus k pi4_lo.
  const T pio4_hi = lanes_splat<T>(7.85398163397448278999e-1);
  const T pio4_lo = lanes_splat<T>(3.061616997868382943065e-17);
  const T hi = k * pio4_hi;
  const T lo = fmsub(k, pio4_hi, hi) + k * pio4_lo;
  const T r = hi + (vxor(a, vand(flip, sign_bit)) + lo);
  return vor(r, vand(sign_bit, y));  // r >= 0: the sign of y
}

#pragma GCC diagnostic pop
#pragma GCC pop_options
#endif  // SHELLCONTRACT_BATCH_AVX2

}  // namespace batch_lanes
}  // namespace shellcontract
