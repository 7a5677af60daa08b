// run_error_ladder: references, rungs and the reference convergence check (error_ladder.hpp).
#include "sim/error_ladder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include "core/classic_locale.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/run.hpp"
#include "shellcontract/validation.hpp"
#include "sim/frame_access.hpp"
#include "sim/option_ranges.hpp"
#include "sim/simulator.hpp"

namespace shellcontract {

const char* ladder_solver_name(SolverKind kind) { return kind == SolverKind::Pbd ? "pbd" : "xpbd"; }

const char* ladder_order_name(ConstraintOrder order) {
  return order == ConstraintOrder::Sequential ? "sequential" : "coloured";
}

namespace {

/// The end state of one run.
struct LadderRun {
  bool failed = false;
  std::string failure;
  double ms_per_step = 0.0;
  Positions x;
  double volume_ratio = 1.0;
  double energy = 0.0;
  MassScaling masses;
};

double total_energy(const ConstraintEnergies& e) { return e.membrane + e.bending + e.anisotropic; }

/// One run's solver settings.
struct RunSettings {
  SolverKind kind = SolverKind::Xpbd;
  int iterations = 1;
  int substeps = 1;
  ConstraintOrder order = ConstraintOrder::Sequential;
  int threads = 1;
};

/// Sees one rung's run: the wall time of each base step (its substeps together) and the end
/// state, normalized.
class LadderObserver final : public RunObserver {
 public:
  explicit LadderObserver(int substeps) : substeps_(substeps) {}
  void frame(const FrameView&, const FrameMetrics& m) override {
    seconds_ += m.step_seconds;
    if (m.frame % substeps_ == 0) {
      frame_ms.push_back(1e3 * seconds_);
      seconds_ = 0.0;
    }
  }
  void finished(const FrameView& view, const RunResult&) override {
    const Simulator& sim = simulator_of(view);
    x = view.normalized_positions();
    volume_ratio = view.volume_ratio();
    energy = total_energy(sim.energies());
    masses = sim.mass_scaling();
  }
  std::vector<double> frame_ms;
  Positions x;
  double volume_ratio = 1.0;
  double energy = 0.0;
  MassScaling masses;

