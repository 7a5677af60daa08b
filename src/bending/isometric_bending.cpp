#include "bending/isometric_bending.hpp"

#include <cmath>

namespace shellcontract {

IsometricBendingRest isometric_bending_rest(const Vec3& x0, const Vec3& x1, const Vec3& x2,
                                            const Vec3& x3, int* clamped) {
  // Interior angles with both vectors pointing away from the common vertex (math-spec 8.1).
  const double c01 = guarded_cotangent(x0 - x1, x2 - x1);  // at x1, face A
  const double c02 = guarded_cotangent(x1 - x0, x2 - x0);  // at x0, face A
  const double c03 = guarded_cotangent(x1 - x0, x3 - x0);  // at x0, face B
  const double c04 = guarded_cotangent(x0 - x1, x3 - x1);  // at x1, face B
  if (clamped)
    for (double c : {c01, c02, c03, c04}) *clamped += std::abs(c) == MAX_COTANGENT ? 1 : 0;
  IsometricBendingRest r;
  r.K << c01 + c04, c02 + c03, -c01 - c02, -c03 - c04;
  r.area_sum = 0.5 * ((x1 - x0).cross(x2 - x0).norm() + (x0 - x1).cross(x3 - x1).norm());
  return r;
}

double isometric_bending_energy(const IsometricBendingRest& r, const Vec3& x0, const Vec3& x1,
                                const Vec3& x2, const Vec3& x3) {
  if (!(r.area_sum > 0.0)) return 0.0;  // both faces degenerate: hinge inactive
  return 1.5 / r.area_sum * isometric_bending_h(r, x0, x1, x2, x3).squaredNorm();
}

std::array<Vec3, 4> isometric_bending_gradient(const IsometricBendingRest& r, const Vec3& x0,
                                               const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  std::array<Vec3, 4> g;
  if (!(r.area_sum > 0.0)) {
    g.fill(Vec3::Zero());
    return g;
  }
  const Vec3 h = isometric_bending_h(r, x0, x1, x2, x3);
  for (int i = 0; i < 4; ++i) g[i] = (3.0 * r.K(i) / r.area_sum) * h;
  return g;
}

}  // namespace shellcontract
