// Per-stage sums of a run: the paper's Table 2 columns (candidate pairs without culling, after
// the broad phase, after the filter, cubic solves) and the time of each stage, reported as means
// per step in the summary.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "shellcontract/sim/frame_metrics.hpp"

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

}  // namespace shellcontract
