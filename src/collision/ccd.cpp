// Conservative CCD narrow phase (math-spec 10.3-10.6, 11).
//
// Method: a 1D inclusion search over the time interval, driven by the coplanarity cubic.
// Each time interval I = [ta, tb] (dyadic, from bisecting [0,1], earliest first) goes through:
//
//  1. Coplanarity cull (Tang et al. 2010, math-spec 10.4, applied on I). The Bernstein
//     coefficients of the cubic f on [0,1] are computed from the end positions (blossom form, no
//     Delta terms) with a rigorous rounding bound, and carried to I by de Casteljau subdivision,
//     which only averages, so it adds at most 4 u max|b| per level (u = 2^-53). If all
//     coefficients are beyond that bound plus tau N (N bounds the normal's length), f keeps one
//     sign on I with |f| > tau N: the points are never coplanar and never within tau of the other
//     primitive's plane/line, so I is excluded. This replaces explicit root finding: the surviving
//     intervals isolate the roots (math-spec 10.5) without Cardano and without dividing by c3, and
//     roots at t = 0 / t = 1, double roots and f == 0 simply make intervals survive.
//  2. Separating-axis cull. For linear motion every relative vector (point minus triangle point,
//     or edge-a point minus edge-b point) over t in I lies in the convex hull of the vertex
//     differences D_k at ta and tb, because it is a bilinear combination of them. So if some
//     direction d has D_k . d > tau |d| for all k (with the rounding bound), the distance stays
//     > tau on I. The axes x, y, z are tried, then the closest-point direction at the midpoint.
//     This is a real geometric test: it excludes the coplanar-for-the-whole-step misses
//     (f == 0, math-spec 10.5 step 2 and 11) and the near misses that cross the plane outside.
//  3. Acceptance. (a) the distance at the midpoint is <= tau + its rounding bound; or (b) a
//     certificate: f changes sign on I (so the points are exactly coplanar at some t* in I) and,
//     seen along one fixed direction n, the point is strictly inside the triangle (VF) or the
//     segments strictly cross (EE) for every t in I; strict orientation signs imply the projection
//     is injective on the common plane, hence a real contact at t*.
//  4. Otherwise bisect, until the interval is 2^-max_depth wide or its relative motion is below
//     rounding; such a leaf is reported as a hit (conservative fallback: floating point cannot
//     decide). A budget on intervals does the same.
//
// Only step 2 and 1 exclude, and both are rigorous, so a true contact is never missed: that is the
// zero-false-negative guarantee. Acceptances need not be rigorous for that; they only decide how
// many near misses within rounding become false positives.
//
// Error model (all inputs are finite doubles; u = 2^-53, gamma_k = k u / (1 - k u)):
//  * a difference of two inputs has relative error <= u per coordinate;
//  * an expression of depth k (k roundings on any path) built from such differences with + - *
//    has absolute error <= gamma_k times the same expression with every term made non-negative
//    (Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed., 3.1 and 3.5);
//  * with M = max |input coordinate|, a position x(t) evaluated by `position` is within 4 u M of
//    the exact one per coordinate (at most three roundings of quantities <= 2M; exact at t = 0, 1).
#include "shellcontract/collision/ccd.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "shellcontract/collision/distance.hpp"

