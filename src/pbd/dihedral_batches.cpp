// The dihedral hinge (the default bending, math-spec 8.3) projected four hinges of one colour at
// a time, on the padded rows of the coloured order (constraint_batches.hpp).
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "core/constants.hpp"
#include "pbd/batch_lanes.hpp"
#include "pbd/constraint_batches.hpp"

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
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"  // as in batch_lanes.hpp


template <class T>
SC_AVX2_INLINE L3<T> cross(const L3<T>& a, const L3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// a where mask is set, else b.
template <class T>
SC_AVX2_INLINE L3<T> select(T mask, const L3<T>& a, const L3<T>& b) {
  return {blend(b.x, a.x, mask), blend(b.y, a.y, mask), blend(b.z, a.z, mask)};
}
/// -a, the sign bit flipped (as the scalar unary minus).
template <class T>
SC_AVX2_INLINE T neg(T a) { return vxor(a, lanes_splat<T>(-0.0)); }
template <class T>
SC_AVX2_INLINE L3<T> neg(const L3<T>& a) { return {neg(a.x), neg(a.y), neg(a.z)}; }

/// A pair of batches (BatchPair) written back with their w, as gather read them.
struct TwoBatches : BatchPair<DihedralBatch> {
  void store(PaddedVertex* xw, int j, const L3<W>& x, W w) const {
    scatter(xw, c0->v[j], c0->count, V3{x.x.a, x.y.a, x.z.a}, w.a);
    if (second) scatter(xw, c1->v[j], c1->count, V3{x.x.b, x.y.b, x.z.b}, w.b);
  }
};

/// project_dihedral_hinge and dihedral_angle_gradient (dihedral_bending.cpp) on the lanes of two
/// batches (see TwoBatches); each line mirrors the scalar one, except that the
/// angle comes from atan2_lanes (a few ulp from std::atan2, which had been four libm calls per
/// batch and most of its time) and that the divisions by |e|, |N_A|^2 and |N_B|^2 are
/// multiplications by reciprocals taken from one division (eight divisions fewer). The results
/// change by rounding only.
/// @param lam  XPBD: the batches' multipliers (lambda + 4 b), else nullptr
template <class Batches>
SC_AVX2_INLINE void dihedral_lanes(const Batches& c, PaddedVertex* xw, double k_bending,
                                   double alpha_tilde, double* lam) {
  using T = typename Batches::T;
  const T zero = lanes_splat<T>(0.0), one = lanes_splat<T>(1.0), two = lanes_splat<T>(2.0);
  // Inactive hinges (kappa = 0): no change. Lanes that are not `ok` or not `active` divide
  // freely, their results discarded (HeldFpExceptions).
  const T kappa = c.load(&DihedralBatch::kappa);
  const T live = cmp_gt(kappa, zero);
  if (lane_bits(live) == 0) return;
  L3<T> xs[4];
  T ws[4];
  for (int j = 0; j < 4; ++j) c.rows(xw, j, xs[j], ws[j]);
  // The hinge (edge, unnormalized normals) and its collapse test, compared in squares.
  const L3<T> e = xs[1] - xs[0];
  const L3<T> NA = cross(e, xs[2] - xs[0]);
  const L3<T> NB = cross(xs[0] - xs[1], xs[3] - xs[1]);
  const T e_sq = dot(e, e), a_sq = dot(NA, NA), b_sq = dot(NB, NB);
  const T floor_sq = lanes_splat<T>(1e-24) * e_sq * e_sq;
  const T ok = vand(vand(live, cmp_gt(e_sq, zero)), vand(cmp_ge(a_sq, floor_sq), cmp_ge(b_sq, floor_sq)));
  if (lane_bits(ok) == 0) return;
  const T L = vsqrt(e_sq);
  // 1 / L, 1 / |N_A|^2 and 1 / |N_B|^2 from one division by their product, unless that
  // product leaves [1e-290, 1e290] on a lane (edges far from the normalized mesh's unit scale).
  const T ab = a_sq * b_sq;
  const T product = L * ab;
  T inv_L, inv_a, inv_b;
  const T in_range = vand(cmp_ge(product, lanes_splat<T>(1e-290)), cmp_le(product, lanes_splat<T>(1e290)));
  if (lane_bits(vandnot(in_range, ok)) == 0) {
    const T inv = one / product;
    inv_L = ab * inv;
    inv_a = (L * b_sq) * inv;
    inv_b = (L * a_sq) * inv;
  } else {
    inv_L = one / L;
    inv_a = one / a_sq;
    inv_b = one / b_sq;
  }
  const L3<T> e_hat = e * inv_L;
  // theta = atan2((NA x NB) . e_hat, NA . NB).
  const T theta = atan2_lanes(dot(cross(NA, NB), e_hat), dot(NA, NB));
  const L3<T> aA = NA * inv_a;
  const L3<T> aB = NB * inv_b;
  L3<T> g[4];
  g[2] = aA * neg(L);
  g[3] = aB * neg(L);
  g[0] = neg(aA * dot(xs[2] - xs[1], e_hat) + aB * dot(xs[3] - xs[1], e_hat));
  g[1] = aA * dot(xs[2] - xs[0], e_hat) + aB * dot(xs[3] - xs[0], e_hat);
  // wrapped_angle_difference: into (-pi, pi].
  T d = theta - c.load(&DihedralBatch::rest_angle);
  d = blend(d, d - lanes_splat<T>(2.0 * PI), cmp_gt(d, lanes_splat<T>(PI)));
  d = blend(d, d + lanes_splat<T>(2.0 * PI), cmp_le(d, lanes_splat<T>(-PI)));
  T n[4];
  for (int j = 0; j < 4; ++j) n[j] = dot(g[j], g[j]);
  const T wg = ws[0] * n[0] + ws[1] * n[1] + ws[2] * n[2] + ws[3] * n[3];
  // The scalar kernel's !(wg > 1e-300) || d == 0 (a NaN d is not 0: it goes on, as there).
  const T active = vand(vand(ok, cmp_gt(wg, lanes_splat<T>(1e-300))), cmp_neq_uq(d, zero));
  if (lane_bits(active) == 0) return;
  const T max_step = c.load(&DihedralBatch::max_step);
  // kernel_parts::step_clamp_factor for the step scale * w_j * g_j: max(value, longest) keeps
  // longest where value is NaN, as std::max(longest, value) does. The square root and the
  // division only when a lane clamps (rare).
  auto clamp_factor = [&](T scale) {
    T longest_sq = zero;
    for (int j = 0; j < 4; ++j) {
      const T s = scale * ws[j];
      longest_sq = vmax(s * s * n[j], longest_sq);
    }
    const T clamp = cmp_gt(longest_sq, max_step * max_step);
    if (lane_bits(vand(clamp, active)) == 0) return one;
    return blend(one, max_step / vsqrt(longest_sq), clamp);
  };
  const T kb = lanes_splat<T>(k_bending);
  if (lam == nullptr) {
    // PBD: dx_j = -k_B d / (2 wg) w_j g_j, clamped (kernel_parts::apply_step).
    T scale = kb * d / (two * wg);
    scale = scale * clamp_factor(scale);
    for (int j = 0; j < 4; ++j) c.store(xw, j, select(active, xs[j] - g[j] * (scale * ws[j]), xs[j]), ws[j]);
    return;
  }
  // XPBD: C = sqrt(2 k_B kappa) d.
  const T at = lanes_splat<T>(alpha_tilde);
  const T l = c.load_lambda(lam);
  const T root = vsqrt(two * kb * kappa);
  const T C = root * d;
  T dlam = (neg(C) - at * l) / (root * root * wg + at);
  dlam = dlam * clamp_factor(root * dlam);
  c.store_lambda(lam, blend(l, l + dlam, active));
  for (int j = 0; j < 4; ++j)
    c.store(xw, j, select(active, xs[j] + g[j] * (ws[j] * root * dlam), xs[j]), ws[j]);
}

/// Batches in pairs where two consecutive ones are of one colour (they share no vertex, so the
/// pair's lanes are independent as a batch's are), else one at a time (see TwoBatches).
void dihedral_batches_avx2(const DihedralBatch* batches, std::size_t count, double k_bending,
                           PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
  std::size_t b = 0;
  while (b < count) {
    double* lam = lambda ? lambda + BATCH_LANES * b : nullptr;
    const bool pair = b + 1 < count && batches[b].same_colour_next;
    dihedral_lanes(TwoBatches{{batches + b, batches + (pair ? b + 1 : b), pair}}, xw, k_bending,
                   ctx.alpha_tilde, lam);
    b += pair ? 2 : 1;
  }
}

#pragma GCC diagnostic pop
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
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"  // as in batch_lanes.hpp
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
#pragma GCC diagnostic pop
#pragma GCC pop_options
#endif

bool batch_atan2(const double* y, const double* x, double* theta, std::size_t n) {
#if SHELLCONTRACT_BATCH_AVX2
  if (!batch_avx2_available()) return false;
  const HeldFpExceptions held;
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
    const HeldFpExceptions held;
    dihedral_batches_avx2(batches, count, k_bending, xw, ctx, lambda);
    return;
  }
#endif
  (void)isa;
  dihedral_batches_scalar(batches, count, k_bending, xw, ctx, lambda);
}

}  // namespace shellcontract
