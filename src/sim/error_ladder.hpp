// Speed against error (`shellcontract bench error`): run one scene at a ladder of
// solver settings and compare each run with a reference run of the same physical model.
//
// The model and its reference (a choice, stated here and in the bench report):
// - XPBD is a discretization of one physical model (compliance alpha = 1 / stiffness), so it
//   converges as the step shrinks and the iterations grow. Its reference is XPBD with many
//   iterations and many substeps over the same simulated time.
// - PBD's stiffness depends on the step and the iteration count (the paper's energy-as-
//   constraint projection), so PBD at another step is another model. Its reference is PBD with
//   many iterations at the base step (the limit the PBD rungs approach), substeps 1.
// - A substep is the base step divided by k, run k times per base step (k times more steps over
//   the same time). The damping is a fraction of the velocity removed per step, so it is
//   rescaled to d_k = 1 - (1 - d)^(1/k): the same fraction is removed per unit time.
// - Sweep order and threads are rungs too: the Coloured order (math-spec 9.4) is another valid
//   Gauss-Seidel order of the same model, so its rungs are compared with the same reference
//   (Sequential order, one thread); its threads change the time, never the result (bit-identical).
// - The masses: under a pressure the explicit load needs a minimum mass per vertex that grows
//   with the step (sim/mass_scaling.hpp), so a run at base.dt / k would have lighter vertices
//   than the run at base.dt: another model. Every run, references included, has the masses of
//   the base step (those of `shellcontract run` at that --dt), and the ladder measures the
//   solver's error alone.
// - Collision handling is off by default: it is not part of the constraint solver being
//   measured and it makes small differences between runs jump (discrete contact decisions).
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "pbd/solver.hpp"
#include "shellcontract/mesh.hpp"
#include "shellcontract/simulation_options.hpp"

