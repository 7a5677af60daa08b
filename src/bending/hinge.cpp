#include "bending/hinge.hpp"

#include <algorithm>

namespace shellcontract {

double guarded_cotangent(const Vec3& u, const Vec3& v) {
  const double cross = u.cross(v).norm();
  const double floor = 1e-12 * u.norm() * v.norm();
  const double denom = std::max(cross, floor);
  if (!(denom > 0.0)) return 0.0;  // a zero-length edge: no angle, no weight
  return std::clamp(u.dot(v) / denom, -MAX_COTANGENT, MAX_COTANGENT);
}

}  // namespace shellcontract
