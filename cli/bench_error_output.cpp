// bench error's outputs (bench_error_output.hpp): the tables, the CSV, the gnuplot script and
// gnuplot's run.
#include "bench_error_output.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <sstream>

#include "core/classic_locale.hpp"
#include "core/decimal_text.hpp"
#include "mesh/file_safety.hpp"
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
       // A space before each count: a reference's iterations (--ref-iterations, up to 100000) would
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

/// gnuplot commands drawing hausdorff (log) against ms_per_step (log) from the CSV text `csv`
/// (to_csv) on gnuplot's stdout: one line per solver, substep count, order and thread count
/// (points labelled by iterations), and each reference's own error (its check) as a star. The same
/// plot as lab/scripts/plot_speed_error.sh.
std::string gnuplot_script(const std::string& csv, bool svg, const std::string& title,
                           const ErrorLadderResult& res) {
  ClassicOStringStream g;
  g << (svg ? "set terminal svg size 900,640 dynamic font 'sans,12'\n"
            : "set terminal pngcairo size 900,640 font 'sans,11'\n");
  // The data in the script (a datablock: no CSV line is "EOD"), the plot on stdout: gnuplot is
  // handed no file name, which it could read as a command ('|...', '<...') or end at a quote.
  g << "set output\n"
    << "$data << EOD\n"
    << csv << "EOD\n"
    << "set datafile separator ','\n"
    << "set logscale xy\n"
    << "set grid\n"
    << "set key below\n"
    << "set xlabel 'wall time per step (ms, median)'\n"
    << "set ylabel 'Hausdorff distance to the reference (normalized units)'\n"
    << "set title " << gnuplot_quoted(title) << " noenhanced\n";
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
    g << "$data skip 1 using 8:" << sel << " with linespoints lt " << style << " dt " << dash
      << " pt " << point << " title '" << title << "', \\\n     $data skip 1 using 8:" << sel
      << ":3 with labels offset char 0.8,0.6 font ',8' tc lt " << style << " notitle, \\\n     ";
  }
  g << "$data skip 1 using 8:(strcol(1) eq 'reference_check' && $9 > 0 ? $9 : 1/0)"
    << " with points pt 3 ps 2 lc rgb 'black' title 'each reference vs its refinement (its own "
       "error)', \\\n     $data skip 1 using 8:(strcol(1) eq 'reference_check' && $9 > 0 ? $9 : "
       "1/0):(strcol(2).' "
       "reference')"
    << " with labels offset char 0,-1 font ',8' notitle\n";
  return g.str();
}

namespace {

/// Writes the whole of `text` to the non-blocking descriptor `fd` from `done` on, as far as it
/// takes it now. False when gnuplot stopped reading (EPIPE: it exited; SIGPIPE is ignored by
/// the CLI, cli/entry.cpp), so that the rest is dropped and its exit status tells.
bool feed(int fd, const std::string& text, std::size_t& done) {
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return true;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

}  // namespace

std::string gnuplot_quoted(const std::string& text) {
  // printable: no newline or other control byte, which would end gnuplot's command; in a
  // single-quoted string gnuplot expands neither backquotes nor @macros, and '' is a quote.
  std::string q = "'";
  for (const char c : printable(text)) q += c == '\'' ? std::string("''") : std::string(1, c);
  return q + "'";
}

void draw_with_gnuplot(const std::string& script, std::ostream& out) {
  // gnuplot gets the script on its stdin and draws on its stdout (`set output` without a name),
  // so it is handed no file name at all: a name starting with '|' or '<' is a command to it.
  int in[2] = {-1, -1}, from[2] = {-1, -1};
  if (::pipe2(in, O_CLOEXEC) != 0 || ::pipe2(from, O_CLOEXEC) != 0) {
    const int e = errno;
    close_fd(in[0]);
    close_fd(in[1]);
    throw UsageError(std::string("cannot start gnuplot: ") + std::strerror(e));
  }
  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attr;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in[0], 0);
  posix_spawn_file_actions_adddup2(&actions, from[1], 1);
  posix_spawnattr_init(&attr);
  // No signal blocked in gnuplot (the caller's thread may block some): Ctrl-C ends it too.
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK);
  char name[] = "gnuplot";
  char* args[] = {name, nullptr};
  pid_t pid = -1;
  const int spawned = ::posix_spawnp(&pid, name, &actions, &attr, args, environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  close_fd(in[0]);
  close_fd(from[1]);
  if (spawned != 0) {
    close_fd(in[1]);
    close_fd(from[0]);
    throw UsageError(std::string("cannot start gnuplot: ") + std::strerror(spawned));
  }
  // The script is written while the plot is read, so that neither pipe can fill and stall both.
  ::fcntl(in[1], F_SETFL, ::fcntl(in[1], F_GETFL) | O_NONBLOCK);
  std::size_t done = 0;
  std::uint64_t drawn = 0;
  int read_error = 0;
  char buf[65536];
  for (;;) {
    if (in[1] >= 0 && (!feed(in[1], script, done) || done == script.size())) close_fd(in[1]);
    pollfd fds[2] = {{from[0], POLLIN, 0}, {in[1], POLLOUT, 0}};
    if (::poll(fds, in[1] >= 0 ? 2 : 1, -1) < 0) {
      if (errno == EINTR) continue;
      read_error = errno;
      break;
    }
    if (fds[0].revents == 0) continue;
    const ssize_t n = ::read(from[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) read_error = errno;
    if (n <= 0) break;
    out.write(buf, n);
    drawn += static_cast<std::uint64_t>(n);
  }
  close_fd(in[1]);
  close_fd(from[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (read_error != 0)
    throw UsageError(std::string("cannot read gnuplot's plot: ") + std::strerror(read_error));
  if (WIFSIGNALED(status))
    throw UsageError("gnuplot was killed by signal " + std::to_string(WTERMSIG(status)));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw UsageError(WEXITSTATUS(status) == 127
                         ? std::string("gnuplot could not be run")
                         : "gnuplot failed (exit " + std::to_string(WEXITSTATUS(status)) + ")");
  if (drawn == 0) throw UsageError("gnuplot drew nothing");
}

bool gnuplot_available() { return std::system("command -v gnuplot > /dev/null 2>&1") == 0; }

}  // namespace shellcontract::cli::bench
