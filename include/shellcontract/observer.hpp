// Watching a run: what an observer is told at each frame (a FrameView: the frame's positions, its
// volume and its measurements), and the observer interface that run_contraction calls. The log's
// columns (shellcontract/report.hpp) and the summary's totals are made from these measurements.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "shellcontract/types.hpp"

namespace shellcontract {

/// Counters of one step (CSV log) and the stages of the paper's Table 2.
struct CollisionStepStats {
  std::int64_t pairs_no_culling = 0;  ///< all non-adjacent VF + EE pairs
  std::int64_t pairs_broad = 0;       ///< after the broad phase (broad_phase_inflation)
  std::int64_t pairs_filtered = 0;    ///< left after the box cull and the filter (first round)
  std::int64_t filter_tests = 0;      ///< non-penetration filter evaluations, all passes
  std::int64_t narrow_tests = 0;      ///< narrow-phase queries run, all rounds
  /// narrow-phase queries that separating_axis_culls settled before the interval search (the
  /// rest, narrow_tests - axis_culls, went through the coplanarity cubic's root isolation)
  std::int64_t axis_culls = 0;
  std::int64_t contacts = 0;  ///< contacts found, all rounds
  int rounds = 0;             ///< detection rounds run
  /// Passes that marked the moved vertices' pairs and collected the next tests: over every live
  /// pair, or over the zone around the step's moved vertices (CollisionOptions::narrow_rescans)
  int rescans_full = 0;
  int rescans_in_zone = 0;
  int broad_phase_calls = 0;           ///< broad phases run (one per step, see resolve)
  std::int64_t failsafe_vertices = 0;  ///< vertices reverted to their start position
  std::int64_t unresolved = 0;         ///< static pairs still reported after the fail-safe
  double broad_seconds = 0.0;
  double filter_seconds = 0.0;
  double narrow_seconds = 0.0;
  double response_seconds = 0.0;
  /// 1 if the step's broad phase was the speculative one (SelfCollision::predict), completed for
  /// the actual end positions; 0 if resolve ran it itself.
  int speculative = 0;
  /// Speculative steps: vertices whose swept box left its predicted box (their primitives were
  /// queried again).
  std::int64_t escaped_vertices = 0;
  /// Wall time of the speculative broad phase's task on the spare thread, which overlaps the
  /// constraint solve: not part of `seconds`, which holds what the calling thread spends (in
  /// predict, waiting for the task, completing it).
  double background_seconds = 0.0;
  /// Parts of background_seconds (diagnostics; 0 when it is): the task's grid construction or
  /// patch, the grid's cell loop, the grid's output of the pairs, and the per-pair records. The
  /// rest of the task is bookkeeping between them.
  double background_grid_seconds = 0.0;
  double background_cell_loop_seconds = 0.0;
  double background_output_seconds = 0.0;
  double background_records_seconds = 0.0;
  /// Parts of broad_seconds spent in the step's own (not speculative) broad phase calls, summed
  /// over them (diagnostics; 0 when the grid did not run): the grid's construction or patch, its
  /// cell loop, its output of the pairs, and the per-pair records with the live list. Where a
  /// many-core run loses its speed-up (lab/pages/scale.md).
  double broad_grid_seconds = 0.0;
  double broad_cell_loop_seconds = 0.0;
  double broad_output_seconds = 0.0;
  double broad_records_seconds = 0.0;
  /// Steps with a prediction: the calling thread's time in predict, before the solve (part of
  /// broad_seconds and of seconds).
  double predict_seconds = 0.0;
  /// Steps with a prediction: wall time the calling thread spent on the speculative task after
  /// the solve (waiting for it, or taking over its remaining work; with one thread, running it
  /// all). Part of broad_seconds: the time the task still cost the step.
  double wait_seconds = 0.0;
  /// Wall time the calling thread spends on the step's collision handling: the whole resolve
  /// call (the four stages plus the bookkeeping between them: pair lists, stale marks) and the
  /// step's predict call (also counted in broad_seconds). The collision cost per step that the
  /// logs report.
  double seconds = 0.0;
};

}  // namespace shellcontract

// The constraint energies of a configuration, as plain data (a leaf: a step's measurements,
// shellcontract/observer.hpp, carry them without the solver).
namespace shellcontract {

/// Sum of each kind of constraint energy at a configuration.
struct ConstraintEnergies {
  double membrane = 0.0;     ///< sum Abar psi over membrane faces
  double bending = 0.0;      ///< k_B E_B (isometric) or k_B kappa (theta - theta_bar)^2 (dihedral)
  double anisotropic = 0.0;  ///< sum Abar psi_A over anisotropic faces
};

}  // namespace shellcontract