namespace shellcontract {

/// What to run. The simulated time is frames x base.dt for every run.
struct ErrorLadderOptions {
  int frames = 50;                                   ///< base steps (simulated time / base dt)
  std::vector<SolverKind> solvers{SolverKind::Pbd, SolverKind::Xpbd};
  std::vector<int> iterations{1, 2, 5, 10, 20, 50};  ///< Gauss-Seidel sweeps per (sub)step
  std::vector<int> substeps{1, 2, 4};                ///< substeps per base step
  /// Sweep orders of the rungs. The references always use the Sequential order.
  std::vector<ConstraintOrder> orders{ConstraintOrder::Sequential};
  /// Threads of the Coloured rungs (each >= 1): one rung per entry. Sequential rungs run on one
  /// thread (the order is serial); collision handling, if on, uses the same count.
  std::vector<int> threads{1};
  /// PBD rungs with substeps > 1 change PBD's model (see file comment); off by default.
  bool pbd_substeps = false;
  int xpbd_reference_iterations = 50;
  int xpbd_reference_substeps = 16;
  int pbd_reference_iterations = 500;
  /// Collision handling in every run (reference included). Off by default (file comment).
  bool collisions = false;
  /// Runs the reference again at half its step (XPBD: twice the substeps) or, for PBD, twice
  /// its iterations, and reports the change (ReferenceCheck).
  bool check_reference = true;
  double hausdorff_error_bound = 1e-7;  ///< absolute, normalized units
  /// Called with a one-line message before each run (progress on stderr in the CLI); may be empty.
  std::function<void(const std::string&)> progress;
};

/// One run of the ladder, compared with its solver's reference at the end of the simulated time.
/// Lengths are in normalized units (the input's bounding-box diagonal is 1).
struct ErrorLadderRow {
  SolverKind solver = SolverKind::Xpbd;
  int iterations = 0;
  int substeps = 1;
  ConstraintOrder order = ConstraintOrder::Sequential;
  int threads = 1;              ///< threads of the solve (Coloured order) and of collisions
  bool failed = false;          ///< the run threw SimulationError (blow-up); errors are NaN
  std::string failure;          ///< its message
  /// Median over the base steps of the wall time of one base step (the sum of its substeps'
  /// Simulator step_seconds: prediction, solve, collisions, velocity update; not the metrics).
  double ms_per_step = 0.0;
  double hausdorff = 0.0;       ///< symmetric Hausdorff distance to the reference surface
  double max_vertex_error = 0.0;  ///< max_i |x_i - x_i^ref| (vertex correspondence)
  double volume_ratio = 1.0;    ///< V/V0 at the end
  double volume_error = 0.0;    ///< |V/V0 - (V/V0)_ref|
  /// Constraint residual, defined as the relative difference of the total constraint energy
  /// (membrane + bending + anisotropic, solver energies()) at the end: |E - E_ref| / E_ref.
  /// (The solvers expose no per-constraint residual C + alpha~ lambda; the energy is what both
  /// PBD and XPBD drive and what the run log reports.)
  double energy_error = 0.0;
  double energy = 0.0;          ///< total constraint energy at the end (normalized units)
  /// The run's masses raised for the pressure and the largest factor (MassScaling): the base
  /// step's in every run (file comment).
  std::size_t mass_scaled_vertices = 0;
  double largest_mass_factor = 1.0;
};

/// Convergence of one reference: the reference run again with a halved step (XPBD: 2x substeps)
/// or doubled iterations (PBD, whose model is tied to the step), compared with the reference.
struct ReferenceCheck {
  SolverKind solver = SolverKind::Xpbd;
  int iterations = 0, substeps = 1;                  ///< the reference
  int refined_iterations = 0, refined_substeps = 1;  ///< the refined run
  double ms_per_step = 0.0;                          ///< the reference's, as in ErrorLadderRow
  double hausdorff = 0.0;       ///< refined vs reference, as in ErrorLadderRow
  double volume_error = 0.0;
  double energy_error = 0.0;
  /// Smallest Hausdorff error of this solver's rungs (rows equal to the reference excluded).
  double smallest_rung_hausdorff = 0.0;
  /// Smallest volume error of this solver's rungs, likewise (reported, not part of converged).
  double smallest_rung_volume_error = 0.0;
  /// hausdorff < smallest_rung_hausdorff: the reference is closer to its own refinement than any
  /// rung is to it, so the table's errors are not the reference's own error.
  bool converged = false;
  bool failed = false;
  std::string failure;
};

struct ErrorLadderResult {
  int frames = 0;
  double dt = 0.0;               ///< base step
  double simulated_time = 0.0;   ///< frames x dt
  /// In run order: per solver, per substeps, per order, per threads, per iterations.
  std::vector<ErrorLadderRow> rows;
  std::vector<ReferenceCheck> references;  ///< one per solver (empty if check_reference is off)
  std::vector<ErrorLadderRow> reference_rows;  ///< the reference runs themselves (errors 0)
  /// Solvers whose energy_error (rungs and reference check) is NaN because it is not
  /// meaningful: the reference's energy is below ENERGY_ERROR_FLOOR of the largest energy of its
  /// rungs (ENERGY_ERROR_FLOOR's comment).
  std::vector<SolverKind> energy_error_not_meaningful;
  /// The masses every run used (file comment): vertices raised for the pressure at the base step
  /// and the largest factor (1: none raised).
  std::size_t mass_scaled_vertices = 0;
  double largest_mass_factor = 1.0;
};

/// A solver's dE_rel = |E - E_ref| / |E_ref| is NaN for all its rows (not its reference's own
/// 0) when |E_ref| < ENERGY_ERROR_FLOOR * max |E| over its rungs: the reference holds next to no
/// energy against the rungs, so the ratio measures how close E_ref is to 0, not how close a rung
/// is to the reference. PBD's reference is the case: its stiffness grows with the iterations,
/// and at 500 sweeps the shell is held nearly rigid, with rounding-level energy.
inline constexpr double ENERGY_ERROR_FLOOR = 1e-6;

/// Runs the references and the ladder for `mesh` with the physics of `base` (pressure, material,
/// bending, damping, base dt, ...). base.solver.kind/iterations, base.frames, base.collisions,
/// base.validate and base.stop_volume_ratio are replaced by the ladder's own.
/// @throws UsageError for empty or non-positive lists, InputError for an unusable mesh,
///         SimulationError if a reference run blows up
ErrorLadderResult run_error_ladder(const Mesh& mesh, const SimOptions& base,
                                   const ErrorLadderOptions& options);

/// "pbd" or "xpbd".
const char* ladder_solver_name(SolverKind kind);

/// "sequential" or "coloured".
const char* ladder_order_name(ConstraintOrder order);

}  // namespace shellcontract