namespace shellcontract {
namespace {

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

RelativeVectors relative_vectors(CcdPrimitive kind, const CcdStencil& x) {
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
std::array<double, 4> bernstein_coefficients(const RelativeVectors& r0, const RelativeVectors& r1) {
  const Vec3 &u0 = r0.u, &v0 = r0.v, &w0 = r0.w, &u1 = r1.u, &v1 = r1.v, &w1 = r1.w;
  return {det3(u0, v0, w0), (det3(u1, v0, w0) + det3(u0, v1, w0) + det3(u0, v0, w1)) / 3.0,
          (det3(u1, v1, w0) + det3(u1, v0, w1) + det3(u0, v1, w1)) / 3.0, det3(u1, v1, w1)};
}

/// The tight rounding bound of bernstein_coefficients (FilterBound::Tight).
double tight_error_bound(const RelativeVectors& r0, const RelativeVectors& r1) {
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

BernsteinBound bernstein_with_bound(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1) {
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
double coarse_error_bound(const RelativeVectors& r0, const RelativeVectors& r1) {
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
double normal_length_bound(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1) {
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

SeparationGaps separation_gaps(double tau, double M) {
  return {(tau + 16.0 * U * M) * (1.0 + 4.0 * U) + UNDERFLOW_FLOOR,
          tau + 48.0 * U * M + UNDERFLOW_FLOOR};
}

/// Step 2a: true if one of the axes x, y, z has every difference at both ends (da, db, nd each)
/// beyond the gap on the same side: the relative vectors, which stay in their convex hull, never
/// come within tau on the interval.
bool axes_separate(const Vec3* da, const Vec3* db, int nd, const SeparationGaps& gaps) {
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
bool direction_separates(const Vec3* da, const Vec3* db, int nd, const Vec3& d,
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
bool crossing_certificate(CcdPrimitive kind, const CcdStencil& xa, const CcdStencil& xb,
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

Closest closest_at(CcdPrimitive kind, const CcdStencil& x) {
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

/// Unit vector of v, or false if |v| is zero (no division by zero).
inline bool unit(const Vec3& v, Vec3& out) {
  const double n = v.norm();
  if (!(n > TINY) || !std::isfinite(n)) return false;
  out = v / n;
  return true;
}

/// Fills the contact data of a hit (math-spec 10.6) at time tc.
void fill_contact(const Query& q, double tc, CcdResult& res) {
  CcdStencil x;
  positions_at(q, tc, x);
  const Closest c = closest_at(q.kind, x);
  res.contact_time = tc;
  res.weights = c.weights;
  const CcdStencil& x0 = *q.x0;
  const CcdStencil& x1 = *q.x1;
  Vec3 n = Vec3::UnitZ();
  bool ok = false;
  if (q.kind == CcdPrimitive::VertexFace) {
    // The unit triangle normal at tc; if the triangle is degenerate there, at t = 0 or 1, then
    // the closest-point direction.
    ok = unit((x[2] - x[1]).cross(x[3] - x[1]), n) ||
         unit((x0[2] - x0[1]).cross(x0[3] - x0[1]), n) ||
         unit((x1[2] - x1[1]).cross(x1[3] - x1[1]), n) || unit(c.direction, n);
  } else {
    const Vec3 ua = x[1] - x[0], ub = x[3] - x[2];
    const Vec3 cr = ua.cross(ub);
    if (cr.squaredNorm() > PARALLEL_SIN2 * ua.squaredNorm() * ub.squaredNorm()) ok = unit(cr, n);
    if (!ok) {  // parallel: closest-point direction at t = 0 (math-spec 10.6), then at tc
      const SegmentSegmentClosest s0 = segment_segment_closest(x0[0], x0[1], x0[2], x0[3]);
      ok = unit(s0.closest_a - s0.closest_b, n) || unit(c.direction, n);
    }
    if (!ok && unit(ua, n)) {  // any unit vector perpendicular to edge a
      const Vec3 axis = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
      ok = unit(n.cross(axis), n);
    }
  }
  if (!ok) n = Vec3::UnitZ();
  res.normal = n;
  // Side at t = 0: sign of n . (sum_k w_k x_k(0)); else against the approach velocity.
  double g0 = 0.0, gv = 0.0;
  for (int k = 0; k < 4; ++k) {
    g0 += res.weights[k] * n.dot(x0[k]);
    gv += res.weights[k] * n.dot(x1[k] - x0[k]);
  }
  res.side = g0 > 0.0 ? 1.0 : g0 < 0.0 ? -1.0 : (gv > 0.0 ? -1.0 : 1.0);
}

struct Interval {
  double ta, tb;
  double b[4];
  double err;  ///< rounding bound of b (without the tau term)
  int depth;
};

/// Refines the start of the first subinterval of `iv` that the coplanarity test cannot exclude:
/// everything before it is proven free, so it is a valid (tighter) time of impact.
double refine_toi(Interval iv, double tau_term, double split_err) {
  for (int it = 0; it < 40; ++it) {
    Interval l = iv, r = iv;
    split_half(iv.b, l.b, r.b);
    const double tm = 0.5 * (iv.ta + iv.tb);
    l.tb = r.ta = tm;
    l.err = r.err = iv.err + split_err;
    if (!one_sign(l.b, l.err + tau_term)) {
      iv = l;
    } else if (!one_sign(r.b, r.err + tau_term)) {
      iv = r;
    } else {
      break;  // both halves excluded: keep the current bound
    }
  }
  return iv.ta;
}

/// Root of the cubic with Bernstein coefficients b on [0,1] that changes sign there (bisection).
double bracketed_root(const double* b) {
  double lo = 0.0, hi = 1.0;
  const bool neg_lo = b[0] < 0.0;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    if ((bernstein_eval(b, mid) < 0.0) == neg_lo) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

/// Blossom B(p1, p2, p3) of the cubic with Bernstein coefficients b on [0,1] (de Casteljau with a
/// different parameter per level). Each level forms (1-p) x + p y with |x|, |y| <= max|b|; with
/// 1 - p rounded, the products and the sum rounded, that is <= 3 u max|b| per level, 9 u max|b|
/// for the three levels, and earlier errors are not amplified (weights >= 0, sum <= 1 + u).
inline double blossom(const double* b, double p1, double p2, double p3) {
  const double r1 = 1.0 - p1, r2 = 1.0 - p2, r3 = 1.0 - p3;
  const double a0 = r1 * b[0] + p1 * b[1], a1 = r1 * b[1] + p1 * b[2], a2 = r1 * b[2] + p1 * b[3];
  const double c0 = r2 * a0 + p2 * a1, c1 = r2 * a1 + p2 * a2;
  return r3 * c0 + p3 * c1;
}

/// Estimate of the root in (0,1) of a cubic with Bernstein coefficients b whose ends have
/// opposite signs: safeguarded Newton on the power form (every iterate stays in the bracket,
/// bisection when Newton leaves it). Not rigorous: the caller verifies the bracket it builds.
double root_estimate(const double* b) {
  const double c0 = b[0], c1 = 3.0 * (b[1] - b[0]), c2 = 3.0 * (b[0] - 2.0 * b[1] + b[2]);
  const double c3 = b[3] - b[0] + 3.0 * (b[1] - b[2]);
  const bool neg_lo = b[0] < 0.0;
  double lo = 0.0, hi = 1.0;
  // Start from the secant of the end values (in (0,1) because they have opposite signs).
  double s = b[0] / (b[0] - b[3]);
  if (!(s > 0.0 && s < 1.0)) s = 0.5;
  for (int it = 0; it < 40; ++it) {
    const double f = ((c3 * s + c2) * s + c1) * s + c0;
    if (f == 0.0) return s;
    if ((f < 0.0) == neg_lo) lo = s;
    else hi = s;
    const double df = (3.0 * c3 * s + 2.0 * c2) * s + c1;
    double next = df != 0.0 ? s - f / df : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - s) < 0x1p-40 || hi - lo < 0x1p-40) return next;
    s = next;
  }
  return s;
}

CcdResult run_ccd(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                  const CcdOptions& options) {
  CcdResult res;
  double M = 0.0;
  bool finite = true;
  for (int k = 0; k < 4; ++k) {
    finite = finite && x0[k].allFinite() && x1[k].allFinite();
    M = std::max({M, x0[k].cwiseAbs().maxCoeff(), x1[k].cwiseAbs().maxCoeff()});
  }
  Query q{kind, &x0, &x1, 0.0, M};
  if (!finite) {
    res.hit = true;
    res.reason = CcdHitReason::NonFiniteInput;
    res.toi = 0.0;
    res.contact_time = 0.0;
    return res;
  }
  const double tau = options.tolerance > 0.0 ? options.tolerance : 0.0;  // NaN or < 0 -> 0
  q.tau = tau;
  const int max_depth = std::min(60, std::max(1, options.max_depth));
  const int max_intervals = std::max(1, options.max_intervals);

  const BernsteinBound bb = bernstein_with_bound(kind, x0, x1);
  const double tau_term = tau > 0.0 ? tau * normal_length_bound(kind, x0, x1) * (1.0 + 4.0 * U) : 0.0;
  const double split_err = 4.0 * U * bb.max_abs;

  // Bounds for the geometric steps (see separation_gaps and crossing_certificate).
  const SeparationGaps gaps = separation_gaps(tau, M);
  // The computed distance is not a certified bound, so it only accepts (never excludes): up to
  // this much above tau it is treated as touching.
  const double dist_slack = 64.0 * U * M;
  // Relative motion: below rounding, bisecting further cannot change any test.
  double motion = 0.0;
  {
    Vec3 d0[4], d1[4];
    const int nd = differences(kind, x0, d0);
    differences(kind, x1, d1);
    for (int k = 0; k < nd; ++k) motion = std::max(motion, (d1[k] - d0[k]).cwiseAbs().maxCoeff());
  }

  Interval stack[2 * 64 + 4];
  int top = 0;
  stack[top++] = Interval{0.0, 1.0, {bb.b[0], bb.b[1], bb.b[2], bb.b[3]}, bb.err, 0};
  CcdStencil xa, xb, xm;
  Closest cm;  // closest points at the midpoint of the last interval tested by `excluded`

  // Steps 1 and 2 on one interval: true if no contact within tau is possible in it (rigorous).
  // Leaves the positions at ta, tb, tm in xa, xb, xm and the closest points at tm in cm.
  auto excluded = [&](const Interval& iv) {
    // 1. Coplanarity cull.
    if (one_sign(iv.b, iv.err + tau_term)) return true;
    // 2a. Separating axes x, y, z over the hull of the differences at ta and tb.
    Vec3 da[4], db[4];
    positions_at(q, iv.ta, xa);
    positions_at(q, iv.tb, xb);
    const int nd = differences(kind, xa, da);
    differences(kind, xb, db);
    if (axes_separate(da, db, nd, gaps)) return true;
    // 2b. Separating axis along the closest-point direction at the midpoint.
    positions_at(q, 0.5 * (iv.ta + iv.tb), xm);
    cm = closest_at(kind, xm);
    return direction_separates(da, db, nd, cm.direction, gaps);
  };

  auto halves = [&](const Interval& iv, Interval& l, Interval& r) {
    l = r = iv;
    split_half(iv.b, l.b, r.b);
    l.tb = r.ta = 0.5 * (iv.ta + iv.tb);
    l.err = r.err = iv.err + split_err;
    l.depth = r.depth = iv.depth + 1;
  };

  bool fast_path_tried = false;
  auto accept = [&](const Interval& iv, CcdHitReason reason, bool certain, double tc) {
    res.hit = true;
    res.certain = certain;
    res.reason = reason;
    // Untightened, the deciding interval's start is the bound (tc >= it): refine_toi's up to 40
    // bisection levels were a fifth of the narrow phase on bear, for a time the response ignores.
    res.toi = options.tighten_toi ? refine_toi(iv, tau_term, split_err) : iv.ta;
    fill_contact(q, std::max(tc, res.toi), res);
    return res;
  };

  while (top > 0) {
    const Interval iv = stack[--top];
    if (++res.intervals > max_intervals)
      return accept(iv, CcdHitReason::Budget, false, 0.5 * (iv.ta + iv.tb));

    if (one_sign(iv.b, iv.err + tau_term)) continue;  // step 1, before the fast path

    // Fast path (tried once per query): if the Bernstein coefficients all have certain signs
    // with exactly one sign change, f has exactly one root t* in I (Descartes' rule for the
    // Bernstein basis), and for tau = 0 only t* can be a contact. Bracket it in a dyadic interval
    // J of width 2^-25 |I| around a Newton estimate, prove the sign change on J with the blossom
    // (error iv.err + 12 u max|b|), and run the crossing certificate on J. J's end times are
    // exact doubles (ta has <= depth bits, the offsets 26 more; depth <= 20 keeps it < 53 bits),
    // so the positions and the Bernstein values refer to the same times. On failure nothing is
    // concluded and the bisection below carries on.
    if (!fast_path_tried && iv.depth <= 20) {
      const double m = iv.err;
      const bool certain_signs = std::abs(iv.b[0]) > m && std::abs(iv.b[1]) > m &&
                                 std::abs(iv.b[2]) > m && std::abs(iv.b[3]) > m;
      const int variations = ((iv.b[0] > 0) != (iv.b[1] > 0)) + ((iv.b[1] > 0) != (iv.b[2] > 0)) +
                             ((iv.b[2] > 0) != (iv.b[3] > 0));
      if (certain_signs && variations == 1) {
        fast_path_tried = true;
        const double s = root_estimate(iv.b);
        const double k = std::floor(s * 0x1p26 + 0.5);
        const double sa = std::max(0.0, (k - 1.0) * 0x1p-26), sb = std::min(1.0, (k + 1.0) * 0x1p-26);
        const double fa = blossom(iv.b, sa, sa, sa), fb = blossom(iv.b, sb, sb, sb);
        const double mj = m + 12.0 * U * bb.max_abs;
        if ((fa > mj && fb < -mj) || (fa < -mj && fb > mj)) {
          const double w = iv.tb - iv.ta;
          const double ja = iv.ta + sa * w, jb = iv.ta + sb * w, jm = iv.ta + s * w;
          positions_at(q, ja, xa);
          positions_at(q, jb, xb);
          positions_at(q, jm, xm);
          const Vec3 n = kind == CcdPrimitive::VertexFace ? (xm[2] - xm[1]).cross(xm[3] - xm[1])
                                                          : (xm[1] - xm[0]).cross(xm[3] - xm[2]);
          if (crossing_certificate(kind, xa, xb, n, M))
            return accept(iv, CcdHitReason::Crossing, true, jm);
        }
      }
    }

    if (excluded(iv)) continue;
    const double tm = 0.5 * (iv.ta + iv.tb);

    // 3a. Distance at the midpoint within tau (+ rounding): a hit. Every time before ta is
    // excluded, but [ta, tm) is not examined yet: unless the contact is already at ta, tighten
    // toi by a greedy descent that keeps the earliest half that cannot be excluded (16 levels).
    if (cm.distance <= tau + dist_slack) {
      const bool certain = cm.distance + 2.0 * dist_slack <= tau;
      positions_at(q, iv.ta, xa);
      const Closest c0 = closest_at(kind, xa);
      if (c0.distance <= tau + dist_slack) return accept(iv, CcdHitReason::Distance, certain, iv.ta);
      // Without tightening, ta itself is the lower bound (every earlier time is excluded).
      double toi = iv.ta;
      if (options.tighten_toi) {
        Interval j, l, r, dummy;
        halves(iv, j, dummy);  // [ta, tm]
        for (int level = 0; level < 16; ++level) {
          halves(j, l, r);
          if (!excluded(l)) {
            j = l;
          } else if (!excluded(r)) {
            j = r;
          } else {
            j.ta = j.tb;  // both excluded: the contact is at the right end, tm
            break;
          }
        }
        toi = j.ta;
      }
      res.hit = true;
      res.certain = certain;
      res.reason = CcdHitReason::Distance;
      res.toi = toi;
      fill_contact(q, tm, res);
      return res;
    }

    // 3b. Certificate: sign change of f on I and a strict inside/crossing configuration.
    const bool sign_change = (iv.b[0] > iv.err && iv.b[3] < -iv.err) ||
                             (iv.b[0] < -iv.err && iv.b[3] > iv.err);
    if (sign_change) {
      const Vec3 n = kind == CcdPrimitive::VertexFace ? (xm[2] - xm[1]).cross(xm[3] - xm[1])
                                                      : (xm[1] - xm[0]).cross(xm[3] - xm[2]);
      if (crossing_certificate(kind, xa, xb, n, M)) {
        const double s = bracketed_root(iv.b);
        return accept(iv, CcdHitReason::Crossing, true, iv.ta + s * (iv.tb - iv.ta));
      }
    }

    // 4. Leaf: conservative hit. Else bisect, earliest half on top.
    if (iv.depth >= max_depth || motion * (iv.tb - iv.ta) <= 8.0 * U * M)
      return accept(iv, CcdHitReason::Undecided, false, tm);
    Interval l, r;
    halves(iv, l, r);
    stack[top++] = r;
    stack[top++] = l;
  }
  return res;  // every interval excluded: proven miss
}

}  // namespace

CcdResult vertex_face_ccd(const CcdStencil& x0, const CcdStencil& x1, const CcdOptions& options) {
  return run_ccd(CcdPrimitive::VertexFace, x0, x1, options);
}

CcdResult edge_edge_ccd(const CcdStencil& x0, const CcdStencil& x1, const CcdOptions& options) {
  return run_ccd(CcdPrimitive::EdgeEdge, x0, x1, options);
}

CcdResult primitive_ccd(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                        const CcdOptions& options) {
  return run_ccd(kind, x0, x1, options);
}

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
  const double tau_term = tau > 0.0 ? tau * normal_length_bound(kind, x0, x1) * (1.0 + 4.0 * U) : 0.0;
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

bool separating_axis_culls(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                           double tolerance) {
  double M = 0.0;
  for (int k = 0; k < 4; ++k) {
    if (!x0[k].allFinite() || !x1[k].allFinite()) return false;
    M = std::max({M, x0[k].cwiseAbs().maxCoeff(), x1[k].cwiseAbs().maxCoeff()});
  }
  // Steps 2a and 2b of the interval search on I = [0, 1], with the same thresholds: the
  // positions at t = 0 and 1 are the inputs themselves, the midpoint is evaluated as there.
  const SeparationGaps gaps = separation_gaps(tolerance > 0.0 ? tolerance : 0.0, M);
  Vec3 da[4], db[4];
  const int nd = differences(kind, x0, da);
  differences(kind, x1, db);
  if (axes_separate(da, db, nd, gaps)) return true;
  CcdStencil xm;
  for (int k = 0; k < 4; ++k) xm[k] = position(x0[k], x1[k], 0.5);
  return direction_separates(da, db, nd, closest_at(kind, xm).direction, gaps);
}

}  // namespace shellcontract
