#include "shellcontract/pbd/constraint_batches.hpp"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <tuple>
#include <type_traits>

// The AVX2 path needs GCC's vector operators on __m256d, its target pragma and x86-64 (the
// project's compiler is g++ 12; others get the scalar path).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define SHELLCONTRACT_BATCH_AVX2 1
#include <immintrin.h>
#else
#define SHELLCONTRACT_BATCH_AVX2 0
#endif

namespace shellcontract {
namespace {

void check_colour_offsets(const std::vector<std::size_t>& offsets, std::size_t size) {
  if (offsets.empty() || offsets.front() != 0 || offsets.back() != size ||
      !std::is_sorted(offsets.begin(), offsets.end()))
    throw std::invalid_argument("constraint batches: colour offsets do not cover the records");
}

/// Fills batches colour by colour; fill(batch, lane, record) copies one record's rest data.
/// Padding lanes get lane 0's vertex ids and keep the zero rest data of the value-initialized batch.
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
      // Only the membrane kernel pipelines its loads (loading early did not pay for hinges).
      if constexpr (std::is_same_v<Batch, MembraneBatch>)
        b.same_colour_next = first + BATCH_LANES < end;
      for (int k = 0; k < BATCH_LANES; ++k) {
        const Record& r = records[first + (k < b.count ? k : 0)];
        for (int j = 0; j < N; ++j) b.v[j][k] = r.v[j];
        if (k < b.count) fill(b, k, r);
      }
      out.batches.push_back(b);
    }
    out.offsets.push_back(out.batches.size());
  }
  return out;
}

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

/// One lane through the scalar kernel: its stencil is copied out of xw into a local (x, w) pair
/// (vertices 0..N-1), projected, and copied back, so the arithmetic is the kernel's own.
template <int N, class Project>
void project_lane(PaddedVertex* xw, const int (&v)[N][BATCH_LANES], int k, const ProjectionContext& ctx,
                  Project project) {
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
// Everything from here to pop_options is compiled for AVX2 + FMA and only called after
// batch_avx2_available(). Arithmetic is written with GCC's vector operators on __m256d (what
// the _mm256_add_pd family expands to), so the compiler contracts a * b + c into FMAs.
#pragma GCC push_options
#pragma GCC target("avx2,fma")

using V = __m256d;

#define SC_AVX2_INLINE inline __attribute__((always_inline))

/// Four lanes of a 3-vector: x, y and z of lanes 0..3.
struct V3 {
  V x, y, z;
};

SC_AVX2_INLINE V splat(double a) { return _mm256_set1_pd(a); }
SC_AVX2_INLINE V3 operator-(const V3& a, const V3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
SC_AVX2_INLINE V3 operator*(const V3& a, V s) { return {a.x * s, a.y * s, a.z * s}; }
SC_AVX2_INLINE V3 operator+(const V3& a, const V3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
SC_AVX2_INLINE V dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
/// a where mask is set, else +0 (so that x - masked(d) == x exactly even when d is inf or NaN).
SC_AVX2_INLINE V3 masked(const V3& a, V mask) {
  return {_mm256_and_pd(a.x, mask), _mm256_and_pd(a.y, mask), _mm256_and_pd(a.z, mask)};
}
/// Ordered a > b: false on NaN, like the scalar kernels' !(a > b) guards.
SC_AVX2_INLINE V greater(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }

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
  // program order start later; about 7% faster on bear (BM_MembraneStvkPbdColouredOrder/batched:1).
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

#undef SC_AVX2_INLINE
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
