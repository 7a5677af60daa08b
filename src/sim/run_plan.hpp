// The run plan: the options resolved once, with the mesh they apply to (docs/design/run-plan.md).
// plan_run turns a mesh and the caller's options into everything a run needs: the defaults
// applied, the derived values set (mu, lambda and k_B from E, nu and h; the order for the mesh's
// size; delta auto), every rule checked, and the regions resolved into the mesh's "f:region" map.
// The Simulator takes a plan and neither checks nor resolves.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "mesh/normalization.hpp"
#include "shellcontract/mesh.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"

namespace shellcontract {

/// What a Simulator is built from.
struct SimPlan {
  /// The input's connectivity at normalized positions (bounding-box diagonal 1), with the run's
  /// regions in its "f:region" map (no map or every face -1: no region).
  Mesh mesh;
  Normalization normalization;  ///< from the input's units to mesh's
  SimOptions options;           ///< resolved and checked; collision.delta is the one used
  /// The time step the explicit pressure's mass floor is set for (sim/mass_scaling.hpp); 0: the
  /// run's options.dt. `bench error` sets its base step for every run of its ladder, so that the
  /// runs at a fraction of the step have the same masses, the same model, as the run at the step.
  double mass_scaling_dt = 0.0;
  /// What the user should know about the contact distance (choose_contact_distance); plan_run
  /// moves them to RunPlan::warnings.
  std::vector<std::string> warnings;
  bool held_at_rest = false;  ///< ContactDistanceChoice::held_at_rest
};

/// Everything a run needs besides an observer: the simulation's plan and what the run reports
/// from the resolution.
struct RunPlan {
  RunOptions options;  ///< as resolved (resolve_run_options): what the summary reports
  SimPlan sim;
  std::size_t regions = 0;  ///< regions in sim.mesh's "f:region" map
  /// Options that have no effect with the others, a region source that found no region: for the
  /// user, in the order found (options by field in backquotes, as ineffective_options).
  std::vector<std::string> warnings;
  double regions_seconds = 0.0;  ///< selecting or reading the regions
};

/// The plan of one run of `mesh` (a checked, closed, outward-oriented triangle mesh from
/// read_input_mesh, any units) with `options`.
/// @throws UsageError for invalid options (naming the field), InputError for an unusable mesh or
///         region file
RunPlan plan_run(const Mesh& mesh, const RunOptions& options);

/// The plan of a Simulator alone: `options` resolved and checked (resolve_sim_options), `mesh`
/// normalized, the contact distance chosen (choose_contact_distance: delta auto resolved, a
/// given delta checked against the mesh, warnings for pairs held at rest). The regions are the
/// "f:region" map `mesh` carries, if any.
/// @throws UsageError for invalid options (a delta above the mesh's bound included), InputError
///         for an unusable mesh
SimPlan plan_simulation(Mesh mesh, SimOptions options);

/// Stores the regions a run would use in the mesh's "f:region" map: auto-selected by curvature
/// (mark_spherical_regions, which also stores the curvature maps), read from the file, from the
/// weights, or none (every face -1). plan_run calls it on its copy of the mesh after
/// resolve_run_options, which selects Auto only when something acts on the regions or they are
/// measured.
/// `warnings`, when given, gets the selection's warnings (a --region-at point far from the
/// surface: RegionReport::warnings).
/// @return the number of regions
/// @throws InputError for an unreadable or out-of-range region file
std::size_t mark_run_regions(Mesh& mesh, const RunOptions& options,
                             std::vector<std::string>* warnings = nullptr);

/// Runs a plan (plan_run(mesh, options), or a plan a caller put together from plan_simulation):
/// run_contraction(mesh, options) is run_contraction(plan_run(mesh, options)). The plan's
/// warnings go to the observer first.
RunResult run_contraction(RunPlan plan, RunObserver* observer = nullptr,
                          RunCheckpointer* checkpointer = nullptr);

}  // namespace shellcontract
