// Counters and stage times of one step of the collision handling (CSV log, the paper's
// Table 2).
#pragma once

#include <cstdint>

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
