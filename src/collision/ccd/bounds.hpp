// The CCD's shared arithmetic: rounding bounds, the coplanarity cubic's Bernstein form and its
// subdivision, the separating-axis and crossing tests, closest points. Private to the narrow
// phase (ccd.cpp) and its filters (filters.cpp), both compiled with -ffp-contract=off (see
// CMakeLists.txt; cull_batch.cpp repeats these roundings lane by lane). The error model is
// described at the top of ccd.cpp.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "collision/ccd.hpp"
#include "collision/distance.hpp"

namespace shellcontract {
namespace ccd_detail {

/// Unit roundoff of double.
constexpr double U = std::numeric_limits<double>::epsilon() / 2.0;
/// Smallest normal double; squared lengths at or below it count as zero.
constexpr double TINY = std::numeric_limits<double>::min();
/// Parallel-edge threshold of math-spec 10.6 (on sin^2 of the angle).
constexpr double PARALLEL_SIN2 = 1e-12;
/// Absolute term added to every rounding bound. The relative model (gamma_k) fails only when
/// results underflow, where each operation can add an absolute error up to 2^-1075; a few dozen
/// operations stay far below 1e-300, and no realistic geometry comes near it.
constexpr double UNDERFLOW_FLOOR = 1e-300;

/// The three vectors of math-spec 10.3, relative to one stencil point.
struct RelativeVectors {
  Vec3 u, v, w;
};

inline RelativeVectors relative_vectors(CcdPrimitive kind, const CcdStencil& x) {
  if (kind == CcdPrimitive::VertexFace) return {x[2] - x[1], x[3] - x[1], x[0] - x[1]};
  return {x[1] - x[0], x[2] - x[0], x[3] - x[0]};
}

inline double det3(const Vec3& a, const Vec3& b, const Vec3& c) { return a.cross(b).dot(c); }

/// det3 with every product made non-negative: the magnitude that bounds its rounding error.
inline double det3_abs(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 A = a.cwiseAbs(), B = b.cwiseAbs(), C = c.cwiseAbs();
  return C.x() * (A.y() * B.z() + A.z() * B.y()) + C.y() * (A.z() * B.x() + A.x() * B.z()) +
         C.z() * (A.x() * B.y() + A.y() * B.x());
}

/// Bernstein coefficients of f on [0,1] and a bound on |computed - exact| for each of them.
struct BernsteinBound {
  std::array<double, 4> b{};
  double err = 0.0;      ///< max_k |b_k computed - b_k exact|
  double max_abs = 0.0;  ///< max_k |b_k computed|
};

/// The Bernstein coefficients of f on [0,1] from the relative vectors at t = 0 and t = 1.
inline std::array<double, 4> bernstein_coefficients(const RelativeVectors& r0,
                                                    const RelativeVectors& r1) {
  const Vec3 &u0 = r0.u, &v0 = r0.v, &w0 = r0.w, &u1 = r1.u, &v1 = r1.v, &w1 = r1.w;
  return {det3(u0, v0, w0), (det3(u1, v0, w0) + det3(u0, v1, w0) + det3(u0, v0, w1)) / 3.0,
          (det3(u1, v1, w0) + det3(u1, v0, w1) + det3(u0, v1, w1)) / 3.0, det3(u1, v1, w1)};
}

/// The tight rounding bound of bernstein_coefficients (FilterBound::Tight).
inline double tight_error_bound(const RelativeVectors& r0, const RelativeVectors& r1) {
  const Vec3 &u0 = r0.u, &v0 = r0.v, &w0 = r0.w, &u1 = r1.u, &v1 = r1.v, &w1 = r1.w;
  // Rounding depth: 3 input differences (1 each, relative) + product + cross subtraction + product
  // with the third factor + 2 dot-product sums = 8 for one det; + 2 for the sum of three dets + 1
  // for /3 = 11. The computed magnitude itself is low by at most a factor (1 - gamma_11), so
  // 16 u times it is a safe bound (gamma_11 / (1 - gamma_11) < 11.01 u).
  double a = std::max(det3_abs(u0, v0, w0), det3_abs(u1, v1, w1));
  a = std::max(a, (det3_abs(u1, v0, w0) + det3_abs(u0, v1, w0) + det3_abs(u0, v0, w1)) / 3.0);
  a = std::max(a, (det3_abs(u1, v1, w0) + det3_abs(u1, v0, w1) + det3_abs(u0, v1, w1)) / 3.0);
  return 16.0 * U * a + UNDERFLOW_FLOOR;
}

inline BernsteinBound bernstein_with_bound(CcdPrimitive kind, const CcdStencil& x0,
                                           const CcdStencil& x1) {
  const RelativeVectors r0 = relative_vectors(kind, x0), r1 = relative_vectors(kind, x1);
  BernsteinBound out;
  out.b = bernstein_coefficients(r0, r1);
  out.err = tight_error_bound(r0, r1);
  for (double b : out.b) out.max_abs = std::max(out.max_abs, std::abs(b));
  return out;
}

/// The coarse rounding bound of bernstein_coefficients (FilterBound::Coarse), from the computed
/// relative vectors alone. Every det3_abs(x, y, z) = sum_i |z_i| (|x_j| |y_k| + |x_k| |y_j|) is at
/// most 2 |x|_inf |y|_inf |z|_1, and an average of three is at most its largest term, so the
/// magnitude a of tight_error_bound is at most 2 mu mv mw with mu = max(|u0|_inf, |u1|_inf),
/// mv likewise, mw = max(|w0|_1, |w1|_1). Computed, mw is low by at most (1 - gamma_2) and the
/// two products add two roundings (the doubling is exact), so the result c satisfies
/// c >= (1 - gamma_4) a, and 16 u c >= gamma_11 a, the error the tight bound covers.
inline double coarse_error_bound(const RelativeVectors& r0, const RelativeVectors& r1) {
  auto inf_norm = [](const Vec3& a) {
    return std::max(std::max(std::abs(a.x()), std::abs(a.y())), std::abs(a.z()));
  };
  // Summed as cull_batch sums it: (|x| + |y|) + |z|.
  auto one_norm = [](const Vec3& a) {
    return (std::abs(a.x()) + std::abs(a.y())) + std::abs(a.z());
  };
  const double mu = std::max(inf_norm(r0.u), inf_norm(r1.u));
  const double mv = std::max(inf_norm(r0.v), inf_norm(r1.v));
  const double mw = std::max(one_norm(r0.w), one_norm(r1.w));
  return 16.0 * U * ((mu * mv) * (mw + mw)) + UNDERFLOW_FLOOR;
}

/// Upper bound, over t in [0,1], of the length of the normal whose dot product with a point
/// offset is f: VF |u x v| <= |u||v|, so point-to-plane distance = |f| / |u x v| >= |f| / N;
/// EE f = ((a1-a0) x (b1-b0)) . (a0-b0) up to sign, so line-line distance >= |f| / N with
/// N = max|a1-a0| max|b1-b0|. Lengths of linear vectors are maximal at an end (convexity).
inline double normal_length_bound(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1) {
  double la, lb;
  if (kind == CcdPrimitive::VertexFace) {
    la = std::max((x0[2] - x0[1]).norm(), (x1[2] - x1[1]).norm());
    lb = std::max((x0[3] - x0[1]).norm(), (x1[3] - x1[1]).norm());
  } else {
    la = std::max((x0[1] - x0[0]).norm(), (x1[1] - x1[0]).norm());
    lb = std::max((x0[3] - x0[2]).norm(), (x1[3] - x1[2]).norm());
  }
  // Differences and norms carry a few relative roundings each; 16 u covers them.
  return la * lb * (1.0 + 16.0 * U);
}

/// True if all four coefficients are > m or all are < -m.
inline bool one_sign(const double* b, double m) {
  return (b[0] > m && b[1] > m && b[2] > m && b[3] > m) ||
         (b[0] < -m && b[1] < -m && b[2] < -m && b[3] < -m);
}

/// de Casteljau split of a cubic's Bernstein coefficients at the middle. Every new value is an
/// average of two old ones, so the rounding added per level is <= 3 u max|b| (three averages on
/// the longest path), and old errors are not amplified.
inline void split_half(const double* b, double* left, double* right) {
  const double l1 = 0.5 * (b[0] + b[1]), m = 0.5 * (b[1] + b[2]), r2 = 0.5 * (b[2] + b[3]);
  const double l2 = 0.5 * (l1 + m), r1 = 0.5 * (m + r2);
  const double mid = 0.5 * (l2 + r1);
  left[0] = b[0];
  left[1] = l1;
  left[2] = l2;
  left[3] = mid;
  right[0] = mid;
  right[1] = r1;
  right[2] = r2;
  right[3] = b[3];
}

/// Bernstein cubic on [0,1] evaluated at s (de Casteljau).
inline double bernstein_eval(const double* b, double s) {
  const double r = 1.0 - s;
  const double a0 = r * b[0] + s * b[1], a1 = r * b[1] + s * b[2], a2 = r * b[2] + s * b[3];
  const double c0 = r * a0 + s * a1, c1 = r * a1 + s * a2;
  return r * c0 + s * c1;
}

/// Position at time t, exact at t = 0 and t = 1. Within 4 u M per coordinate of the exact value
/// (M = max |coordinate| of a and b): b - a, the product and the sum round once each, on values
/// <= 2M, M/2... and M; for t > 1/2 the form b - (1-t)(b-a) keeps the multiplier <= 1/2, and
/// 1 - t is exact there (Sterbenz).
inline Vec3 position(const Vec3& a, const Vec3& b, double t) {
  if (t <= 0.5) return a + t * (b - a);
  return b - (1.0 - t) * (b - a);
}

/// The query data shared by the steps below.
struct Query {
  CcdPrimitive kind;
  const CcdStencil* x0;
  const CcdStencil* x1;
  double tau;
  double M;  ///< max |input coordinate|
};

inline void positions_at(const Query& q, double t, CcdStencil& out) {
  for (int k = 0; k < 4; ++k) out[k] = position((*q.x0)[k], (*q.x1)[k], t);
}

/// Vertex differences whose convex hull contains every relative vector at one time:
/// VF p - f_i (3), EE a_i - b_j (4). Returns the count.
inline int differences(CcdPrimitive kind, const CcdStencil& x, Vec3* d) {
  if (kind == CcdPrimitive::VertexFace) {
    d[0] = x[0] - x[1];
    d[1] = x[0] - x[2];
    d[2] = x[0] - x[3];
    return 3;
  }
  d[0] = x[0] - x[2];
  d[1] = x[0] - x[3];
  d[2] = x[1] - x[2];
  d[3] = x[1] - x[3];
  return 4;
}

/// Rounding-aware thresholds of the separating-axis steps (2a, 2b) for tolerance tau and
/// M = max |input coordinate|:
///  * a difference vector D of computed positions is within 12 u M per coordinate of the exact
///    one (two positions at 4 u M, one subtraction of values <= 2M), so its dot product with any
///    d is within 12 sqrt3 u M |d| + gamma_3 2 sqrt3 M |d| < 32 u M |d| of the exact value; 48
///    leaves room for the rounding of the threshold itself (`direction`, times |d|);
///  * one coordinate of D: 12 u M, used for the axis tests (16 with room; `axis`).
struct SeparationGaps {
  double axis;
  double direction;
};

inline SeparationGaps separation_gaps(double tau, double M) {
  return {(tau + 16.0 * U * M) * (1.0 + 4.0 * U) + UNDERFLOW_FLOOR,
          tau + 48.0 * U * M + UNDERFLOW_FLOOR};
}

/// Step 2a: true if one of the axes x, y, z has every difference at both ends (da, db, nd each)
/// beyond the gap on the same side: the relative vectors, which stay in their convex hull, never
/// come within tau on the interval.
inline bool axes_separate(const Vec3* da, const Vec3* db, int nd, const SeparationGaps& gaps) {
  for (int ax = 0; ax < 3; ++ax) {
    double lo = da[0][ax], hi = da[0][ax];
    for (int k = 0; k < nd; ++k) {
      lo = std::min({lo, da[k][ax], db[k][ax]});
      hi = std::max({hi, da[k][ax], db[k][ax]});
    }
    if (lo > gaps.axis || hi < -gaps.axis) return true;
  }
  return false;
}

/// Step 2b: true if every difference at both ends has a dot product with d above the gap times
/// |d| (false for d = 0).
inline bool direction_separates(const Vec3* da, const Vec3* db, int nd, const Vec3& d,
                                const SeparationGaps& gaps) {
  const double dn = d.norm();
  if (!(dn > 0.0)) return false;
  double smin = std::numeric_limits<double>::infinity();
  for (int k = 0; k < nd; ++k) smin = std::min({smin, da[k].dot(d), db[k].dot(d)});
  return smin > gaps.direction * dn * (1.0 + 8.0 * U);
}

/// Sign of h(t) = det(e(t), r(t), n) on an interval where e, r are linear with end values
/// (ea, ra) and (eb, rb): +1 if its three Bernstein coefficients are all > err, -1 if all < -err,
/// else 0 (undecided). The middle coefficient is the blossom (det(ea,rb,n) + det(eb,ra,n)) / 2.
inline int quadratic_sign(const Vec3& ea, const Vec3& ra, const Vec3& eb, const Vec3& rb,
                          const Vec3& n, double err) {
  const Vec3 ran = ra.cross(n), rbn = rb.cross(n);
  const double h0 = ea.dot(ran), h2 = eb.dot(rbn);
  const double h1 = 0.5 * (ea.dot(rbn) + eb.dot(ran));
  if (h0 > err && h1 > err && h2 > err) return 1;
  if (h0 < -err && h1 < -err && h2 < -err) return -1;
  return 0;
}

/// The contact certificate of step 3(b), for the positions xa at ta and xb at tb, seen along n.
///
/// Error bound of one det(e, r, n) with e, r differences of computed positions (each coordinate
/// within 4 u M, so each coordinate of e, r within 8 u M + u 2M <= 12 u M; |e|, |r| <= 2 sqrt3 M):
/// perturbation 2 * (sqrt3 12 u M)(2 sqrt3 M)|n| = 144 u M^2 |n|, rounding gamma_5 times the
/// magnitude <= 5.01 u * 8 M^2 |n|_1 <= 70 u M^2 |n|; the blossom average adds ~12 u M^2 |n|.
/// 320 u M^2 |n| bounds all of it.
inline bool crossing_certificate(CcdPrimitive kind, const CcdStencil& xa, const CcdStencil& xb,
                                 const Vec3& n, double M) {
  const double nn = n.norm();
  if (!(nn > 0.0)) return false;
  const double err = 320.0 * U * M * M * nn * (1.0 + 1e-9) + UNDERFLOW_FLOOR;
  if (kind == CcdPrimitive::VertexFace) {
    int s[3];
    for (int i = 0; i < 3; ++i) {
      const int k = 1 + i, l = 1 + (i + 1) % 3;
      s[i] = quadratic_sign(xa[l] - xa[k], xa[0] - xa[k], xb[l] - xb[k], xb[0] - xb[k], n, err);
      if (s[i] == 0) return false;
    }
    return s[0] == s[1] && s[1] == s[2];
  }
  // EE: b0 and b1 strictly on opposite sides of line a, and a0, a1 of line b (projected along n).
  const int oc = quadratic_sign(xa[1] - xa[0], xa[2] - xa[0], xb[1] - xb[0], xb[2] - xb[0], n, err);
  if (oc == 0) return false;
  const int od = quadratic_sign(xa[1] - xa[0], xa[3] - xa[0], xb[1] - xb[0], xb[3] - xb[0], n, err);
  if (od != -oc) return false;
  const int oa = quadratic_sign(xa[3] - xa[2], xa[0] - xa[2], xb[3] - xb[2], xb[0] - xb[2], n, err);
  if (oa == 0) return false;
  const int ob = quadratic_sign(xa[3] - xa[2], xa[1] - xa[2], xb[3] - xb[2], xb[1] - xb[2], n, err);
  return ob == -oa;
}

/// Closest-point data of a stencil at one time: distance, the direction from the other
/// primitive's closest point (VF: from the triangle to p; EE: from edge b to edge a), weights.
struct Closest {
  double distance = 0.0;
  Vec3 direction = Vec3::Zero();
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();
};

inline Closest closest_at(CcdPrimitive kind, const CcdStencil& x) {
  Closest c;
  if (kind == CcdPrimitive::VertexFace) {
    const PointTriangleClosest pt = point_triangle_closest(x[0], x[1], x[2], x[3]);
    c.distance = pt.distance;
    c.direction = x[0] - pt.closest;
    c.weights = Eigen::Vector4d(1.0, -pt.alpha[0], -pt.alpha[1], -pt.alpha[2]);
  } else {
    const SegmentSegmentClosest ss = segment_segment_closest(x[0], x[1], x[2], x[3]);
    c.distance = ss.distance;
    c.direction = ss.closest_a - ss.closest_b;
    c.weights = Eigen::Vector4d(1.0 - ss.s, ss.s, -(1.0 - ss.r), -ss.r);
  }
  return c;
}

}  // namespace ccd_detail
}  // namespace shellcontract
