// The region finders at any scale: positions brought near a unit diagonal by a power of two, and
// their results taken back (cap_internal.hpp, finder_exponent).
#include <algorithm>
#include <cmath>

#include "geometry/cap_internal.hpp"

namespace shellcontract::detail {
namespace {

/// A bounding-box diagonal in [2^-FINDER_FREE_EXPONENT, 2^FINDER_FREE_EXPONENT] is left as it is:
/// the finders' squares and cubes of lengths stay far from the double's range there, and every
/// mesh of a usual scale keeps its bits.
constexpr int FINDER_FREE_EXPONENT = 64;

/// A --region-at point farther than this many bounding-box diagonals from the box's centre is
/// taken at this distance, in its direction: its nearest surface point moves by about 1 /
/// REGION_POINT_FAR of the diagonal, and no distance overflows (1e300 used to crash the seed).
constexpr double REGION_POINT_FAR = 1e6;

Vec3 ldexp3(const Vec3& v, int e) { return {std::ldexp(v.x(), e), std::ldexp(v.y(), e), std::ldexp(v.z(), e)}; }

void ldexp_all(Eigen::VectorXd& v, int e) {
  for (double& a : v) a = std::ldexp(a, e);
}

}  // namespace

int finder_exponent(const Positions& x) {
  if (x.rows() == 0 || !x.allFinite()) return 0;
  const Vec3 lo = x.colwise().minCoeff().transpose(), hi = x.colwise().maxCoeff().transpose();
  // The largest side, not the diagonal: it cannot overflow, and it is within sqrt(3) of it.
  const double side = (hi - lo).maxCoeff();
  if (!(side > 0.0) || !std::isfinite(side)) return 0;
  int e = 0;
  std::frexp(side, &e);
  return std::abs(e) <= FINDER_FREE_EXPONENT ? 0 : e;
}

Positions scaled_by_power_of_two(const Positions& x, int k) {
  Positions out(x.rows(), 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (Eigen::Index d = 0; d < 3; ++d) out(i, d) = std::ldexp(x(i, d), -k);
  return out;
}

std::vector<Vec3> scaled_by_power_of_two(const std::vector<Vec3>& points, int k) {
  std::vector<Vec3> out;
  out.reserve(points.size());
  for (const Vec3& p : points) out.push_back(p.allFinite() ? ldexp3(p, -k) : p);
  return out;
}

void unscale_finder_results(int k, RegionReport* report, CurvatureField* curvature) {
  if (report) {
    report->total_area = std::ldexp(report->total_area, 2 * k);
    report->reference_mean_curvature = std::ldexp(report->reference_mean_curvature, -k);
    for (RegionSummary& r : report->regions) {
      r.area = std::ldexp(r.area, 2 * k);
      r.centre = ldexp3(r.centre, k);
      r.radius = std::ldexp(r.radius, k);
      r.mean_curvature = std::ldexp(r.mean_curvature, -k);
    }
  }
  if (curvature) {
    ldexp_all(curvature->mixed_area, 2 * k);
    ldexp_all(curvature->gaussian, -2 * k);
    ldexp_all(curvature->mean, -k);
    ldexp_all(curvature->k_max, -k);
    ldexp_all(curvature->k_min, -k);
  }
}

Vec3 pulled_in(const Vec3& p, const Vec3& centre, double diagonal) {
  Vec3 d = p - centre;
  if (!d.allFinite()) d = 0.5 * p - 0.5 * centre;  // both near the largest double: halved, finite
  const double n = d.stableNorm(), limit = REGION_POINT_FAR * diagonal;
  return n > limit ? Vec3(centre + d * (limit / n)) : p;
}

}  // namespace shellcontract::detail
