// The constraint solver's settings as plain data. A leaf: the run options (sim/config.hpp)
// include this, not the solver (solver.hpp).
#pragma once

#include "shellcontract/material/material_params.hpp"

namespace shellcontract {

/// pbd: the paper's energy-as-constraint projection (C = E); xpbd: C = sqrt(2E) with compliance,
/// so stiffness has physical meaning (math-spec 9.1, 9.2; design.md "Two solver modes").
enum class SolverKind { Pbd, Xpbd };

/// Order of the Gauss-Seidel sweep inside each kind of constraint (math-spec 9.4).
enum class ConstraintOrder {
  /// Array order of the ConstraintSet (the paper's sequential Gauss-Seidel), single thread.
  Sequential,
  /// Constraints grouped by a greedy vertex colouring (no two of one colour share a vertex),
  /// colours in sequence, each colour's constraints in parallel (TBB). A different but equally
  /// valid Gauss-Seidel order; its result does not depend on the number of threads (bit-identical).
  Coloured,
};

/// Solver settings (defaults: the paper's values where it gives them, math-spec 14).
struct SolverSettings {
  SolverKind kind = SolverKind::Pbd;
  int iterations = 5;        ///< Gauss-Seidel sweeps per step (paper: 5)
  double k_bending = 0.01;   ///< k_B: PBD correction multiplier / XPBD energy scale (9.5)
  double dt = 0.01;          ///< time step (normalized units), used by XPBD's alpha/dt^2
  AnisoKind aniso = AnisoKind::None;  ///< E_A model on ConstraintSet::anisotropic
  /// Paper's k_A term inside the E_A projection (math-spec 9.3; PBD only). When false, k_A is
  /// applied as an explicit force by the simulator (math-spec 9.2 R) or not at all.
  bool k_a_in_projection = true;
  /// Inversion-aware orientation s = sign(n . n_ref) for the E_A faces (math-spec 4.2 option);
  /// default s = +1.
  bool inversion_aware = false;
  /// Sweep order; Sequential keeps the paper's order and results.
  ConstraintOrder order = ConstraintOrder::Sequential;
  /// Threads of the Coloured order (0 = TBB's default, the machine's cores); ignored by
  /// Sequential. Must be >= 0.
  int threads = 0;
};

}  // namespace shellcontract
