#include "fem/triangle_element.hpp"

namespace shellcontract {

TriangleRest triangle_rest(const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  TriangleRest r;
  const Vec3 E1 = x1 - x3;
  const Vec3 E2 = x2 - x3;
  const Vec3 N = E1.cross(E2);
  const double l1 = E1.norm();
  const double l2 = E2.norm();
  const double l3 = (x2 - x1).norm();
  const double lbar = (l1 + l2 + l3) / 3.0;
  const double twice_area = N.norm();
  r.area = 0.5 * twice_area;
  r.min_edge = std::min(l1, std::min(l2, l3));
  // Degenerate (math-spec 11): Dm would be singular. lbar = 0 also lands here.
  if (!(twice_area >= ZERO_AREA_RATIO * lbar * lbar) || twice_area <= 0.0 || l1 <= 0.0) {
    r.degenerate = true;
    return r;
  }
  r.degenerate = false;
  r.T1 = E1 / l1;
  r.T2 = (N / twice_area).cross(r.T1);
  Mat2 Dm;
  Dm << l1, E2.dot(r.T1), 0.0, E2.dot(r.T2);
  // Upper triangular with det = 2 Abar > 0: invert in closed form.
  const double det = Dm(0, 0) * Dm(1, 1);
  r.Dm_inv << Dm(1, 1) / det, -Dm(0, 1) / det, 0.0, Dm(0, 0) / det;
  return r;
}

}  // namespace shellcontract
