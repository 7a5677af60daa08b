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
#include "collision/ccd.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "collision/ccd/bounds.hpp"
#include "collision/distance.hpp"

namespace shellcontract {
namespace {

using namespace ccd_detail;  // NOLINT(google-build-using-namespace): this file's own helpers

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
    if ((bernstein_eval(b, mid) < 0.0) == neg_lo)
      lo = mid;
    else
      hi = mid;
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
    if ((f < 0.0) == neg_lo)
      lo = s;
    else
      hi = s;
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
  const double tau_term =
      tau > 0.0 ? tau * normal_length_bound(kind, x0, x1) * (1.0 + 4.0 * U) : 0.0;
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
        const double sa = std::max(0.0, (k - 1.0) * 0x1p-26),
                     sb = std::min(1.0, (k + 1.0) * 0x1p-26);
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
      if (c0.distance <= tau + dist_slack)
        return accept(iv, CcdHitReason::Distance, certain, iv.ta);
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
    const bool sign_change =
        (iv.b[0] > iv.err && iv.b[3] < -iv.err) || (iv.b[0] < -iv.err && iv.b[3] > iv.err);
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

}  // namespace shellcontract
