// Isometric bending (Bergou et al. 2006 as implemented by Bender et al. 2014; paper section 3.2,
// math-spec 8.1-8.2). Flat rest state: E_B(x) = 3/(2(A0+A1)) |h|^2 with h = sum_i K_i x_i, where
// K and the rest areas A0, A1 are computed once from the rest mesh. Stencil order: hinge.hpp.
//
// \note Curved rest states are NOT rest states of this model: E_B(xbar) > 0 on every non-flat
// hinge, so it pulls each hinge toward flat (math-spec 8.2, 12 item 3).
#pragma once

#include <Eigen/Core>

#include "bending/hinge.hpp"

namespace shellcontract {

/// Rest data of one isometric-bending hinge.
struct IsometricBendingRest {
  Eigen::Vector4d K = Eigen::Vector4d::Zero();  ///< cotangent weights, sum K = 0
  double area_sum = 0.0;                        ///< A0 + A1 (rest areas of the two faces)
};

/// Computes K and A0 + A1 from the rest positions (math-spec 8.1, interior angles).
/// @param clamped  if not null, incremented once per rest cotangent that was clamped to
///                 +-cot(1 degree) (an angle below 1 or above 179 degrees, math-spec 11)
IsometricBendingRest isometric_bending_rest(const Vec3& x0, const Vec3& x1, const Vec3& x2,
                                            const Vec3& x3, int* clamped = nullptr);

/// h(x) = sum_i K_i x_i.
inline Vec3 isometric_bending_h(const IsometricBendingRest& r, const Vec3& x0, const Vec3& x1,
                                const Vec3& x2, const Vec3& x3) {
  return r.K(0) * x0 + r.K(1) * x1 + r.K(2) * x2 + r.K(3) * x3;
}

/// E_B = 3/(2(A0+A1)) |h|^2 (positive form; Bender's library stores the negative).
double isometric_bending_energy(const IsometricBendingRest& r, const Vec3& x0, const Vec3& x1,
                                const Vec3& x2, const Vec3& x3);

/// Gradient dE_B/dx_i = 3 K_i h / (A0 + A1), i = 0..3 (stencil order).
std::array<Vec3, 4> isometric_bending_gradient(const IsometricBendingRest& r, const Vec3& x0,
                                               const Vec3& x1, const Vec3& x2, const Vec3& x3);

}  // namespace shellcontract