 private:
  int substeps_;
  double seconds_ = 0.0;
};

/// Runs frames base steps of `base` with the given solver settings, through run_contraction (the
/// run's one time loop) with a plan of these simulation options alone.
LadderRun run_one(const Mesh& mesh, const SimOptions& base, const RunSettings& rs, int frames,
                  bool collisions) {
  const int substeps = rs.substeps;
  SimOptions o = base;
  o.solver.kind = rs.kind;
  o.solver.iterations = rs.iterations;
  o.solver.order = rs.order;
  o.solver.threads = rs.threads;
  o.dt = base.dt / substeps;
  o.frames = frames * substeps;
  // Same fraction of velocity removed per unit time as the base run (file comment of the header).
  o.damping = 1.0 - std::pow(1.0 - base.damping, 1.0 / substeps);
  o.collisions = collisions;
  o.validate = ValidateMode::Off;
  o.stop_volume_ratio = 0.0;
  RunPlan plan;
  plan.sim = plan_simulation(mesh, o);
  // The pressure's mass floor depends on the step (sim/mass_scaling.hpp): at its own dt a
  // substepped run would have other masses than the base run, another model, and its error
  // against the reference would not be the solver's alone. Every run takes the base step's.
  plan.sim.mass_scaling_dt = base.dt;
  LadderObserver observer(substeps);
  const RunResult result = run_contraction(std::move(plan), &observer);
  LadderRun r;
  if (result.status == RunStatus::SimulationFailed) {
    r.failed = true;
    r.failure = result.message;
  }
  std::vector<double>& frame_ms = observer.frame_ms;
  if (!frame_ms.empty()) {
    // Median, not mean: the machine is shared and a few slow steps should not decide the rung.
    auto mid = frame_ms.begin() + static_cast<std::ptrdiff_t>(frame_ms.size() / 2);
    std::nth_element(frame_ms.begin(), mid, frame_ms.end());
    r.ms_per_step = *mid;
  }
  r.x = std::move(observer.x);
  r.volume_ratio = observer.volume_ratio;
  r.energy = observer.energy;
  r.masses = observer.masses;
  return r;
}

void require_positive(const std::vector<int>& v, const char* what) {
  if (v.empty()) throw UsageError(std::string("error ladder: empty list of ") + what);
  for (int k : v)
    if (k < 1) throw UsageError(std::string("error ladder: ") + what + " must be >= 1");
}

double relative(double a, double ref) {
  const double d = std::abs(a - ref);
  return ref != 0.0 ? d / std::abs(ref) : d;
}

}  // namespace

ErrorLadderResult run_error_ladder(const Mesh& mesh, const SimOptions& base,
                                   const ErrorLadderOptions& opt) {
  if (opt.frames < 1) throw UsageError("error ladder: frames must be >= 1");
  if (opt.solvers.empty()) throw UsageError("error ladder: no solver");
  require_positive(opt.iterations, "iterations");
  require_positive(opt.substeps, "substeps");
  require_positive(opt.threads, "threads");
  if (opt.orders.empty()) throw UsageError("error ladder: no sweep order");
  require_positive({opt.xpbd_reference_iterations, opt.xpbd_reference_substeps,
                    opt.pbd_reference_iterations},
                   "reference iterations and substeps");
  if (!(opt.hausdorff_error_bound > 0.0)) throw UsageError("error ladder: Hausdorff bound must be > 0");
  // A run of k substeps per step takes frames * k steps (run_one): counted in 64 bits and held to
  // a run's frame bound before anything runs, so that no product wraps (a wrapped count ran a
  // reference of a few steps, and every rung was measured against nearly the rest state).
  const bool any_xpbd =
      std::find(opt.solvers.begin(), opt.solvers.end(), SolverKind::Xpbd) != opt.solvers.end();
  std::int64_t most_substeps = 1;
  if (any_xpbd || opt.pbd_substeps)
    most_substeps = *std::max_element(opt.substeps.begin(), opt.substeps.end());
  if (any_xpbd)
    most_substeps = std::max<std::int64_t>(
        most_substeps, std::int64_t{opt.xpbd_reference_substeps} * (opt.check_reference ? 2 : 1));
  if (most_substeps * opt.frames > option_ranges::MAX_FRAMES)
    throw UsageError("error ladder: " + std::to_string(opt.frames) + " frames of " +
                     std::to_string(most_substeps) + " substeps are " +
                     std::to_string(most_substeps * opt.frames) + " steps, more than a run's " +
                     std::to_string(option_ranges::MAX_FRAMES) +
                     ": fewer frames (-n) or substeps (--substeps, --ref-substeps)");

  auto say = [&](const std::string& s) {
    if (opt.progress) opt.progress(s);
  };
  ErrorLadderResult result;
  result.frames = opt.frames;
  result.dt = base.dt;
  result.simulated_time = opt.frames * base.dt;

  // The rest mesh of a Simulator is the normalized, triangulated input: the surface every
  // position array of the runs belongs to (all runs normalize the same input identically).
  SimOptions probe = base;  // only the rest mesh is needed: no collision structures
  probe.collisions = false;
  probe.validate = ValidateMode::Off;
  const Mesh surface = Simulator(mesh, probe).rest_mesh();

  auto compare = [&](const LadderRun& run, const LadderRun& ref, ErrorLadderRow& row) {
    row.ms_per_step = run.ms_per_step;
    row.volume_ratio = run.volume_ratio;
    row.energy = run.energy;
    row.mass_scaled_vertices = run.masses.raised;
    row.largest_mass_factor = run.masses.largest_factor;
    if (run.failed) {
      row.failed = true;
      row.failure = run.failure;
      const double nan = std::numeric_limits<double>::quiet_NaN();
      row.hausdorff = row.max_vertex_error = row.volume_error = row.energy_error = nan;
      return;
    }
    row.hausdorff = symmetric_hausdorff_distance(surface, run.x, ref.x, opt.hausdorff_error_bound);
    row.max_vertex_error = max_vertex_distance(run.x, ref.x);
    row.volume_error = std::abs(run.volume_ratio - ref.volume_ratio);
    row.energy_error = relative(run.energy, ref.energy);
  };
  auto describe = [](const RunSettings& r) {
    ClassicOStringStream s;
    s << ladder_solver_name(r.kind) << " iterations " << r.iterations << " substeps " << r.substeps;
    if (r.order != ConstraintOrder::Sequential)
      s << ' ' << ladder_order_name(r.order) << " threads " << r.threads;
    return s.str();
  };

  for (SolverKind kind : opt.solvers) {
    const bool xpbd = kind == SolverKind::Xpbd;
    const int ref_it = xpbd ? opt.xpbd_reference_iterations : opt.pbd_reference_iterations;
    const int ref_sub = xpbd ? opt.xpbd_reference_substeps : 1;
    const RunSettings ref_settings{kind, ref_it, ref_sub, ConstraintOrder::Sequential, 1};
    say("reference " + describe(ref_settings));
    const LadderRun ref = run_one(mesh, base, ref_settings, opt.frames, opt.collisions);
    if (ref.failed) throw SimulationError("error ladder: the reference (" + describe(ref_settings) + ") failed: " + ref.failure);
    ErrorLadderRow ref_row;
    ref_row.solver = kind;
    ref_row.iterations = ref_it;
    ref_row.substeps = ref_sub;
    compare(ref, ref, ref_row);
    result.reference_rows.push_back(ref_row);
    result.mass_scaled_vertices = ref.masses.raised;  // every run's (run_one)
    result.largest_mass_factor = ref.masses.largest_factor;

    double smallest = std::numeric_limits<double>::infinity();
    double smallest_dv = std::numeric_limits<double>::infinity();
    const std::vector<int> subs = xpbd || opt.pbd_substeps ? opt.substeps : std::vector<int>{1};
    for (int sub : subs)
      for (ConstraintOrder order : opt.orders) {
        const bool serial = order == ConstraintOrder::Sequential;
        for (int threads : serial ? std::vector<int>{1} : opt.threads)
          for (int it : opt.iterations) {
            const RunSettings rs{kind, it, sub, order, threads};
            say("rung " + describe(rs));
            ErrorLadderRow row;
            row.solver = kind;
            row.iterations = it;
            row.substeps = sub;
            row.order = order;
            row.threads = threads;
            compare(run_one(mesh, base, rs, opt.frames, opt.collisions), ref, row);
            // The reference's own settings reproduce it exactly (error 0): not a rung error.
            if (!row.failed && !(it == ref_it && sub == ref_sub && serial)) {
              smallest = std::min(smallest, row.hausdorff);
              smallest_dv = std::min(smallest_dv, row.volume_error);
            }
            result.rows.push_back(row);
          }
      }

    // dE_rel against a reference with next to no energy is not meaningful (ENERGY_ERROR_FLOOR).
    double largest = 0.0;
    for (const ErrorLadderRow& row : result.rows)
      if (row.solver == kind && !row.failed) largest = std::max(largest, std::abs(row.energy));
    const bool energy_meaningful = !(std::abs(ref.energy) < ENERGY_ERROR_FLOOR * largest);
    if (!energy_meaningful) {
      result.energy_error_not_meaningful.push_back(kind);
      for (ErrorLadderRow& row : result.rows)
        if (row.solver == kind) row.energy_error = std::numeric_limits<double>::quiet_NaN();
    }

    if (opt.check_reference) {
      ReferenceCheck c;
      c.solver = kind;
      c.iterations = ref_it;
      c.substeps = ref_sub;
      // Halving the step is a change of model for PBD, so its reference is refined in iterations.
      c.refined_iterations = xpbd ? ref_it : 2 * ref_it;
      c.refined_substeps = xpbd ? 2 * ref_sub : ref_sub;
      c.ms_per_step = ref.ms_per_step;
      const RunSettings fine_settings{kind, c.refined_iterations, c.refined_substeps,
                                      ConstraintOrder::Sequential, 1};
      say("reference check " + describe(fine_settings));
      const LadderRun fine = run_one(mesh, base, fine_settings, opt.frames, opt.collisions);
      ErrorLadderRow d;
      compare(fine, ref, d);
      c.failed = d.failed;
      c.failure = d.failure;
      c.hausdorff = d.hausdorff;
      c.volume_error = d.volume_error;
      c.energy_error =
          energy_meaningful ? d.energy_error : std::numeric_limits<double>::quiet_NaN();
      c.smallest_rung_hausdorff = smallest;
      c.smallest_rung_volume_error = smallest_dv;
      c.converged = !c.failed && c.hausdorff < smallest;
      result.references.push_back(c);
    }
  }
  return result;
}

}  // namespace shellcontract
