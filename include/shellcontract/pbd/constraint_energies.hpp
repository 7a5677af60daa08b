// The constraint energies of a configuration, as plain data (a leaf: a step's measurements,
// sim/frame_metrics.hpp, carry them without the solver).
#pragma once

namespace shellcontract {

/// Sum of each kind of constraint energy at a configuration.
struct ConstraintEnergies {
  double membrane = 0.0;     ///< sum Abar psi over membrane faces
  double bending = 0.0;      ///< k_B E_B (isometric) or k_B kappa (theta - theta_bar)^2 (dihedral)
  double anisotropic = 0.0;  ///< sum Abar psi_A over anisotropic faces
};

}  // namespace shellcontract
