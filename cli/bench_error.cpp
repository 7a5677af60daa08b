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

#include "command_line.hpp"
#include "commands.hpp"
#include "core/classic_locale.hpp"
#include "core/decimal_text.hpp"
#include "core/list_text.hpp"
#include "mesh/file_safety.hpp"
#include "output_paths.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "sim/error_ladder.hpp"

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
            failing), 2 bad input mesh, 3 a reference run failed (blow-up))";

/// run's bound on --frames (its option table's), for bench error's --frames.
constexpr long MAX_BENCH_FRAMES = 1000000;

/// Parses "1,2,5" into integers in [1, most]: a list as every list option takes one
/// (core/list_text.hpp), each item as an integer option's (parse_decimal_integer), each once.
std::vector<int> parse_list(const std::string& list, const char* option, long most) {
  std::vector<std::string> items;
  std::string why;
  if (!split_list(list, items, why))
    throw UsageError(std::string(option) + ": '" + list + "': " + why);
  std::vector<int> out;
  for (const std::string& item : items) {
    long v = 0;
    if (!parse_decimal_integer(item, v) || v < 1 || v > most)
      throw UsageError(std::string(option) + ": '" + item + "' is not an integer in [1, " +
                       std::to_string(most) + "]");
    if (std::find(out.begin(), out.end(), v) != out.end())
      throw UsageError(std::string(option) + ": " + item + " is given twice");
    out.push_back(static_cast<int>(v));
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

std::string fmt(double v, int precision = 3, const char* nan_text = "failed") {
  if (std::isnan(v)) return nan_text;
  ClassicOStringStream s;
  s << std::setprecision(precision) << v;
  return s.str();
}

void print_rows(const std::vector<ErrorLadderRow>& rows, std::ostream& os) {
  os << std::left << std::setw(7) << "solver" << std::setw(11) << "order" << std::right
     << std::setw(4) << "thr" << std::setw(6) << "iter" << std::setw(5) << "sub" << std::setw(13) << "ms_per_step" << std::setw(12) << "hausdorff"
     << std::setw(12) << "max_vertex" << std::setw(9) << "V/V0" << std::setw(11) << "dV"
     << std::setw(11) << "dE_rel" << '\n';
  for (const ErrorLadderRow& r : rows) {
    os << std::left << std::setw(7) << ladder_solver_name(r.solver) << std::setw(11)
       << ladder_order_name(r.order) << std::right << std::setw(4) << r.threads << std::setw(6)
       << r.iterations << std::setw(5) << r.substeps << std::setw(13) << fmt(r.ms_per_step)
       << std::setw(12) << fmt(r.hausdorff) << std::setw(12) << fmt(r.max_vertex_error)
       << std::setw(9) << fmt(r.volume_ratio, 4) << std::setw(11) << fmt(r.volume_error)
       << std::setw(11) << fmt(r.energy_error, 3, r.failed ? "failed" : "n/a") << '\n';
  }
}

void print_checks(const std::vector<ReferenceCheck>& checks, std::ostream& os) {
  for (const ReferenceCheck& c : checks) {
    os << ladder_solver_name(c.solver) << " reference (" << c.iterations << " iterations, "
       << c.substeps << " substeps) vs (" << c.refined_iterations << " iterations, "
       << c.refined_substeps << " substeps): ";
    if (c.failed) {
      os << "refined run failed: " << c.failure << '\n';
      continue;
    }
    os << "hausdorff " << fmt(c.hausdorff) << ", dV " << fmt(c.volume_error) << ", dE_rel "
       << fmt(c.energy_error, 3, "n/a") << "; smallest rung hausdorff "
       << fmt(c.smallest_rung_hausdorff) << ", dV " << fmt(c.smallest_rung_volume_error) << " -> "
       << (c.converged ? "converged" : "NOT converged") << '\n';
  }
}

/// CSV: one row per rung ("rung"), per reference ("reference", errors 0) and per reference
/// check ("reference_check": the refined run's errors against the reference, at the
/// reference's ms_per_step). Every number in the shortest form that reads back as the same
/// double, so the table can be recomputed; a NaN (a failed run's errors, a dE_rel that is not
/// meaningful) is "nan". The order and threads columns come last, so readers of the older
/// 13-column files still find theirs.
std::string to_csv(const ErrorLadderResult& res) {
  ClassicOStringStream s;
  const auto n = [](double v) { return shortest_text(v); };
  s << "row_type,solver,iterations,substeps,frames,dt,failed,ms_per_step,hausdorff,"
       "max_vertex_error,volume_ratio,volume_error,energy_error,order,threads\n";
  auto row = [&](const char* type, const ErrorLadderRow& r) {
    s << type << ',' << ladder_solver_name(r.solver) << ',' << r.iterations << ',' << r.substeps
      << ',' << res.frames << ',' << n(res.dt) << ',' << (r.failed ? 1 : 0) << ','
      << n(r.ms_per_step) << ',' << n(r.hausdorff) << ',' << n(r.max_vertex_error) << ','
      << n(r.volume_ratio) << ',' << n(r.volume_error) << ',' << n(r.energy_error) << ','
      << ladder_order_name(r.order) << ',' << r.threads << '\n';
  };
  for (const ErrorLadderRow& r : res.rows) row("rung", r);
  for (const ErrorLadderRow& r : res.reference_rows) row("reference", r);
  for (const ReferenceCheck& c : res.references) {
    s << "reference_check," << ladder_solver_name(c.solver) << ',' << c.refined_iterations << ','
      << c.refined_substeps << ',' << res.frames << ',' << n(res.dt) << ',' << (c.failed ? 1 : 0)
      << ',' << n(c.ms_per_step) << ',' << n(c.hausdorff) << ",," << ',' << n(c.volume_error) << ','
      << n(c.energy_error) << ",sequential,1\n";
  }
  return s.str();
}

/// gnuplot commands drawing hausdorff (log) against ms_per_step (log) from the CSV: one line per
/// solver, substep count, order and thread count (points labelled by iterations), and each reference's own error
/// (its check) as a star. The same plot as lab/scripts/plot_speed_error.sh.
std::string gnuplot_script(const std::string& csv, const std::string& out, const std::string& title,
                           const ErrorLadderResult& res) {
  const bool svg = std::filesystem::path(out).extension() == ".svg";
  ClassicOStringStream g;
  g << (svg ? "set terminal svg size 900,640 dynamic font 'sans,12'\n"
            : "set terminal pngcairo size 900,640 font 'sans,11'\n");
  g << "set output '" << out << "'\n"
    << "set datafile separator ','\n"
    << "set logscale xy\n"
    << "set grid\n"
    << "set key below\n"
    << "set xlabel 'wall time per step (ms, median)'\n"
    << "set ylabel 'Hausdorff distance to the reference (normalized units)'\n"
    << "set title '" << title << "' noenhanced\n";
  // Series: (solver, substeps, order, threads) present among the rungs, in run order.
  std::vector<std::tuple<SolverKind, int, ConstraintOrder, int>> series;
  for (const ErrorLadderRow& r : res.rows) {
    const auto k = std::make_tuple(r.solver, r.substeps, r.order, r.threads);
    if (std::find(series.begin(), series.end(), k) == series.end()) series.push_back(k);
  }
  g << "plot ";
  // One colour per (solver, substeps); the order and threads show in the line and point style
  // (solid dots: sequential; dashed squares: coloured on 1 thread; dotted triangles: more).
  std::vector<std::pair<SolverKind, int>> colours;
  for (const auto& [kind, sub, order, threads] : series) {
    const std::pair<SolverKind, int> c{kind, sub};
    if (std::find(colours.begin(), colours.end(), c) == colours.end()) colours.push_back(c);
    const int style = 1 + static_cast<int>(std::find(colours.begin(), colours.end(), c) - colours.begin());
    const bool serial = order == ConstraintOrder::Sequential;
    const int point = serial ? 7 : threads == 1 ? 5 : 9;
    const int dash = serial ? 1 : threads == 1 ? 2 : 3;
    const std::string name = ladder_solver_name(kind);
    const std::string order_name = ladder_order_name(order);
    const std::string sel = "(strcol(1) eq 'rung' && strcol(2) eq '" + name +
                            "' && $4 == " + std::to_string(sub) + " && strcol(14) eq '" +
                            order_name + "' && $15 == " + std::to_string(threads) +
                            " && $9 > 0 ? $9 : 1/0)";
    std::string title = name + ", " + std::to_string(sub) + (sub == 1 ? " substep" : " substeps");
    if (order != ConstraintOrder::Sequential)
      title += ", " + order_name + " " + std::to_string(threads) + (threads == 1 ? " thread" : " threads");
    g << "'" << csv << "' skip 1 using 8:" << sel << " with linespoints lt " << style
      << " dt " << dash << " pt " << point << " title '" << title
      << "', \\\n     '" << csv << "' skip 1 using 8:" << sel
      << ":3 with labels offset char 0.8,0.6 font ',8' tc lt " << style << " notitle, \\\n     ";
  }
  g << "'" << csv << "' skip 1 using 8:(strcol(1) eq 'reference_check' && $9 > 0 ? $9 : 1/0)"
    << " with points pt 3 ps 2 lc rgb 'black' title 'each reference vs its refinement (its own error)', \\\n     '"
    << csv << "' skip 1 using 8:(strcol(1) eq 'reference_check' && $9 > 0 ? $9 : 1/0):(strcol(2).' reference')"
    << " with labels offset char 0,-1 font ',8' notitle\n";
  return g.str();
}

/// The folders for the plot's temporary CSV, chosen before the (long) runs: of $TMPDIR, /tmp and
/// /var/tmp, those in which a temporary file can be created and written (one byte, removed at
/// once), in that order, as Python's tempfile and mkstemp-based tools fall back (a TMPDIR set to
/// a folder that is gone is common in batch jobs). A real file, not access(): as root access()
/// passes for any folder of a writable mount (TMPDIR=/proc), and a full disk passes it too; the
/// file then failed after every run of the benchmark.
/// @throws UsageError when none takes one
std::vector<std::string> temporary_folders() {
  std::vector<std::string> candidates, usable;
  if (const char* env = std::getenv("TMPDIR"); env != nullptr && *env != '\0')
    candidates.push_back(env);
  candidates.insert(candidates.end(), {"/tmp", "/var/tmp"});
  std::string why;
  for (const std::string& folder : candidates) {
    std::error_code ec;
    if (!std::filesystem::is_directory(folder, ec)) {
      why += "; " + folder + ": not a folder";
      continue;
    }
    RegisteredTemporary t = create_registered_temporary(folder, "shellcontract_bench_error.csv");
    if (t.fd < 0) {
      why += "; " + folder + ": " + std::strerror(errno);
      continue;
    }
    ssize_t n = -1;
    do n = ::write(t.fd, "x", 1);
    while (n < 0 && errno == EINTR);
    const int e = n == 1 ? 0 : n < 0 ? errno : EIO;
    ::close(t.fd);
    ::unlink(t.path.c_str());
    unregister_temporary(t.slot);
    if (e == 0)
      usable.push_back(folder);
    else
      why += "; " + folder + ": " + std::strerror(e);
  }
  if (usable.empty())
    throw UsageError(
        "--plot without --csv needs a temporary file, and none of $TMPDIR, /tmp, "
        "/var/tmp takes one (" +
        why.substr(2) + "): give --csv FILE");
  return usable;
}

/// A new temporary file holding text, in the first of `folders` (temporary_folders) where it can
/// be written whole (a folder that filled up during the runs passes to the next), created
/// exclusively and registered for removal on SIGINT and SIGTERM (mesh/file_safety.hpp), so that
/// no file already there is replaced and none is left behind by Ctrl-C; the caller removes it and
/// unregisters. An empty path (fd -1) and `error` set when no folder takes it.
RegisteredTemporary temporary_csv(const std::vector<std::string>& folders, const std::string& text,
                                  std::string& error) {
  for (const std::string& folder : folders) {
    RegisteredTemporary t = create_registered_temporary(folder, "shellcontract_bench_error.csv");
    if (t.fd < 0) {
      error += std::string(error.empty() ? "" : "; ") + "cannot create a temporary file in '" +
               folder + "': " + std::strerror(errno);
      continue;
    }
    std::size_t done = 0;
    int e = 0;
    while (done < text.size() && e == 0) {
      const ssize_t n = ::write(t.fd, text.data() + done, text.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0)
        e = n < 0 ? errno : EIO;
      else
        done += static_cast<std::size_t>(n);
    }
    ::close(t.fd);
    t.fd = -1;
    if (e == 0) return t;
    ::unlink(t.path.c_str());
    unregister_temporary(t.slot);
    error += std::string(error.empty() ? "" : "; ") + "cannot write the temporary file '" + t.path +
             "': " + std::strerror(e);
  }
  return {};
}

bool gnuplot_available() { return std::system("command -v gnuplot > /dev/null 2>&1") == 0; }

}  // namespace

int command_bench_error(int argc, char** argv) {
  std::vector<std::string> temp_folders;  // for the plot's CSV when --csv is not given
  std::string input, csv, plot, solver = "both", iterations = "1,2,5,10,20,50", substeps = "1,2,4";
  std::string collisions = "off", orders = "sequential", threads = "1";
  ErrorLadderOptions opt;
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
      "ref-iterations",
      po::value<int>(&opt.xpbd_reference_iterations)->default_value(opt.xpbd_reference_iterations),
      "XPBD reference sweeps per substep")(
      "ref-substeps",
      po::value<int>(&opt.xpbd_reference_substeps)->default_value(opt.xpbd_reference_substeps),
      "XPBD reference substeps")(
      "pbd-ref-iterations",
      po::value<int>(&opt.pbd_reference_iterations)->default_value(opt.pbd_reference_iterations),
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
    opt.iterations = parse_list(iterations, "--iterations", 100000);
    opt.substeps = parse_list(substeps, "--substeps", 100000);
    opt.threads = parse_list(threads, "--threads", 4096);
    opt.orders = parse_orders(orders);
    opt.check_reference = !no_check;
    // run's grammar and upper bound for --frames; 0 frames would compare nothing.
    long frames = 0;
    if (!parse_decimal_integer(frames_text, frames) || frames < 1 || frames > MAX_BENCH_FRAMES)
      throw UsageError("--frames: '" + frames_text + "' is not an integer in [1, " +
                       std::to_string(MAX_BENCH_FRAMES) + "]");
    opt.frames = static_cast<int>(frames);
    base.dt = run_value("dt", dt_text).sim.dt;
    if (pressure_text.find(':') != std::string::npos)
      throw UsageError("--pressure: '" + pressure_text +
                       "': bench error takes one pressure, not keyframes");
    base.pressure = run_value("pressure", pressure_text).sim.pressure;
    if (opt.xpbd_reference_iterations < 1 || opt.xpbd_reference_substeps < 1 || opt.pbd_reference_iterations < 1)
      throw UsageError("reference iterations and substeps must be >= 1");
    if (!plot.empty()) {
      const auto ext = std::filesystem::path(plot).extension();
      if (ext != ".png" && ext != ".svg") throw UsageError("--plot: expected a .png or .svg file, got '" + plot + "'");
      // Checked before the (long) runs, not after.
      if (!gnuplot_available())
        throw UsageError("--plot needs gnuplot, which is not installed (Debian: apt-get install gnuplot-nox)");
      if (csv.empty()) temp_folders = temporary_folders();
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
              << fmt(res.largest_mass_factor) << " times), the same in every run\n";
  std::cout << '\n';
  print_rows(res.rows, std::cout);
  std::cout << "\nreferences (errors 0 by definition):\n";
  print_rows(res.reference_rows, std::cout);
  if (!res.references.empty()) {
    std::cout << "\nreference check:\n";
    print_checks(res.references, std::cout);
  }
  for (SolverKind kind : res.energy_error_not_meaningful)
    std::cout << "\ndE_rel of " << ladder_solver_name(kind)
              << " n/a (nan in the CSV): its reference's energy is below " << ENERGY_ERROR_FLOOR
              << " of its rungs' largest, so a ratio to it would not measure the rungs' error\n";

  try {
    std::string data_file = csv;
    const std::string text = to_csv(res);
    if (!csv.empty()) write_text_atomic(csv, text);
    if (!plot.empty()) {
      // gnuplot reads the CSV; without --csv it goes to a temporary file removed afterwards.
      RegisteredTemporary temporary;
      if (data_file.empty()) {
        std::string error;
        temporary = temporary_csv(temp_folders, text, error);
        if (temporary.path.empty()) {
          // Not bad usage (no hint to --help): the folders took a file before the runs.
          std::cerr << "shellcontract bench error: --plot: " << error << "; no plot drawn (--csv "
                    << "FILE keeps the data; the table is on stdout)\n";
          return static_cast<int>(ExitCode::BadUsage);
        }
        data_file = temporary.path;
      }
      const std::string title = std::filesystem::path(input).filename().string() + ": " +
                                std::to_string(res.frames) + " steps, dt " + fmt(res.dt);
      const std::string script = gnuplot_script(data_file, plot, title, res);
      FILE* pipe = ::popen("gnuplot", "w");
      int status = -1;
      if (pipe) {
        std::fwrite(script.data(), 1, script.size(), pipe);
        status = ::pclose(pipe);
      }
      if (csv.empty()) {
        ::unlink(data_file.c_str());
        unregister_temporary(temporary.slot);
      }
      if (status != 0) throw UsageError("gnuplot failed to draw '" + plot + "'");
      if (!quiet) std::cerr << "plot written to " << plot << '\n';
    }
  } catch (const UsageError& e) {
    return usage_error("bench error", e.what());
  }
  return static_cast<int>(ExitCode::Success);
}

}  // namespace shellcontract::cli
