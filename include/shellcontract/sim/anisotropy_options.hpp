// The anisotropic regions' settings as plain data (fibre directions, k_A). A leaf: the run
// options (sim/config.hpp) include this, not the anisotropy setup (anisotropy.hpp, which needs
// the mesh). Which faces are regions is not an option here: the run plan resolves it into the
// mesh's "f:region" map (sim/run_plan.hpp).
#pragma once

#include "shellcontract/core/types.hpp"

namespace shellcontract {

/// How the fibre direction a of a region face is chosen (the paper never gives one).
enum class FiberMode {
  /// Tangent direction from the face toward its region's area-weighted centre: shortening along
  /// it pulls the region together (default; docs/design/anisotropy.md "Fibre direction" gives the measurement).
  TowardCentre,
  /// One user 3D direction d for every face: a = normalize(d . T1, d . T2) (math-spec 7).
  User,
};

/// Options of the anisotropic regions.
struct AnisotropyOptions {
  FiberMode fiber_mode = FiberMode::TowardCentre;
  Vec3 user_direction = Vec3::UnitX();    ///< FiberMode::User only
  double kappa_a = 0.1;                   ///< k_A = kappa_A mu_A sqrt(Abar_j) (math-spec 9.3, 14)
  double mu_aniso = 1.0;                  ///< mu_A, for k_A
};

}  // namespace shellcontract
