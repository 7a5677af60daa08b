// The CCD's cheap conservative tests in front of the narrow phase (math-spec 10.4, 11): the
// coplanarity cubic and its Bernstein form, the non-penetration filter, swept-box and
// separating-axis culls.
#include <algorithm>
#include <array>
#include <cmath>

#include "collision/ccd.hpp"
#include "collision/ccd/bounds.hpp"

namespace shellcontract {

using namespace ccd_detail;  // NOLINT(google-build-using-namespace): the shared bounds

std::array<double, 4> coplanarity_cubic(CcdPrimitive kind, const CcdStencil& x0,
                                        const CcdStencil& x1) {
  const RelativeVectors r0 = relative_vectors(kind, x0), r1 = relative_vectors(kind, x1);
  const Vec3 &u = r0.u, &v = r0.v, &w = r0.w;
  const Vec3 du = r1.u - r0.u, dv = r1.v - r0.v, dw = r1.w - r0.w;
  return {det3(u, v, w), det3(du, v, w) + det3(u, dv, w) + det3(u, v, dw),
          det3(du, dv, w) + det3(du, v, dw) + det3(u, dv, dw), det3(du, dv, dw)};
}

std::array<double, 4> coplanarity_bernstein(CcdPrimitive kind, const CcdStencil& x0,
                                            const CcdStencil& x1) {
  return bernstein_with_bound(kind, x0, x1).b;
}

std::array<double, 4> tang_bernstein(CcdPrimitive kind, const CcdStencil& x0,
                                     const CcdStencil& x1) {
  const RelativeVectors r0 = relative_vectors(kind, x0), r1 = relative_vectors(kind, x1);
  const Vec3 n0 = r0.u.cross(r0.v), n1 = r1.u.cross(r1.v);
  const Vec3 nhat = 0.5 * (n0 + n1 - (r1.u - r0.u).cross(r1.v - r0.v));
  return {r0.w.dot(n0), (2.0 * r0.w.dot(nhat) + r1.w.dot(n0)) / 3.0,
          (2.0 * r1.w.dot(nhat) + r0.w.dot(n1)) / 3.0, r1.w.dot(n1)};
}

std::array<double, 4> bernstein_from_power(const std::array<double, 4>& c) {
  return {c[0], c[0] + c[1] / 3.0, c[0] + 2.0 * c[1] / 3.0 + c[2] / 3.0, c[0] + c[1] + c[2] + c[3]};
}

bool nonpenetration_filter_culls(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                                 double tolerance, FilterBound bound) {
  for (int k = 0; k < 4; ++k)
    if (!x0[k].allFinite() || !x1[k].allFinite()) return false;
  const RelativeVectors r0 = relative_vectors(kind, x0), r1 = relative_vectors(kind, x1);
  const std::array<double, 4> b = bernstein_coefficients(r0, r1);
  const double err =
      bound == FilterBound::Tight ? tight_error_bound(r0, r1) : coarse_error_bound(r0, r1);
  const double tau = tolerance > 0.0 ? tolerance : 0.0;
  const double tau_term =
      tau > 0.0 ? tau * normal_length_bound(kind, x0, x1) * (1.0 + 4.0 * U) : 0.0;
  return one_sign(b.data(), err + tau_term);
}

bool swept_boxes_apart(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                       double tolerance) {
  // Non-finite input is never culled. x * 0 is NaN for an infinite or NaN x and 0 otherwise, so
  // one sum tests all 24 coordinates (an overflowing sum only makes the test answer "keep").
  double probe = 0.0;
  for (int k = 0; k < 4; ++k) probe += (x0[k].sum() + x1[k].sum()) * 0.0;
  if (!(probe == 0.0)) return false;
  const double tau = tolerance > 0.0 ? tolerance : 0.0;
  // A computed gap g = fl(d) has |g - d| <= u |d|, so g > tau (1 + 4u) (itself rounded by at most
  // one ulp) gives d >= g (1 - u) > tau. For tau = 0 the test is g > 0, whose sign is exact.
  const double limit = tau * (1.0 + 4.0 * U);
  // Primitive A is stencil points [0, split), B is [split, 4).
  const int split = kind == CcdPrimitive::VertexFace ? 1 : 2;
  for (int d = 0; d < 3; ++d) {
    double lo[4], hi[4];
    for (int k = 0; k < 4; ++k) {
      lo[k] = std::min(x0[k][d], x1[k][d]);
      hi[k] = std::max(x0[k][d], x1[k][d]);
    }
    const double alo = split == 1 ? lo[0] : std::min(lo[0], lo[1]);
    const double ahi = split == 1 ? hi[0] : std::max(hi[0], hi[1]);
    const double blo = split == 1 ? std::min({lo[1], lo[2], lo[3]}) : std::min(lo[2], lo[3]);
    const double bhi = split == 1 ? std::max({hi[1], hi[2], hi[3]}) : std::max(hi[2], hi[3]);
    if (blo - ahi > limit || alo - bhi > limit) return true;
  }
  return false;
}

namespace {

/// The separating-axis steps' inputs: the vertex differences at both ends and the gaps for
/// tolerance tau and the largest input coordinate. False (nothing set) for non-finite input.
struct SeparationInput {
  Vec3 da[4], db[4];
  int nd = 0;
  SeparationGaps gaps{};
};

bool separation_input(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                      double tolerance, SeparationInput& in) {
  double M = 0.0;
  for (int k = 0; k < 4; ++k) {
    if (!x0[k].allFinite() || !x1[k].allFinite()) return false;
    M = std::max({M, x0[k].cwiseAbs().maxCoeff(), x1[k].cwiseAbs().maxCoeff()});
  }
  // Steps 2a and 2b of the interval search on I = [0, 1], with the same thresholds: the
  // positions at t = 0 and 1 are the inputs themselves, the midpoint is evaluated as there.
  in.gaps = separation_gaps(tolerance > 0.0 ? tolerance : 0.0, M);
  in.nd = differences(kind, x0, in.da);
  differences(kind, x1, in.db);
  return true;
}

bool direction_step(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                    const SeparationInput& in) {
  CcdStencil xm;
  for (int k = 0; k < 4; ++k) xm[k] = position(x0[k], x1[k], 0.5);
  return direction_separates(in.da, in.db, in.nd, closest_at(kind, xm).direction, in.gaps);
}

}  // namespace

bool separating_axis_culls(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                           double tolerance) {
  SeparationInput in;
  if (!separation_input(kind, x0, x1, tolerance, in)) return false;
  return axes_separate(in.da, in.db, in.nd, in.gaps) || direction_step(kind, x0, x1, in);
}

bool separating_axes_culls(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                           double tolerance) {
  SeparationInput in;
  return separation_input(kind, x0, x1, tolerance, in) &&
         axes_separate(in.da, in.db, in.nd, in.gaps);
}

bool separating_direction_culls(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                                double tolerance) {
  SeparationInput in;
  return separation_input(kind, x0, x1, tolerance, in) && direction_step(kind, x0, x1, in);
}

}  // namespace shellcontract
