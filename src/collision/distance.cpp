// Point-triangle and segment-segment closest points (math-spec 10.6).
#include "collision/distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shellcontract {
namespace {

/// Smallest normal double: squared lengths at or below it are treated as zero, so a quotient by
/// them can neither overflow nor be 0/0.
constexpr double TINY = std::numeric_limits<double>::min();

/// Relative threshold of the parallel-edge test |u1 x u2|^2 <= 1e-12 |u1|^2 |u2|^2 (math-spec 10.6).
constexpr double PARALLEL_SIN2 = 1e-12;

double clamp01(double x) { return std::min(1.0, std::max(0.0, x)); }

/// Closest point to p on the union of the three edges of a (possibly degenerate) triangle.
PointTriangleClosest closest_on_edges(const Vec3& p, const Vec3& f0, const Vec3& f1,
                                      const Vec3& f2) {
  PointTriangleClosest best;
  best.distance = std::numeric_limits<double>::infinity();
  const Vec3* f[3] = {&f0, &f1, &f2};
  for (int k = 0; k < 3; ++k) {
    const int l = (k + 1) % 3;
    const double s = point_segment_parameter(p, *f[k], *f[l]);
    const Vec3 q = *f[k] + s * (*f[l] - *f[k]);
    const double d = (p - q).norm();
    if (d < best.distance) {
      best.distance = d;
      best.closest = q;
      best.alpha.setZero();
      best.alpha[k] = 1.0 - s;
      best.alpha[l] = s;
    }
  }
  return best;
}

PointTriangleClosest make_closest(const Vec3& p, const Vec3& f0, const Vec3& f1, const Vec3& f2,
                                  double a0, double a1, double a2) {
  PointTriangleClosest out;
  out.alpha = Vec3(a0, a1, a2);
  out.closest = a0 * f0 + a1 * f1 + a2 * f2;
  out.distance = (p - out.closest).norm();
  return out;
}

}  // namespace

double point_segment_parameter(const Vec3& p, const Vec3& a0, const Vec3& a1) {
  const Vec3 d = a1 - a0;
  const double len2 = d.squaredNorm();
  if (!(len2 > TINY)) return 0.0;  // zero-length segment: its only point
  return clamp01((p - a0).dot(d) / len2);
}

PointTriangleClosest point_triangle_closest(const Vec3& p, const Vec3& f0, const Vec3& f1,
                                            const Vec3& f2) {
  // Ericson, Real-Time Collision Detection, 5.1.5 ClosestPtPointTriangle, with a = f0, b = f1,
  // c = f2. Each region test uses dot products only; the divisions below are guarded because a
  // degenerate triangle can make their denominators 0.
  const Vec3 ab = f1 - f0, ac = f2 - f0, ap = p - f0;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return make_closest(p, f0, f1, f2, 1, 0, 0);  // vertex region f0

  const Vec3 bp = p - f1;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return make_closest(p, f0, f1, f2, 0, 1, 0);  // vertex region f1

  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {  // edge region f0-f1
    const double den = d1 - d3;                // >= 0 here
    const double v = den > TINY ? clamp01(d1 / den) : 0.0;
    return make_closest(p, f0, f1, f2, 1.0 - v, v, 0);
  }

  const Vec3 cp = p - f2;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return make_closest(p, f0, f1, f2, 0, 0, 1);  // vertex region f2

  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {  // edge region f0-f2
    const double den = d2 - d6;
    const double w = den > TINY ? clamp01(d2 / den) : 0.0;
    return make_closest(p, f0, f1, f2, 1.0 - w, 0, w);
  }

  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {  // edge region f1-f2
    const double den = (d4 - d3) + (d5 - d6);
    const double w = den > TINY ? clamp01((d4 - d3) / den) : 0.0;
    return make_closest(p, f0, f1, f2, 0, 1.0 - w, w);
  }

  // Face region. va + vb + vc = |ab x ac|^2 in exact arithmetic (Lagrange identity); for a
  // degenerate or nearly degenerate triangle it is 0 or pure rounding, and the projection is
  // meaningless, so the closest point is searched on the edges instead.
  const double den = va + vb + vc;
  const double scale = ab.squaredNorm() * ac.squaredNorm();
  if (!(den > 1e-14 * scale) || !(den > TINY)) return closest_on_edges(p, f0, f1, f2);
  const double v = vb / den, w = vc / den;
  if (v < 0.0 || w < 0.0 || v + w > 1.0) return closest_on_edges(p, f0, f1, f2);  // rounding
  return make_closest(p, f0, f1, f2, 1.0 - v - w, v, w);
}

double point_triangle_distance(const Vec3& p, const Vec3& f0, const Vec3& f1, const Vec3& f2) {
  return point_triangle_closest(p, f0, f1, f2).distance;
}

SegmentSegmentClosest segment_segment_closest(const Vec3& a0, const Vec3& a1, const Vec3& b0,
                                              const Vec3& b1) {
  // Ericson, Real-Time Collision Detection, 5.1.9 ClosestPtSegmentSegment, with the parallel
  // branch replaced by endpoint projections (math-spec 10.6).
  SegmentSegmentClosest out;
  const Vec3 d1 = a1 - a0, d2 = b1 - b0, r = a0 - b0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (!(a > TINY) && !(e > TINY)) {
    s = t = 0.0;  // both segments are points
  } else if (!(a > TINY)) {
    s = 0.0;
    t = clamp01(f / e);  // e > TINY
  } else {
    const double c = d1.dot(r);
    if (!(e > TINY)) {
      t = 0.0;
      s = clamp01(-c / a);  // a > TINY
    } else {
      const double b = d1.dot(d2);
      // The cross product is more accurate than a e - b^2 for nearly parallel edges.
      const double cross2 = d1.cross(d2).squaredNorm();
      if (cross2 > PARALLEL_SIN2 * a * e) {
        const double denom = a * e - b * b;  // = cross2 > 0 up to rounding
        s = denom > TINY ? clamp01((b * f - c * e) / denom) : 0.0;
        t = (b * s + f) / e;
        if (t < 0.0) {
          t = 0.0;
          s = clamp01(-c / a);
        } else if (t > 1.0) {
          t = 1.0;
          s = clamp01((b - c) / a);
        }
      } else {
        // Parallel: some closest pair has an endpoint on one side; try all four.
        out.parallel = true;
        const double cand[4][2] = {{0.0, point_segment_parameter(a0, b0, b1)},
                                   {1.0, point_segment_parameter(a1, b0, b1)},
                                   {point_segment_parameter(b0, a0, a1), 0.0},
                                   {point_segment_parameter(b1, a0, a1), 1.0}};
        double best = std::numeric_limits<double>::infinity();
        for (const auto& st : cand) {
          const double dist2 = ((a0 + st[0] * d1) - (b0 + st[1] * d2)).squaredNorm();
          if (dist2 < best) {
            best = dist2;
            s = st[0];
            t = st[1];
          }
        }
      }
    }
  }
  out.s = s;
  out.r = t;
  out.closest_a = a0 + s * d1;
  out.closest_b = b0 + t * d2;
  out.distance = (out.closest_a - out.closest_b).norm();
  return out;
}

double segment_segment_distance(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  return segment_segment_closest(a0, a1, b0, b1).distance;
}

}  // namespace shellcontract
