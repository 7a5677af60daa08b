// A stage's wall time, read once or added to a statistics field: one clock for every stage the
// collision statistics report (CollisionStepStats, the broad phase's grid parts).
#pragma once

#include <chrono>

namespace shellcontract {

/// Starts at construction (or restart()); elapsed() is the wall time since then, in seconds, on
/// std::chrono::steady_clock.
class StageTimer {
 public:
  using Clock = std::chrono::steady_clock;

  StageTimer() : start_(Clock::now()) {}

  /// Seconds since the start.
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

  /// Adds elapsed() to `total` (a statistics field that sums a stage over a step).
  void add_to(double& total) const { total += elapsed(); }

  /// Starts again now.
  void restart() { start_ = Clock::now(); }

 private:
  Clock::time_point start_;
};

}  // namespace shellcontract
