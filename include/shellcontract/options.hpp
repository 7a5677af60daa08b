// Options of one contraction run as a caller gives them (CLI, Python, C++): the simulation's
// options (shellcontract/simulation_options.hpp) plus where the anisotropic regions come from,
// and the option table that sets them by name from text. Plain data (no mesh, solver or
// collision classes); the run plan resolves and checks them (docs/design/run-plan.md).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "shellcontract/simulation_options.hpp"

namespace shellcontract {

/// Where the faces of the anisotropic regions come from.
enum class RegionSource {
  Auto,  ///< spherical regions found by curvature (select_spherical_regions)
  File,  ///< RunOptions::region_file: one line per region, 0-based face ids
  /// Per-vertex weights (RunOptions::region_weight_file or vertex_weights): the weighted faces
  /// are the regions, their weights the strength (sim/region_weights.hpp).
  Weights,
  None,
};

/// The Gauss-Seidel order a run asks for (--order). Auto (the default): the coloured order at
/// every size. At equal time it was never less accurate than the paper's sequential order on
/// the paper's meshes and two spheres (every rung of `shellcontract bench error`:
/// lab/speed-error/orders/README.md), it runs the batched kernels on every thread, and its result
/// does not depend on the thread count. Sequential (one fixed order, the paper's
/// scheme's: docs/math/spec.md 14.1) stays available.
enum class OrderChoice { Auto, Sequential, Coloured };

/// Default of RunOptions::region_max_area: RegionOptions{}.max_area_fraction
/// (shellcontract/regions.hpp; a test holds the two equal).
inline constexpr double DEFAULT_REGION_MAX_AREA = 0.25;

/// The order a run asking for `choice` uses.
ConstraintOrder order_for(OrderChoice choice);

/// The simulation options of the default run: XPBD (physical stiffness, so that the result does
/// not depend on the mesh's resolution) with DEFAULT_XPBD_DAMPING. The Simulator's own defaults
/// (SimOptions) stay the paper's PBD scheme.
inline SimOptions default_run_sim_options() {
  SimOptions s;
  s.solver.kind = SolverKind::Xpbd;
  s.damping = DEFAULT_XPBD_DAMPING;
  return s;
}

/// Everything a run needs besides the mesh. Lengths are in normalized units.
///
/// The defaults are the default run: XPBD with the default shell material (young, thickness) and
/// its damping. resolve_run_options goes back to the paper's settings where a caller leaves them:
/// under --solver pbd the membrane is mu and lambda (not the shell material) and the damping is
/// DEFAULT_DAMPING; with mu or lambda chosen, they are the membrane. "Chosen" is set through the
/// option table (which records it in `given`) or, for a caller that writes the fields, changed
/// from the default.
struct RunOptions {
  SimOptions sim = default_run_sim_options();
  /// The Gauss-Seidel order: run_contraction sets sim.solver.order from it and the mesh's size.
  OrderChoice order = OrderChoice::Auto;
  /// None by default: regions switch the local contraction on. An anisotropic energy (--aniso)
  /// or measure_regions without a region source given selects Auto (resolve_run_options).
  RegionSource regions = RegionSource::None;
  std::string region_file;  ///< RegionSource::File only
  /// --region-weights: one weight in [0, 1] per vertex (read_vertex_weights); resolve_run_options
  /// then sets regions to Weights.
  std::string region_weight_file;
  /// The same weights given as numbers (Python region_weights=W), instead of the file.
  std::vector<double> vertex_weights;
  /// --region-at: the regions are the spherical caps around the surface points nearest to
  /// these (select_regions_at, as `regions --region-at`); resolve_run_options then sets regions
  /// to Auto. Excludes a region source given otherwise.
  std::vector<Vec3> region_points;
  /// RegionSource::Auto only: regions larger than this fraction of the total area are dropped
  /// (RegionOptions::max_area_fraction; a large one, such as bear's head, deflates the shell).
  double region_max_area = DEFAULT_REGION_MAX_AREA;
  /// Select the regions even when no local contraction acts on them, to report how far they sink.
  bool measure_regions = false;
  /// Membrane stiffness from Young's modulus, Poisson ratio and thickness (math-spec 6). When
  /// both young and thickness are set, resolve_run_options replaces mu and lambda with them; it
  /// unsets the defaults under pbd and when mu or lambda is chosen (see above).
  std::optional<double> young = DEFAULT_SHELL_YOUNG;
  double poisson = 0.3;
  std::optional<double> thickness = DEFAULT_SHELL_THICKNESS;
  /// The options set through the option table, by field name ("k_b", "region_weights"; not a
  /// front end's spelling), so that a run can say which of them have no effect in its
  /// configuration (ineffective_options).
  std::set<std::string> given;
};

/// One warning per given option that has no effect with the others (e.g. region_shrink
/// without regions, c10 with a material other than Mooney-Rivlin, delta with collisions off),
/// naming the options by field in backquotes (`region_shrink`; spell_options spells them for a
/// front end). The run plan reports them as warnings.
std::vector<std::string> ineffective_options(const RunOptions& options);

/// The options, by field, that have no effect in this configuration whatever their value, given
/// or not: the rules of ineffective_options (a given one of them is its "has no effect" warning).
/// Not those whose given value another option replaces (mu and lambda beside young or
/// thickness): the run used a value for them. The run summary records these empty.
std::set<std::string> options_without_effect(const RunOptions& options);

/// Applies the defaults that depend on other options, derives the values that follow from
/// others (mu and lambda from young; the solver's time step and threads, the collision threads
/// and the speculative broad phase) and checks every option and the rules between them. The
/// mesh-free part of the run plan (run_plan.hpp, src/sim/run_plan.cpp): every default and rule
/// has this one owner. Every option's value must lie in the option table's range, as its text
/// would (a caller that writes the fields is held to it too). Idempotent, so that a caller (the
/// CLI, to refuse bad options before it reads the mesh) may resolve what plan_run resolves again.
/// @throws UsageError naming the option by its field (`target_volume`; option_table.hpp spells it
///         for the CLI or Python)
void resolve_run_options(RunOptions& options);

/// The derived fields of SimOptions (solver.dt, solver.threads -> collision.threads,
/// collision.speculative, the anisotropy's mu_A, the solver's k_A switch) from the others, then
/// the checks of check_sim_options.
void resolve_sim_options(SimOptions& options);

/// Checks the simulation options' ranges and the rules between them.
/// @throws UsageError naming the option by its field
void check_sim_options(const SimOptions& options);

}  // namespace shellcontract

