// Options of one contraction run as a caller gives them (CLI, Python, C++): the simulation's
// options plus where the anisotropic regions come from. option_table.hpp parses them from text,
// run.hpp runs them.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

#include "shellcontract/geometry/region_selection.hpp"
#include "shellcontract/sim/config.hpp"

namespace shellcontract {

/// Where the faces of the anisotropic regions come from.
enum class RegionSource {
  Auto,  ///< spherical regions found by curvature (select_spherical_regions)
  File,  ///< RunOptions::region_file: one line per region, 0-based face ids
  None,
};

/// Everything a run needs besides the mesh. Lengths are in normalized units.
struct RunOptions {
  SimOptions sim;
  /// None by default: regions switch the local contraction on. An anisotropic energy (--aniso)
  /// or measure_regions without a region source given selects Auto (resolve_run_options).
  RegionSource regions = RegionSource::None;
  std::string region_file;  ///< RegionSource::File only
  /// RegionSource::Auto only: regions larger than this fraction of the total area are dropped
  /// (RegionOptions::max_area_fraction; a large one, such as bear's head, deflates the shell).
  double region_max_area = RegionOptions{}.max_area_fraction;
  /// Select the regions even when no local contraction acts on them, to report how far they sink.
  bool measure_regions = false;
  /// Membrane stiffness from Young's modulus, Poisson ratio and thickness (math-spec 6). When
  /// both young and thickness are set, resolve_run_options replaces mu and lambda with them.
  std::optional<double> young;
  double poisson = 0.3;
  std::optional<double> thickness;
  /// The options set through the option table (CLI spelling), so that a run can say which of
  /// them have no effect in its configuration (ineffective_options).
  std::set<std::string> given;
};

/// One warning per given option that has no effect with the others (e.g. --region-shrink
/// without regions, --c10 with a material other than Mooney-Rivlin, --delta with
/// collisions off). run_contraction reports them as warnings.
std::vector<std::string> ineffective_options(const RunOptions& options);

/// Checks the options that depend on each other and derives the values that follow from others
/// (mu and lambda from --young; the solver's time step and threads, the collision threads and the
/// speculative broad phase). Called once, by run_contraction and by the Simulator; every value
/// has this one owner.
/// @throws UsageError naming the option
void resolve_run_options(RunOptions& options);

/// The derived fields of SimOptions (solver.dt, solver.threads -> collision.threads,
/// collision.speculative, the anisotropy's mu_A, the solver's k_A switch) from the others.
void resolve_sim_options(SimOptions& options);

}  // namespace shellcontract