// One step's measurements, as plain data (a leaf: observers, the log and the totals read them
// without the Simulator).
namespace shellcontract {

/// Per-step measurements (one CSV row of the run log).
struct FrameMetrics {
  int frame = 0;                  ///< 1-based index of the step just taken
  double time = 0.0;              ///< simulated time after the step (normalized units)
  double volume_ratio = 1.0;      ///< V / V0, V from CGAL PMP::volume
  ConstraintEnergies energies;    ///< after the step; zero unless SimOptions::frame_energies
  double max_displacement = 0.0;  ///< max_i |x_i^{n+1} - x_i^n| (normalized units)
  double step_seconds = 0.0;      ///< wall time of the step (predict, solve, collisions, velocity)
  double solve_seconds = 0.0;     ///< wall time of the constraint projection alone
  CollisionStepStats collision;   ///< zero when collisions are off
  /// New self-intersections (face pairs not intersecting in the input) found by CGAL at this
  /// frame; -1 when not validated at this frame.
  long new_intersections = -1;
};

}  // namespace shellcontract

// Per-stage sums of a run: the paper's Table 2 columns (candidate pairs without culling, after
// the broad phase, after the filter, cubic solves) and the time of each stage, reported as means
// per step in the summary.
namespace shellcontract {

class RunTotals {
 public:
  /// Adds one step's measurements.
  void add(const FrameMetrics& m);
  /// (name, value) pairs in a fixed order: means per step over `frames` steps, and the fail-safe
  /// total. The names are the summary's "table2" keys.
  std::vector<std::pair<std::string, double>> per_step(int frames) const;

 private:
  double no_culling_ = 0, broad_ = 0, filtered_ = 0, tests_ = 0, axis_culls_ = 0, contacts_ = 0,
         failsafe_ = 0;
  double broad_calls_ = 0, filter_tests_ = 0, rounds_ = 0, speculative_ = 0, escaped_ = 0,
         background_s_ = 0, wait_s_ = 0, bg_grid_s_ = 0, bg_cells_s_ = 0, bg_output_s_ = 0,
         bg_records_s_ = 0, predict_s_ = 0, rescans_full_ = 0, rescans_in_zone_ = 0;
  double grid_s_ = 0, cells_s_ = 0, output_s_ = 0, records_s_ = 0;
  double broad_s_ = 0, filter_s_ = 0, narrow_s_ = 0, response_s_ = 0, collision_s_ = 0,
         solve_s_ = 0, step_s_ = 0;
};


class Simulator;  // the library's own (not part of the public headers)
struct RunResult;  // shellcontract/run.hpp

/// What an observer sees of a run at one frame: read-only, and valid only during the callback
/// that received it.
class FrameView {
 public:
  /// Made by run_contraction.
  explicit FrameView(const Simulator& sim) : sim_(&sim) {}
  /// The number of steps taken: 0 at the rest state, then 1, 2, ...
  int frame() const;
  /// Whether the run ends at this frame (its frame count, its stop ratio or its target).
  bool last() const;
  /// V / V0 at this frame.
  double volume_ratio() const;
  /// The vertex positions in the input's units, row i = vertex i (a copy).
  Positions positions() const;
  /// The vertex positions in the run's normalized units (the mesh scaled to a unit bounding-box
  /// diagonal, centred), without a copy.
  const Positions& normalized_positions() const;
  /// The number of regions the local contraction acts on.
  std::size_t regions() const;

 private:
  const Simulator* sim_;
  friend const Simulator& simulator_of(const FrameView& view);  // the library's exporters
};

/// Sees a run. Every callback runs on the thread that called run_contraction, also while other
/// threads of the process run the library at once (each run works in a task arena of its own),
/// and never inside the run's parallel work: between steps, or in the preparation between its
/// stages (stage(), and cancelled() there). A callback may start a run of its own.
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  /// Something the user should know (degenerate faces, no regions found, ...), as it is found.
  virtual void warning(const std::string& /*text*/) {}
  /// The run enters a stage that can take seconds on a large mesh, in the order they run: the
  /// preparation's ("selecting the regions (curvature)", "building the rest state", "finding the
  /// contact pairs at rest", ...) before started(), and "checking the result for
  /// self-intersections" in the last step (`validate` end), before its frame(). A few words for
  /// a person; the set of stages may change. A stage lasts until the next one, started(),
  /// frame() or finished(); not called otherwise between steps.
  virtual void stage(const std::string& /*what*/) {}
  /// The run is prepared, before its first step: frame 0, the rest state (a resumed run: the
  /// checkpoint's frame).
  virtual void started(const FrameView& /*view*/) {}
  /// After each step, with its measurements.
  virtual void frame(const FrameView& /*view*/, const FrameMetrics& /*metrics*/) {}
  /// Polled after every step and in the run's preparation (run.hpp): true ends it, Cancelled.
  virtual bool cancelled() { return false; }
  /// After the last step, before run_contraction returns.
  virtual void finished(const FrameView& /*view*/, const RunResult& /*result*/) {}
};

/// Several observers in order.
class ObserverList final : public RunObserver {
 public:
  void add(RunObserver& o) { observers_.push_back(&o); }
  void warning(const std::string& text) override;
  void stage(const std::string& what) override;
  void started(const FrameView& view) override;
  void frame(const FrameView& view, const FrameMetrics& m) override;
  bool cancelled() override;
  void finished(const FrameView& view, const RunResult& r) override;

 private:
  std::vector<RunObserver*> observers_;
};

}  // namespace shellcontract
