// Helpers of the CCD narrow-phase tests (test_ccd.cpp, test_ccd_filters.cpp): a stencil's
// motion printed, interpolated, and its distance and coplanarity triple product evaluated
// directly at one time (the independent answers the tests compare with).
#pragma once

#include <array>
#include <sstream>
#include <string>

#include "collision/ccd.hpp"
#include "collision/distance.hpp"

namespace shellcontract::test {

inline std::string describe(const CcdStencil& x0, const CcdStencil& x1) {
  std::ostringstream o;
  o.precision(17);
  for (int k = 0; k < 4; ++k)
    o << "\n  x" << k << ": (" << x0[k].transpose() << ") -> (" << x1[k].transpose() << ")";
  return o.str();
}

inline CcdStencil lerp(const CcdStencil& x0, const CcdStencil& x1, double t) {
  CcdStencil x;
  for (int k = 0; k < 4; ++k) x[k] = x0[k] + t * (x1[k] - x0[k]);
  return x;
}

/// Distance of the stencil at one time, computed directly.
inline double distance_at(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1, double t) {
  const CcdStencil x = lerp(x0, x1, t);
  return kind == CcdPrimitive::VertexFace ? point_triangle_distance(x[0], x[1], x[2], x[3])
                                          : segment_segment_distance(x[0], x[1], x[2], x[3]);
}

/// The coplanarity triple product of math-spec 10.3 evaluated directly at time t.
inline double triple_product_at(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1, double t) {
  const CcdStencil x = lerp(x0, x1, t);
  if (kind == CcdPrimitive::VertexFace)
    return (x[2] - x[1]).cross(x[3] - x[1]).dot(x[0] - x[1]);
  return (x[1] - x[0]).cross(x[2] - x[0]).dot(x[3] - x[0]);
}

inline double power_eval(const std::array<double, 4>& c, double t) {
  return ((c[3] * t + c[2]) * t + c[1]) * t + c[0];
}

inline const CcdPrimitive KINDS[] = {CcdPrimitive::VertexFace, CcdPrimitive::EdgeEdge};

}  // namespace shellcontract::test
