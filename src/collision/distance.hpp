// Closest points and distances between the CCD primitives (math-spec 10.6): point-triangle and
// segment-segment. Eigen only (house-style.md section 1, dependency rule).
//
// Both functions accept degenerate primitives (a triangle collapsed to a segment or a point, a
// segment collapsed to a point) and never divide by a quantity that can be zero.
#pragma once

#include "shellcontract/types.hpp"

namespace shellcontract {

/// Closest point of a triangle to a point.
struct PointTriangleClosest {
  /// Barycentric weights (alpha0, alpha1, alpha2) of the closest point q = sum_k alpha_k f_k;
  /// each in [0, 1], summing to 1 (math-spec 10.6, "clamped barycentrics").
  Vec3 alpha = Vec3(1.0, 0.0, 0.0);
  Vec3 closest = Vec3::Zero();  ///< q, same units as the inputs
  double distance = 0.0;        ///< |p - q|, same units as the inputs
};

/// Closest points of two segments.
struct SegmentSegmentClosest {
  double s = 0.0;                ///< parameter on segment a: point a0 + s (a1 - a0), s in [0, 1]
  double r = 0.0;                ///< parameter on segment b: point b0 + r (b1 - b0), r in [0, 1]
  Vec3 closest_a = Vec3::Zero();  ///< closest point on segment a
  Vec3 closest_b = Vec3::Zero();  ///< closest point on segment b
  double distance = 0.0;         ///< |closest_a - closest_b|
  bool parallel = false;         ///< true if the parallel (endpoint projection) branch was taken
};

/// Closest point of a segment to a point, as the clamped parameter on the segment.
/// @param p   the point, any length unit
/// @param a0  segment start, same unit
/// @param a1  segment end, same unit
/// @return s in [0, 1] such that a0 + s (a1 - a0) is a closest point; 0 for a zero-length segment
double point_segment_parameter(const Vec3& p, const Vec3& a0, const Vec3& a1);

/// Closest point on the triangle (f0, f1, f2) to p, found with the Voronoi-region tests of
/// Ericson, Real-Time Collision Detection, section 5.1.5 (vertex regions, then edge regions,
/// then the face), i.e. clamped barycentrics with region tests (math-spec 10.6).
/// @param p   the query point, any length unit
/// @param f0  first triangle vertex, same unit (vertex order does not matter)
/// @param f1  second triangle vertex
/// @param f2  third triangle vertex
/// @return the barycentric weights of the closest point, the point, and the distance
/// \note A degenerate triangle (zero area) is handled as the union of its three edges.
PointTriangleClosest point_triangle_closest(const Vec3& p, const Vec3& f0, const Vec3& f1,
                                            const Vec3& f2);

/// Distance between a point and a triangle (see point_triangle_closest).
/// @return |p - q| >= 0 in the input units
double point_triangle_distance(const Vec3& p, const Vec3& f0, const Vec3& f1, const Vec3& f2);

/// Closest points between the segments a0-a1 and b0-b1, parameters clamped to [0, 1]
/// (Ericson section 5.1.9). The edges are treated as parallel when
/// |u1 x u2|^2 <= 1e-12 |u1|^2 |u2|^2 (math-spec 10.6); then the closest pair is the best of the
/// four endpoint-to-segment projections, which is exact for parallel segments.
/// @param a0  start of segment a, any length unit
/// @param a1  end of segment a, same unit
/// @param b0  start of segment b
/// @param b1  end of segment b
/// @return parameters, closest points and the distance
/// \note Zero-length segments are handled as points.
SegmentSegmentClosest segment_segment_closest(const Vec3& a0, const Vec3& a1, const Vec3& b0,
                                              const Vec3& b1);

/// Distance between two segments (see segment_segment_closest).
/// @return the distance >= 0 in the input units
double segment_segment_distance(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1);

}  // namespace shellcontract
