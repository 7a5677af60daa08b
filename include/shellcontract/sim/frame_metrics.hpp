// One step's measurements, as plain data (a leaf: observers, the log and the totals read them
// without the Simulator).
#pragma once

#include "shellcontract/collision/collision_stats.hpp"
#include "shellcontract/pbd/constraint_energies.hpp"

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
