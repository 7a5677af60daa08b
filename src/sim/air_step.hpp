// Whether the enclosed air's spring outruns the explicit step: a prediction made before a run's
// first step from its rest shape and masses (docs/math/air-pressure.md section 4). The outside
// pressure and the air are applied explicitly (math-spec 2, Step 1), so the volume is a mass on a
// spring integrated by symplectic Euler with damping; past the step's stability bound the volume
// can overshoot its balance further every step, and the run swing or blow up. The membrane and
// the contacts can only slow that mode, so the prediction is on the safe side.
#pragma once

#include <Eigen/Core>
#include <string>

#include "shellcontract/simulation_options.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// The volume mode of a shell under the air's net pressure, linearized at its balance volume
/// V/V0 = R (air-pressure.md section 4). All lengths in normalized units.
struct AirStep {
  /// The shell's mean inward move in one step from rest under the largest pressure P: the
  /// volume the step takes, P dt^2 sum_i w_i q_i |g_i|, over the area A (g_i = dV/dx_i, q_i
  /// the pressure force per unit P: |g_i| in the energy-consistent form, the ring area / 3 in
  /// the paper's). P dt^2 / rho_A for area-lumped masses on a smooth shell.
  double move = 0.0;
  /// R (1 - R) V0 / A: move / length is (omega dt)^2 of the volume mode at V/V0 = R, at most
  /// (the membrane and the contacts, left out, only lower it).
  double length = 0.0;
  /// 2 (2 - damping): symplectic Euler with the damping's velocity factor is stable for
  /// (omega dt)^2 below it and overshoots further every step above it.
  double limit = 0.0;

  /// (omega dt)^2 of the volume mode; 0 where no air acts.
  double omega_dt_squared() const { return length > 0.0 ? move / length : 0.0; }
  /// Whether the mode can grow: (omega dt)^2 above the limit.
  bool overshoots() const { return length > 0.0 && move > limit * length; }
};

/// The volume mode of the shell at rest positions `x` (normalized) with inverse masses
/// `inv_mass` (after the floors and the pressure's mass scaling) under options `s`: its largest
/// pressure (the largest key with keys), `air_balance`, `dt`, `damping` and `pressure_model`.
/// Zero (no air acts) where that pressure is not above 0, `air_balance` is 0, or the volume
/// or area is not above 0.
AirStep air_step(const Positions& x, const Faces& faces, const Eigen::VectorXd& inv_mass,
                 const SimOptions& s);

/// The warning before a run whose volume mode `a` overshoots (options named as `field`,
/// spell_options), with the `density`, `dt` and `pressure` at which it would not (the mode's
/// (omega dt)^2 scales as pressure dt^2 / density); empty where it does not overshoot, and
/// where a target volume (`target_volume`, its keys) holds the volume instead of the air.
std::string air_step_warning(const AirStep& a, const SimOptions& s);

}  // namespace shellcontract
