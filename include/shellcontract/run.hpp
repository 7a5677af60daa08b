// The library's entry point: a whole contraction run (docs/architecture.md): the regions, the time
// loop with its stop criteria (frame count, stop ratio, target volume, stall), the run's status
// and totals. The CLI, the Python module and the exporters are observers of this one loop
// (shellcontract/observer.hpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/observer.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/simulation_options.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// How a run ended; RunResult::exit_code maps it onto the documented exit codes.
enum class RunStatus {
  Completed,         ///< every frame ran, or the stop ratio was reached, or the target is held
  TargetNotReached,  ///< a target volume or stop ratio was not reached: the volume stalled or the
                     ///< frames ran out
  SimulationFailed,  ///< non-finite positions, a blow-up or out of memory; the state is the
                     ///< last good step
  NewIntersections,  ///< validation found self-intersections the input did not have
  Cancelled,         ///< the observer or the checkpointer asked to stop (Ctrl-C in Python, the CLI)
};

/// The status as the summary writes it: "ok", "target not reached", "failed",
/// "new self-intersections" or "cancelled".
const char* status_name(RunStatus status);

/// |V/V0 - R| within which a target volume counts as reached and held, for R >= 0.1
/// (docs/math/volume-control.md, section 4).
inline constexpr double TARGET_VOLUME_TOLERANCE = 0.005;
/// The same as a fraction of R, which bounds it below R = 0.1: there an absolute 0.005 is more
/// than 5 % of R, and at R <= 0.005 it is all of R, so that a shell collapsed to V/V0 near 0
/// counted as having reached R = 0.001.
inline constexpr double TARGET_VOLUME_RELATIVE_TOLERANCE = 0.05;

/// The tolerance on V/V0 for the goal R: min(TARGET_VOLUME_TOLERANCE,
/// TARGET_VOLUME_RELATIVE_TOLERANCE * R). The two bounds meet at R = 0.1, so it has no jump.
inline double target_volume_tolerance(double goal) {
  return std::min(TARGET_VOLUME_TOLERANCE, TARGET_VOLUME_RELATIVE_TOLERANCE * std::abs(goal));
}

/// Whether V/V0 = `volume_ratio` has reached the goal R (a target volume, or the stop ratio's
/// stall check): |V/V0 - R| <= target_volume_tolerance(R). False for a non-finite V/V0.
inline bool target_volume_reached(double volume_ratio, double goal) {
  return std::abs(volume_ratio - goal) <= target_volume_tolerance(goal);
}

/// The volume has stalled when V/V0 changed by less than STALL_CHANGE over the last STALL_FRAMES
/// frames while it is still off its target: contacts lock the shell, or the pressure is balanced.
inline constexpr int STALL_FRAMES = 20;
inline constexpr double STALL_CHANGE = 1e-4;

/// What a run produced.
struct RunResult {
  RunStatus status = RunStatus::Completed;
  std::string message;  ///< why it did not complete, for the user; empty when completed
  int frames_run = 0;
  double final_volume_ratio = 1.0;
  double min_volume_ratio = 1.0;
  /// Whether the target volume or stop ratio was reached (true when neither was asked for; the
  /// summary then writes null).
  bool target_reached = true;
  /// The first frame within target_volume_tolerance of the target once its ramp ended or its keys
  /// hold the last frame's value to the end (or the stop ratio's crossing frame); -1 if never.
  int frame_target_reached = -1;
  /// The time loop of this process: a resumed run's own part (from first_frame), not the
  /// interrupted process's.
  double wall_seconds = 0.0;
  int first_frame = 0;           ///< the frame this process's loop started at (a resumed run's)
  double regions_seconds = 0.0;  ///< selecting or reading the regions, before the loop
  double prepare_seconds = 0.0;  ///< building the Simulator: rest state, constraints, collisions
  long new_intersections = -1;   ///< at the last validated frame; -1 when never validated
  std::size_t regions = 0;       ///< anisotropic regions used (or measured)
  std::size_t anisotropic_faces = 0;
  double region_inward_displacement = 0.0;  ///< Simulator::region_inward_displacement at the end
  /// The same for each region alone, in the regions' order (the regions file's lines, or the
  /// automatic regions' ids); empty when there are none.
  std::vector<double> region_sinks;
  double outside_region_displacement = 0.0;  ///< Simulator::outside_region_displacement at the end
  std::size_t degenerate_faces = 0;
  /// Vertices whose mass the pressure's minimum mass for the time step raised, and the largest
  /// factor by which one was raised (1: none); docs/design/defaults.md, "Mass scaling".
  std::size_t mass_scaled_vertices = 0;
  double max_mass_scale = 1.0;
  std::size_t excluded_contact_pairs = 0;
  /// The contact distance delta the run used (normalized units; --delta auto resolved for the
  /// mesh); 0 with collisions off.
  double contact_distance = 0.0;
  double normalization_scale = 1.0;
  /// The Gauss-Seidel order the run used (RunOptions::order resolved for the mesh).
  ConstraintOrder order = ConstraintOrder::Sequential;
  std::vector<std::string> warnings;
  RunTotals totals;
  Positions positions;  ///< final positions in the input's units, row i = vertex i

  /// The process exit code of this result (README "Exit codes").
  int exit_code() const;
};

class RunCheckpointer;  // shellcontract/checkpoint.hpp

/// Runs the contraction of `mesh` (checked, closed, outward: read_input_mesh) to its end. A cancel
/// is heard in the preparation too, and skips `validate` end (docs/architecture.md, "Cancelling").
/// @throws UsageError for invalid options, InputError for an unusable mesh or region file
///         (before the first step), std::bad_alloc if preparing the run runs out of memory. A
///         failing step is not thrown: it ends the run with RunStatus::SimulationFailed and the
///         last good state; so does running out of memory (std::bad_alloc) in a step, in an
///         observer's frame() or in the end's validation, and a std::runtime_error from a step
///         (TBB's "pthread_create has failed" when the address space is exhausted), with a
///         message that says so.
///         An exception that the observer or the checkpointer throws (besides std::bad_alloc from
///         an observer's frame() or finished(), above) passes out of run_contraction unchanged;
///         the run ends where it was thrown.
/// @param checkpointer  continues from its checkpoint, and saves the state when it asks
///         (shellcontract/checkpoint.hpp); InputError if its checkpoint does not fit the mesh and
///         options: another version or mesh (check_checkpoint_input), or options that resolve to
///         other values than the checkpoint's (the threads aside; options_for_resume gives the
///         ones that fit). The face-list and weights files are the caller's to check
///         (check_checkpoint_files).
RunResult run_contraction(const Mesh& mesh, const RunOptions& options,
                          RunObserver* observer = nullptr, RunCheckpointer* checkpointer = nullptr);

}  // namespace shellcontract
