// The four-vertex bending stencil shared by both bending models (math-spec 8.1).
//
//            x2
//           /  `.
//   face A /     `.
//        x0 ------ x1     shared edge e0 = x0 x1
//          `.     /
//   face B   `.  /
//              x3
//
// Face A = (x0, x1, x2) and face B = (x1, x0, x3) are both counter-clockwise seen from outside
// for a consistently oriented mesh, so N_A = (x1-x0) x (x2-x0) and N_B = (x0-x1) x (x3-x1) are
// outward (math-spec 8.3).
#pragma once

#include <array>

#include "shellcontract/types.hpp"

namespace shellcontract {

/// Vertex ids of a hinge in stencil order (x0, x1, x2, x3) as drawn above.
using HingeVertices = std::array<int, 4>;

/// Cotangent of the angle between u and v, guarded and clamped (math-spec 11):
/// cot = u.v / max(|u x v|, 1e-12 |u||v|), then clamped to +-cot(1 degree) = +-57.29.
double guarded_cotangent(const Vec3& u, const Vec3& v);

/// Largest |cot| that guarded_cotangent returns: cot(1 degree).
inline constexpr double MAX_COTANGENT = 57.289961630759424;

}  // namespace shellcontract
