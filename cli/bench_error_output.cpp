// bench error's outputs (bench_error_output.hpp): the tables, the CSV, the gnuplot script and
// the plot's temporary CSV.
#include "bench_error_output.hpp"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "core/classic_locale.hpp"
#include "core/decimal_text.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract::cli::bench {

std::string fmt(double v, int precision, const char* nan_text) {
  if (std::isnan(v)) return nan_text;
  ClassicOStringStream s;
  s << std::setprecision(precision) << v;
  return s.str();
}

void print_rows(const std::vector<ErrorLadderRow>& rows, std::ostream& os) {
  os << std::left << std::setw(7) << "solver" << std::setw(11) << "order" << std::right
     << std::setw(5) << "thr" << std::setw(8) << "iter" << std::setw(7) << "sub" << std::setw(13)
     << "ms_per_step" << std::setw(12) << "hausdorff" << std::setw(12) << "max_vertex"
     << std::setw(9) << "V/V0" << std::setw(11) << "dV" << std::setw(11) << "dE_rel" << '\n';
  for (const ErrorLadderRow& r : rows) {
    os << std::left << std::setw(7) << ladder_solver_name(r.solver) << std::setw(11)
       << ladder_order_name(r.order)
       << std::right
       // A space before each count: a reference's iterations (--ref-iterations, any int) would
       // otherwise run into the threads' column.
       << ' ' << std::setw(4) << r.threads << ' ' << std::setw(7) << r.iterations << ' '
       << std::setw(6) << r.substeps << std::setw(13) << fmt(r.ms_per_step) << std::setw(12)
       << fmt(r.hausdorff) << std::setw(12) << fmt(r.max_vertex_error) << std::setw(9)
       << fmt(r.volume_ratio, 4) << std::setw(11) << fmt(r.volume_error) << std::setw(11)
       << fmt(r.energy_error, 3, r.failed ? "failed" : "n/a") << '\n';
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
/// solver, substep count, order and thread count (points labelled by iterations), and each
/// reference's own error (its check) as a star. The same plot as lab/scripts/plot_speed_error.sh.
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
    const int style =
        1 + static_cast<int>(std::find(colours.begin(), colours.end(), c) - colours.begin());
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
      title += ", " + order_name + " " + std::to_string(threads) +
               (threads == 1 ? " thread" : " threads");
    g << "'" << csv << "' skip 1 using 8:" << sel << " with linespoints lt " << style << " dt "
      << dash << " pt " << point << " title '" << title << "', \\\n     '" << csv
      << "' skip 1 using 8:" << sel << ":3 with labels offset char 0.8,0.6 font ',8' tc lt "
      << style << " notitle, \\\n     ";
  }
  g << "'" << csv << "' skip 1 using 8:(strcol(1) eq 'reference_check' && $9 > 0 ? $9 : 1/0)"
    << " with points pt 3 ps 2 lc rgb 'black' title 'each reference vs its refinement (its own "
       "error)', \\\n     '"
    << csv
    << "' skip 1 using 8:(strcol(1) eq 'reference_check' && $9 > 0 ? $9 : 1/0):(strcol(2).' "
       "reference')"
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

}  // namespace shellcontract::cli::bench
