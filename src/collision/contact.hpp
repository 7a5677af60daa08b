// Collision response: signed contact constraints (math-spec 10.8, the R default). Eigen only.
#pragma once

#include <array>

#include "collision/ccd.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// One contact found by the narrow phase, frozen for the response (math-spec 10.8: n_c, the
/// weights and the side sign are kept fixed while projecting).
struct Contact {
  CcdPrimitive kind = CcdPrimitive::VertexFace;
  std::array<int, 2> pair{};  ///< (vertex id, face id) or (edge id a, edge id b)
  std::array<int, 4> v{};     ///< vertex ids in the CCD stencil order (ccd.hpp)
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();  ///< contact vector = sum_k weights_k x_k
  Vec3 normal = Vec3::UnitZ();  ///< unit n_c
  double side = 1.0;            ///< sigma_c, the side at t = 0
};

/// Projects C = sigma n . (sum_k weights_k x_k) - separation >= 0 once, mass-weighted
/// (math-spec 10.8): lambda = -C / sum_k w_k weights_k^2, dx_k = lambda w_k weights_k sigma n.
/// Nothing happens when C >= 0 or every involved vertex is pinned.
/// @param separation  target distance along n (normalized units, >= 0)
/// @param x           positions, 3 doubles per vertex, updated in place
/// @param w           inverse masses
/// @return true if the positions changed
bool project_contact(const Contact& c, double separation, double* x, const double* w);

}  // namespace shellcontract
