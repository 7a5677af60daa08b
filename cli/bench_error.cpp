// shellcontract bench error: speed against error of the constraint solver (docs/cli.md,
// "shellcontract bench error"). Runs a ladder of solver settings on one mesh, compares each run with a
// reference run of the same model (sim/error_ladder.hpp says which), prints a table, writes a
// CSV and draws the plot with gnuplot.
//
// Exit codes: 0 success, 1 bad usage (unknown option, bad list, unwritable output, gnuplot
// missing or failing), 2 bad input mesh, 3 a reference run failed (blow-up).
#include <unistd.h>

#include <algorithm>
#include <boost/program_options.hpp>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "bench_error_output.hpp"
#include "command_line.hpp"
#include "commands.hpp"
#include "core/classic_locale.hpp"
#include "core/decimal_text.hpp"
#include "core/list_text.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/formats.hpp"
#include "output_paths.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "sim/error_ladder.hpp"
#include "sim/option_ranges.hpp"

namespace po = boost::program_options;

namespace shellcontract::cli {
namespace {

constexpr const char* BENCH_ERROR_USAGE = R"(usage: shellcontract bench error INPUT [options]

Speed against error of the constraint solver on one mesh. Every run simulates the same time
(--frames x --dt) with the library's default physics, not run's shell material: pressure with air
(balance 0.5), StVK with mu = lambda = 1, dihedral bending with k_B 0.01, damping 0.2; it is
compared at the end with a reference run of the same model:
  xpbd rungs: against XPBD with --ref-iterations sweeps and --ref-substeps substeps per step
              (XPBD converges to one physical model as the step shrinks);
  pbd rungs:  against PBD with --pbd-ref-iterations sweeps at the base step (PBD's stiffness
              depends on the step, so a smaller step is another model; PBD rungs use substeps 1
              unless --pbd-substeps).
Coloured rungs (--orders coloured or both) use the parallel colour order (another valid
Gauss-Seidel order, compared with the same sequential references) on each of --threads; their
errors do not depend on the thread count (bit-identical), only their time does.
A substep divides the step by k and runs k times as many steps; the damping is rescaled so the
same fraction of velocity is removed per unit time. Every run, the references too, has the
masses of a run at --dt: the pressure's minimum vertex mass grows with the step, and at its
own smaller step a run would be another model (docs/design/defaults.md, "Mass scaling").
Collision handling is off unless --collisions on. Errors are in normalized units (bounding-box
diagonal 1):
  hausdorff    symmetric Hausdorff distance to the reference surface (CGAL, bounded error)
  max_vertex   max_i |x_i - x_i_ref|
  dV           |V/V0 - (V/V0)_ref|
  dE_rel       constraint residual: |E - E_ref| / E_ref, E = total constraint energy
  ms_per_step  median over the steps of the wall time of one step (all its substeps)
The reference check reruns each reference with half its step (xpbd) or twice its iterations
(pbd); it is converged when that change is smaller than the smallest hausdorff of the table.
In --csv a check's row has its reference's ms_per_step (it is plotted there; not timed).

exit codes: 0 success, 1 bad usage (also: an unwritable --csv or --plot, gnuplot missing or
            failing), 2 bad input mesh, 3 a reference run failed (blow-up), memory ran out or
            the system refused a resource, 130 interrupted)";

/// One count, as an integer option of run's (parse_decimal_integer), in [1, most].
int parse_count(const std::string& text, const char* option, long most) {
  long v = 0;
  if (!parse_decimal_integer(text, v) || v < 1 || v > most)
    throw UsageError(std::string(option) + ": '" + text + "' is not an integer in [1, " +
                     std::to_string(most) + "]");
  return static_cast<int>(v);
}

/// Parses "1,2,5" into integers in [1, most]: a list as every list option takes one
/// (core/list_text.hpp), each item as an integer option's (parse_decimal_integer), each once.
std::vector<int> parse_list(const std::string& list, const char* option, long most) {
  std::vector<std::string> items;
  std::string why;
  if (!split_list(list, items, why))
    throw UsageError(std::string(option) + ": '" + list + "': " + why);
  std::vector<int> out;
  for (const std::string& item : items) {
    const int v = parse_count(item, option, most);
    if (std::find(out.begin(), out.end(), v) != out.end())
      throw UsageError(std::string(option) + ": " + item + " is given twice");
    out.push_back(v);
  }
  return out;
}

/// --orders: sequential, coloured or both (the two), each order once.
std::vector<ConstraintOrder> parse_orders(const std::string& list) {
  std::vector<std::string> items;
  std::string why;
  if (!split_list(list, items, why)) throw UsageError("--orders: '" + list + "': " + why);
  std::vector<ConstraintOrder> out;
  for (const std::string& item : items) {
    std::vector<ConstraintOrder> named;
    if (item == "sequential")
      named = {ConstraintOrder::Sequential};
    else if (item == "coloured")
      named = {ConstraintOrder::Coloured};
    else if (item == "both")
      named = {ConstraintOrder::Sequential, ConstraintOrder::Coloured};
    else
      throw UsageError("--orders: expected sequential, coloured or both, got '" + item + "'");
    for (ConstraintOrder o : named) {
      if (std::find(out.begin(), out.end(), o) != out.end())
        throw UsageError("--orders: '" + list + "' names " + ladder_order_name(o) + " twice");
      out.push_back(o);
    }
  }
  return out;
}

/// The value of run's option `name` (its table entry: run's grammar, range and message, which
/// the caller spells with spell_options) for one of bench error's own, in a scratch RunOptions.
RunOptions run_value(const std::string& name, const std::string& text) {
  RunOptions scratch;
  for (const OptionSpec& o : run_option_table())
    if (o.name == name) o.set(scratch, text);
  return scratch;
}

}  // namespace

