// The region finders at any scale: their report taken back from positions brought near a unit
// size by a power of two (curvature.hpp, detail::finder_exponent), and far --region-at points.
#include <algorithm>
#include <cmath>

#include "core/power_of_two.hpp"
#include "geometry/cap_internal.hpp"

namespace shellcontract::detail {
namespace {

/// A --region-at point farther than this many bounding-box diagonals from the box's centre is
/// taken at this distance, in its direction: its nearest surface point moves by about 1 /
/// REGION_POINT_FAR of the diagonal, and no distance overflows (1e300 used to crash the seed).
constexpr double REGION_POINT_FAR = 1e6;

}  // namespace

std::vector<Vec3> scaled_by_power_of_two(const std::vector<Vec3>& points, int k) {
  std::vector<Vec3> out;
  out.reserve(points.size());
  for (const Vec3& p : points) out.push_back(p.allFinite() ? Vec3(times_power_of_two(p, -k)) : p);
  return out;
}

void unscale_finder_results(int k, RegionReport* report, CurvatureField* curvature) {
  if (report) {
    report->total_area = std::ldexp(report->total_area, 2 * k);
    report->reference_mean_curvature = std::ldexp(report->reference_mean_curvature, -k);
    for (RegionSummary& r : report->regions) {
      r.area = std::ldexp(r.area, 2 * k);
      r.centre = times_power_of_two(r.centre, k);
      r.radius = std::ldexp(r.radius, k);
      r.mean_curvature = std::ldexp(r.mean_curvature, -k);
    }
    for (RegionPoint& p : report->points) {
      p.surface_point = times_power_of_two(p.surface_point, k);
      p.distance = std::ldexp(p.distance, k);
    }
  }
  if (curvature) unscale_curvature(k, *curvature);
}

Vec3 pulled_in(const Vec3& p, const Vec3& centre, double diagonal) {
  Vec3 d = p - centre;
  if (!d.allFinite()) d = 0.5 * p - 0.5 * centre;  // half the offset, the same direction
  // The offset's length as n 2^e, n in [0.5, 2): it may exceed the largest double (a point at
  // 1e308 on every axis), where its norm would be infinite and the point would fall onto the
  // centre.
  const double largest = d.cwiseAbs().maxCoeff();
  if (!(largest > 0.0)) return p;
  const int e = binary_exponent(largest);
  const Vec3 u = times_power_of_two(d, -e);
  const double n = u.norm(), limit = REGION_POINT_FAR * diagonal;
  return std::ldexp(n, e) > limit ? Vec3(centre + u * (limit / n)) : p;
}

std::vector<Vec3> pulled_in(const std::vector<Vec3>& points, const Positions& x) {
  if (x.rows() == 0) return points;
  const Vec3 lo = x.colwise().minCoeff().transpose(), hi = x.colwise().maxCoeff().transpose();
  const Vec3 centre = 0.5 * lo + 0.5 * hi;
  const double diagonal = (hi - lo).stableNorm();
  std::vector<Vec3> out;
  out.reserve(points.size());
  for (const Vec3& p : points) out.push_back(p.allFinite() ? pulled_in(p, centre, diagonal) : p);
  return out;
}

}  // namespace shellcontract::detail
