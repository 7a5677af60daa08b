// Plain option structs of a simulation run. Defaults are the paper's values where it gives
// them, otherwise ours (math-spec 14); README.md "Options" documents how they were chosen.
#pragma once

#include <string>

#include "shellcontract/material/material.hpp"
#include "shellcontract/material/registry.hpp"
#include "shellcontract/collision/self_collision.hpp"
#include "shellcontract/pbd/solver.hpp"
#include "shellcontract/sim/anisotropy.hpp"
#include "shellcontract/sim/pressure.hpp"

namespace shellcontract {

/// isometric: the paper's flat-rest model (math-spec 8.2); dihedral: rest-aware (8.3).
enum class BendingModel { Isometric, Dihedral, None };

/// Where the anisotropic regions' k_A inward term acts: inside the E_A projection (the paper,
/// math-spec 9.3; PBD only, in XPBD it becomes Force), as an explicit inward force
/// f_i = -sum k_A n_j in the prediction (math-spec 9.2 R), or not at all.
enum class InwardTerm { Projection, Force, None };

/// When CGAL's self-intersection test checks the result (new intersections vs the input's).
enum class ValidateMode { Off, End, EveryFrame };

/// area: m_i = rho_A sum Abar_j / 3 (math-spec 1.4, default); unit: m_i = 1.
enum class MassModel { AreaLumped, Unit };

/// Default over-pressure in normalized units. Chosen by measurement (README "Choosing the
/// defaults"): with DEFAULT_DAMPING, 200 default frames contract eight, hand, elk and bear
/// visibly and monotonically without blowing up.
inline constexpr double DEFAULT_PRESSURE = 2.0;

/// Default fraction of the velocity removed per step. The paper has no damping; without it the
/// undamped PBD shell rings (V/V0 oscillates around its quasi-static path, README measurement).
inline constexpr double DEFAULT_DAMPING = 0.2;

/// Options of one contraction run. Lengths are in normalized units (bounding-box diagonal 1).
struct SimOptions {
  double pressure = DEFAULT_PRESSURE;            ///< P, normalized units
  PressureModel pressure_model = PressureModel::EnergyConsistent;
  int frames = 200;                              ///< number of time steps
  double dt = 0.01;                              ///< time step (math-spec 14)
  SolverSettings solver;                         ///< pbd/xpbd, iterations (5), k_B (0.01)
  MaterialKind material = MaterialKind::Stvk;
  MaterialParams material_params;
  BendingModel bending = BendingModel::Isometric;
  MassModel mass = MassModel::AreaLumped;
  double density = 1.0;                          ///< rho_A, mass per normalized area
  double stop_volume_ratio = 0.0;                ///< epsilon: stop when V/V0 < epsilon (0 = off)
  double damping = DEFAULT_DAMPING;              ///< fraction of velocity removed per step, [0, 1)
  AnisotropyOptions anisotropy;                  ///< regions, fibres, kappa_A (solver.aniso = model)
  InwardTerm inward_term = InwardTerm::Projection;
  /// Continuous collision detection and response (paper section 4). On by default: users expect
  /// a result that never passes through itself (design.md).
  bool collisions = true;
  CollisionOptions collision;                    ///< delta, rounds, broad-phase method
  ValidateMode validate = ValidateMode::Off;
};

/// A step that moves a vertex farther than this (normalized units: the mesh's bounding-box
/// diagonal is 1) is a blow-up: the run stops with SimulationError (exit code 3).
inline constexpr double BLOWUP_DISPLACEMENT = 1.0;

}  // namespace shellcontract
