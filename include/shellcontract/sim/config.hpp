// Plain option structs of a simulation run. Defaults are the paper's values where it gives
// them, otherwise ours (math-spec 14); README.md "Options" documents how they were chosen.
// A leaf: each module's settings come from its own leaf header beside it (no mesh, solver,
// collision or material classes); the run plan (run_plan.hpp) resolves and checks them.
#pragma once

#include <string>

#include "shellcontract/collision/collision_options.hpp"
#include "shellcontract/material/material_params.hpp"
#include "shellcontract/pbd/solver_settings.hpp"
#include "shellcontract/sim/anisotropy_options.hpp"
#include "shellcontract/sim/pressure_model.hpp"
#include "shellcontract/sim/schedule.hpp"

namespace shellcontract {

/// isometric: the paper's flat-rest model (math-spec 8.2); dihedral: rest-aware (8.3).
enum class BendingModel { Isometric, Dihedral, None };

/// The local contraction's mechanism on the regions: Volume (default) sinks each region as a
/// mirrored dimple around its apex, as large as region_shrink asks, and holds it there
/// (region_dimple.hpp, docs/math/local-contraction.md): the region sinks a chosen amount and the
/// rest of the shell is left alone once it is there; under a global pressure its faces also take
/// the region load REGION_LOAD_GAIN S P (local_contraction.hpp). Force is the paper's extra
/// pressure P_A on the region faces, f_i = -(P_A/6) sum N_j, applied in the prediction without
/// net force or torque (math-spec 9.2 R); it keeps pushing for the whole run, so the sink creeps
/// on and spreads to the rest.
/// Projection is the paper's k_A inside the E_A projection (math-spec 9.3; PBD only, in XPBD it
/// becomes Force). None: no inward term.
enum class InwardTerm { Projection, Force, Volume, None };

/// The shape InwardTerm::Volume drives each region's dimple to: Volume projects the dimple's cap
/// volume only (region_volume.hpp); Mirror moves its interior vertices onto the mirror image of
/// the rest cap through the rim's plane, an isometry (region_mirror.hpp), and keeps the volume
/// projection for a region that cannot be mirrored.
enum class DimpleShape { Volume, Mirror };

/// Default strength of the local contraction (SimOptions::region_shrink, in [0, 1]): with the
/// Volume mechanism, a region on a shell at its rest volume loses 2 * 0.7 = 1.4 times its rest cap
/// volume, as a mirrored dimple (dimple_rest_volume). Chosen by measurement
/// (lab/pages/local-contraction.md, sections 1-2): at -p 0 it sinks bumpy_sphere's bumps much
/// farther than the rest of the shell moves, the smallest one by more than its radius; 1 adds
/// little more depth and less locality.
inline constexpr double DEFAULT_REGION_SHRINK = 0.7;

/// When CGAL's self-intersection test checks the result (new intersections vs the input's).
enum class ValidateMode { Off, End, EveryFrame };

/// area: m_i = rho_A sum Abar_j / 3 (math-spec 1.4, default); unit: m_i = 1.
enum class MassModel { AreaLumped, Unit };

/// Default net over-pressure at the rest volume, normalized units. Chosen with the default air
/// (DEFAULT_AIR_BALANCE) and dihedral bending by measurement (docs/design/defaults.md): 200 default
/// frames end between V/V0 0.4 and 0.8 on eight, hand, elk, bear and the kitten.
inline constexpr double DEFAULT_PRESSURE = 4.0;

/// Default balance volume ratio of the enclosed air (air_net_pressure): the net pressure vanishes
/// at V/V0 = 0.5, so that every mesh slows down and stops short of being crushed, whatever its
/// shape or resolution (docs/design/defaults.md).
inline constexpr double DEFAULT_AIR_BALANCE = 0.5;

/// Default length of the target-volume ramp, in frames: long enough that the shell follows the
/// shrinking volume quasi-statically, short enough to hold the target for most of a default run.
inline constexpr int DEFAULT_TARGET_RAMP_FRAMES = 100;

/// Largest V/V0 a key of a keyframed target volume may ask: re-inflation to the rest volume and
/// beyond it up to twice the volume; a larger ratio is taken for a typo (50 for 0.5).
inline constexpr double MAX_KEYED_VOLUME_RATIO = 2.0;

/// Default fraction of the velocity removed per step of the paper's PBD solver (--solver pbd).
/// The paper has no damping; without it the undamped PBD shell rings (V/V0 oscillates around its
/// quasi-static path, README measurement).
inline constexpr double DEFAULT_DAMPING = 0.2;

/// The default run's damping (XPBD with the default shell material, RunOptions). Half the PBD
/// value: a run that removes less velocity lets the rest of the shell spring back to its rest
/// shape sooner after the regions' dimples pull on it, so the local contraction stays local
/// (bumpy_sphere at -p 0: 0.1 is more local than 0.2, docs/design/defaults.md "The default
/// run").
inline constexpr double DEFAULT_XPBD_DAMPING = 0.1;

/// The default run's shell material (XPBD, RunOptions): Young's modulus and thickness in
/// normalized units (bounding-box diagonal 1), Poisson ratio 0.3. Chosen by measurement
/// (docs/design/defaults.md "The default run"): icospheres of 320 to 20,480 faces end within
/// 0.02 of each other and bear with bear split in four within 0.03, and the wrinkles take a size
/// set by the thickness (lab/pages/wrinkles.md).
inline constexpr double DEFAULT_SHELL_YOUNG = 1000.0;
inline constexpr double DEFAULT_SHELL_THICKNESS = 0.002;

/// Whether the collision broad phase starts speculatively while the constraint solve runs
/// (CollisionOptions::speculative, SelfCollision::predict). Its task runs on the core that a
/// single-threaded solve leaves idle; a parallel solve needs that core itself, and the task
/// slows both the solve and the step there (lab/history.md).
enum class SpeculativeBroadPhase {
  Auto,  ///< on with the sequential order (single-threaded solve), off with the coloured one
  On,
  Off,
};

/// Options of one contraction run. Lengths are in normalized units (bounding-box diagonal 1).
struct SimOptions {
  double pressure = DEFAULT_PRESSURE;            ///< P, normalized units
  /// R of the enclosed air (air_net_pressure): the net pressure vanishes at V/V0 = R; 0 = no air.
  double air_balance = DEFAULT_AIR_BALANCE;
  PressureModel pressure_model = PressureModel::EnergyConsistent;
  int frames = 200;                              ///< number of time steps
  double dt = 0.01;                              ///< time step (math-spec 14)
  SolverSettings solver;                         ///< pbd/xpbd, iterations (5), k_B (0.01)
  MaterialKind material = MaterialKind::Stvk;
  MaterialParams material_params;
  /// Rest-aware by default: the paper's flat-rest isometric model pushes a curved shell outward
  /// even at P = 0 (docs/design/defaults.md "Rest drift").
  BendingModel bending = BendingModel::Dihedral;
  MassModel mass = MassModel::AreaLumped;
  double density = 1.0;                          ///< rho_A, mass per normalized area
  /// epsilon: stop at the step whose V/V0 would fall below epsilon, with the volume projected onto
  /// epsilon V0 in that step (docs/math/volume-control.md), so the run ends on epsilon (0 = off).
  double stop_volume_ratio = 0.0;
  /// R: drive V/V0 to R and hold it there with a global volume constraint (docs/math/volume-control.md); 0 = off.
  double target_volume = 0.0;
  /// Frames over which the constraint's target goes from V0 to R V0 (smoothstep ramp).
  int target_ramp_frames = DEFAULT_TARGET_RAMP_FRAMES;
  /// Keyframed target V/V0 (--target-volume "0:1, 60:0.5, 120:0.85"); when not empty it is the
  /// target instead of the ramp to target_volume, and target_volume is its last key's value
  /// (docs/design/keyframes.md).
  Schedule target_volume_schedule;
  /// Keyframed pressure (-p "0:4, 100:0"); when not empty it is P at each frame, and pressure is
  /// its largest key value (what the checks of "is there a compressing pressure" read).
  Schedule pressure_schedule;
  double damping = DEFAULT_DAMPING;              ///< fraction of velocity removed per step, [0, 1)
  AnisotropyOptions anisotropy;                  ///< fibres, kappa_A (solver.aniso = model)
  InwardTerm inward_term = InwardTerm::Volume;
  /// How much the regions shrink, in [0, 1]: the local contraction's strength (dimple_rest_volume
  /// for InwardTerm::Volume, region_pressure for InwardTerm::Force).
  double region_shrink = DEFAULT_REGION_SHRINK;
  DimpleShape dimple_shape = DimpleShape::Volume;  ///< InwardTerm::Volume's dimple (--dimple)
  /// Continuous collision detection and response (paper section 4). On by default: users expect
  /// a result that never passes through itself (design.md).
  bool collisions = true;
  CollisionOptions collision;                    ///< delta, rounds, broad-phase method
  /// --delta auto: the plan (plan_simulation) sets collision.delta to auto_contact_distance of
  /// the normalized rest mesh, capped at the collision.delta given (sim/contact_distance.hpp).
  bool auto_delta = false;
  /// Sets collision.speculative when the options are resolved (the value given there is ignored).
  SpeculativeBroadPhase speculative_broad_phase = SpeculativeBroadPhase::Auto;
  ValidateMode validate = ValidateMode::Off;
  /// Fill FrameMetrics::energies after every step. Costs a pass over every constraint (a
  /// noticeable share of a default run; lab/history.md), so a caller that does not log them
  /// (the CLI
  /// without --log) turns it off; Simulator::energies() still computes them on demand.
  bool frame_energies = true;
};

/// A step that moves a vertex farther than this (normalized units: the mesh's bounding-box
/// diagonal is 1) is a blow-up: the run stops with SimulationError (exit code 3).
inline constexpr double BLOWUP_DISPLACEMENT = 1.0;

}  // namespace shellcontract
