// External pressure load (math-spec 3). Eigen only.
#pragma once

#include "shellcontract/core/types.hpp"

namespace shellcontract {

/// energy: f_i = -(P/6) sum_{j ni i} N_j = -P dV/dx_i (default; no net force, work = -P dV).
/// paper:  f_i = -P nhat_i sum_{j ni i} A_j / 3 with the area-weighted unit vertex normal
///         (paper eq. for Step 1; same direction, larger magnitude on coarse meshes).
enum class PressureModel { EnergyConsistent, Paper };

/// Pressure forces at positions x (math-spec 3). P > 0 with outward normals pushes inward.
/// @param x      #V by 3 current positions
/// @param faces  #F by 3 faces, counter-clockwise from outside
/// @param P      over-pressure (normalized units: force per unit area of the unit-diagonal mesh)
/// @param f      #V by 3 output forces (resized and overwritten)
/// \note In the paper form, a vertex whose summed normal is zero (|sum N| = 0) gets no force.
void pressure_forces(const Positions& x, const Faces& faces, double P, PressureModel model,
                     Positions& f);

}  // namespace shellcontract