int command_bench_error(int argc, char** argv) {
  std::string input, csv, plot, solver = "both", iterations = "1,2,5,10,20,50", substeps = "1,2,4";
  std::string collisions = "off", orders = "sequential", threads = "1";
  ErrorLadderOptions opt;
  // Read as text by parse_count, as run's integer options are (Boost's int had a grammar and
  // words of its own).
  std::string ref_iterations = std::to_string(opt.xpbd_reference_iterations);
  std::string ref_substeps = std::to_string(opt.xpbd_reference_substeps);
  std::string pbd_ref_iterations = std::to_string(opt.pbd_reference_iterations);
  SimOptions base;
  // Read as text by run's own table (run_value), so that a value run refuses is refused here
  // before the runs, with run's message, not found out as a failed reference (exit 3).
  std::string frames_text = std::to_string(opt.frames), dt_text = shortest_text(base.dt),
              pressure_text = shortest_text(base.pressure);
  bool no_check = false, quiet = false;
  po::options_description visible("options");
  visible.add_options()("help,h", "show this help")(
      "frames,n", po::value<std::string>(&frames_text)->default_value(frames_text),
      "base steps simulated (time = frames x dt); an integer in [1, 1000000]")(
      "dt", po::value<std::string>(&dt_text)->default_value(dt_text),
      "base time step (normalized units); as run's --dt, a number in [1e-100, 1]")(
      "pressure,p", po::value<std::string>(&pressure_text)->default_value(pressure_text),
      "outside over-pressure P; as run's, a number in [-1e+06, 1e+06] (no keyframes)")(
      "solver", po::value<std::string>(&solver)->default_value(solver), "pbd|xpbd|both")(
      "iterations", po::value<std::string>(&iterations)->default_value(iterations),
      "Gauss-Seidel sweeps of the rungs (list)")(
      "substeps", po::value<std::string>(&substeps)->default_value(substeps),
      "substeps of the rungs (list)")("pbd-substeps", po::bool_switch(&opt.pbd_substeps),
                                      "also run PBD rungs with substeps > 1")(
      "orders", po::value<std::string>(&orders)->default_value(orders),
      "sweep orders of the rungs: sequential, coloured or both (list)")(
      "threads", po::value<std::string>(&threads)->default_value(threads),
      "threads of the coloured rungs (list; results do not depend on it)")(
      "ref-iterations", po::value<std::string>(&ref_iterations)->default_value(ref_iterations),
      "XPBD reference sweeps per substep")(
      "ref-substeps", po::value<std::string>(&ref_substeps)->default_value(ref_substeps),
      "XPBD reference substeps")(
      "pbd-ref-iterations",
      po::value<std::string>(&pbd_ref_iterations)->default_value(pbd_ref_iterations),
      "PBD reference sweeps")("collisions",
                              po::value<std::string>(&collisions)->default_value(collisions),
                              "on|off: collision handling in every run")(
      "no-check", po::bool_switch(&no_check), "skip the reference convergence check")(
      "csv", po::value<std::string>(&csv), "write the table as CSV")(
      "plot", po::value<std::string>(&plot), "draw error against time with gnuplot (.png or .svg)")(
      "quiet,q", po::bool_switch(&quiet), "no progress on stderr");
  try {
    const po::variables_map vm = parse_command_line(argc, argv, visible, input);
    if (vm.count("help")) {
      std::cout << BENCH_ERROR_USAGE << "\n\n" << visible << '\n';
      return static_cast<int>(ExitCode::Success);
    }
    if (input.empty()) throw UsageError("missing INPUT mesh");
    if (solver == "pbd") opt.solvers = {SolverKind::Pbd};
    else if (solver == "xpbd") opt.solvers = {SolverKind::Xpbd};
    else if (solver == "both") opt.solvers = {SolverKind::Pbd, SolverKind::Xpbd};
    else throw UsageError("--solver: expected pbd, xpbd or both, got '" + solver + "'");
    if (collisions != "on" && collisions != "off")
      throw UsageError("--collisions: expected on or off, got '" + collisions + "'");
    opt.collisions = collisions == "on";
    // run's bounds of --iterations and --threads; substeps as iterations (both multiply the work
    // of a step). Without one, --threads 9999 started that many threads.
    namespace ranges = option_ranges;
    opt.iterations = parse_list(iterations, "--iterations", ranges::MAX_ITERATIONS);
    opt.substeps = parse_list(substeps, "--substeps", ranges::MAX_ITERATIONS);
    opt.threads = parse_list(threads, "--threads", ranges::THREADS.hi);
    // The references' counts as the rungs' (the pbd reference check runs twice
    // --pbd-ref-iterations, which an int holds): 2000000000 ran as a typo would, for hours.
    opt.xpbd_reference_iterations =
        parse_count(ref_iterations, "--ref-iterations", ranges::MAX_ITERATIONS);
    opt.xpbd_reference_substeps =
        parse_count(ref_substeps, "--ref-substeps", ranges::MAX_ITERATIONS);
    opt.pbd_reference_iterations =
        parse_count(pbd_ref_iterations, "--pbd-ref-iterations", ranges::MAX_ITERATIONS);
    opt.orders = parse_orders(orders);
    opt.check_reference = !no_check;
    // run's grammar and upper bound for --frames; 0 frames would compare nothing.
    opt.frames = parse_count(frames_text, "--frames", ranges::MAX_FRAMES);
    base.dt = run_value("dt", dt_text).sim.dt;
    if (pressure_text.find(':') != std::string::npos)
      throw UsageError("--pressure: '" + pressure_text +
                       "': bench error takes one pressure, not keyframes");
    base.pressure = run_value("pressure", pressure_text).sim.pressure;
    if (!plot.empty()) {
      // Any case, as the mesh formats' extensions: gnuplot's terminal comes from it, not the name.
      const std::string ext = lower_extension(plot);
      if (ext != "png" && ext != "svg")
        throw UsageError("--plot: expected a .png or .svg file, got '" + plot + "'");
      // Checked before the (long) runs, not after.
      if (!bench::gnuplot_available())
        throw UsageError(
            "--plot needs gnuplot, which is not installed (Debian: apt-get install gnuplot-nox)");
    }
    // Neither output may be the mesh or the other, and both must be writable, checked before
    // the (long) runs: docs/design/output-safety.md.
    OutputPlan plan;
    plan.inputs.push_back({"INPUT", input});
    if (!csv.empty()) plan.outputs.push_back({"--csv", csv});
    if (!plot.empty()) plan.outputs.push_back({"--plot", plot});
    check_planned_outputs(plan);
  } catch (const po::error& e) {
    return usage_error("bench error", e.what());
  } catch (const UsageError& e) {
    return usage_error("bench error", spell_options(e.what(), OptionSpelling::Cli));
  }

  Mesh mesh;
  try {
    InputReport report;
    mesh = read_input_mesh(input, &report);
    if (!quiet)
      for (const std::string& w : report.warnings) std::cerr << "warning: " << w << '\n';
  } catch (const InputError& e) {
    std::cerr << "shellcontract bench error: " << e.what() << '\n';
    return static_cast<int>(ExitCode::BadInput);
  }

  if (!quiet) opt.progress = [](const std::string& s) { std::cerr << "  " << s << '\n'; };
  ErrorLadderResult res;
  try {
    res = run_error_ladder(mesh, base, opt);
  } catch (const InputError& e) {
    std::cerr << "shellcontract bench error: " << e.what() << '\n';
    return static_cast<int>(ExitCode::BadInput);
  } catch (const UsageError& e) {
    return usage_error("bench error", spell_options(e.what(), OptionSpelling::Cli));
  } catch (const SimulationError& e) {
    std::cerr << "shellcontract bench error: " << e.what() << '\n';
    return static_cast<int>(ExitCode::SimulationFailed);
  }

  std::cout << input << ": " << mesh.number_of_faces() << " faces, " << res.frames
            << " steps of dt " << res.dt << " (simulated time " << res.simulated_time
            << "), collisions " << collisions << '\n';
  if (res.mass_scaled_vertices > 0)
    std::cout << "masses: " << res.mass_scaled_vertices << " of " << mesh.number_of_vertices()
              << " vertices raised for the pressure at dt " << res.dt << " (up to "
              << bench::fmt(res.largest_mass_factor) << " times), the same in every run\n";
  std::cout << '\n';
  bench::print_rows(res.rows, std::cout);
  std::cout << "\nreferences (errors 0 by definition):\n";
  bench::print_rows(res.reference_rows, std::cout);
  if (!res.references.empty()) {
    std::cout << "\nreference check:\n";
    bench::print_checks(res.references, std::cout);
  }
  for (SolverKind kind : res.energy_error_not_meaningful)
    std::cout << "\ndE_rel of " << ladder_solver_name(kind)
              << " n/a (nan in the CSV): its reference's energy is below " << ENERGY_ERROR_FLOOR
              << " of its rungs' largest, so a ratio to it would not measure the rungs' error\n";

  try {
    const std::string text = bench::to_csv(res);
    if (!csv.empty()) write_text_atomic(csv, text);
    if (!plot.empty()) {
      const std::string title = std::filesystem::path(input).filename().string() + ": " +
                                std::to_string(res.frames) + " steps, dt " + bench::fmt(res.dt);
      const bool svg = lower_extension(plot) == "svg";
      const std::string script = bench::gnuplot_script(text, svg, title, res);
      // Through a temporary beside the plot, renamed over it once gnuplot has drawn it whole:
      // a gnuplot that fails (or Ctrl-C) leaves the previous plot as it was.
      try {
        write_file_atomic(plot, [&](std::ostream& out) { bench::draw_with_gnuplot(script, out); });
      } catch (const UsageError& e) {
        throw UsageError("--plot '" + printable(plot) + "' not drawn: " + e.what());
      }
      if (!quiet) std::cerr << "plot written to " << plot << '\n';
    }
  } catch (const UsageError& e) {
    return usage_error("bench error", e.what());
  }
  return static_cast<int>(ExitCode::Success);
}

}  // namespace shellcontract::cli