// The one table of run options: name, help, default and accepted range of every option of
// `shellcontract run`. The CLI builds its parser and --help from it, the Python module its keyword
// arguments, and a test walks it; lists kept by hand are held to it by tests (architecture.md).
namespace shellcontract {

/// One option. Values travel as text so that the CLI and Python parse them the same way (the same
/// double from the same digits, hence the same run).
struct OptionSpec {
  std::string name;        ///< CLI spelling without dashes, e.g. "k-b"; Python uses k_b
  char short_name = 0;     ///< one-letter alias, 0 for none
  /// What the value is, e.g. "P" or "N"; empty for a switch. Alternatives are separated by '|'
  /// ("auto|none|FILE"). Three marks in it are conventions that code relies on, not only words
  /// for --help:
  /// - FILE: the value may name a file the run reads (--regions, --region-weights). Lists kept
  ///   by hand must name every such option (docs/architecture.md, "A new option": the CLI's
  ///   inputs, over which no output may be written, the inputs a checkpoint records, the sweep's
  ///   paths); tests find the options by this word.
  /// - KEYS: the value may be keyframes "FRAME:VALUE, ..." (with_keyframes: --pressure,
  ///   --target-volume); Python takes a list of (frame, value) pairs for it
  ///   (python/src/option_values.cpp finds the options by this word).
  /// - a ',' (X,Y,Z): a point or a direction; Python takes a sequence for it.
  std::string value_name;
  std::string help;        ///< one sentence or two, ending with the accepted range
  bool is_switch = false;  ///< a flag without a value ("on" when given)
  /// May be given several times on the command line: the values, joined by ';', are set at once.
  bool repeatable = false;
  /// Parses `value` into `options`. @throws UsageError naming the option and the accepted range
  std::function<void(RunOptions&, const std::string&)> set;
  /// The option's value in `options` as text ("" for an unset optional value); get(RunOptions{})
  /// is the default shown in --help, in the shortest form that reads back exactly (0.3).
  std::function<std::string(const RunOptions&)> get;
  /// Example values outside the accepted range, for the test that walks the table.
  std::vector<std::string> bad_examples;
};

/// Every option of a run, in --help order.
const std::vector<OptionSpec>& run_option_table();

/// The option named `name` (CLI spelling; Python's underscores are accepted too), or nullptr.
const OptionSpec* find_run_option(const std::string& name);

/// Sets one option from text. @throws UsageError for an unknown name or a bad value
void set_run_option(RunOptions& options, const std::string& name, const std::string& value);

/// How a front end names the options. The library's messages name an option by its field, in
/// backquotes (`k_b`: the table's name with underscores, as RunOptions::given records it); each
/// front end spells it its own way.
enum class OptionSpelling {
  Cli,     ///< the table's name ("k-b"); "--k-b" in a message
  Python,  ///< the field's name ("k_b"), as contract() takes it
};

/// The field name of a table name: "k-b" -> "k_b".
std::string option_field(const std::string& name);

/// The option's name in a spelling: "k-b" (Cli) or "k_b" (Python).
std::string option_name(const OptionSpec& option, OptionSpelling spelling);

/// A library message with every backquoted option field (`target_volume`) spelled for the front
/// end: "--target-volume" (Cli) or "target_volume" (Python); the region finders' options too
/// (REGION_OPTION_FIELDS: "--max-area-fraction", "max_area_fraction"). Backquotes around anything
/// else are left as they are.
std::string spell_options(const std::string& message, OptionSpelling spelling);

/// The shortest decimal text that reads back as exactly `x` (0.3, 1e-4, 2).
std::string shortest_text(double x);

}  // namespace shellcontract
