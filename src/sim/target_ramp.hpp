// The ramp a run uses: its target volume's and its regions' sink (simulator.cpp,
// simulator_regions.cpp), and what the summary records of it (run_report.cpp).
#pragma once

#include <algorithm>

#include "shellcontract/simulation_options.hpp"

namespace shellcontract {

/// SimOptions::target_ramp_frames, at most half the run's frames (at least 1): a run shorter
/// than twice the ramp still reaches its target at half its frames.
inline int target_ramp_used(const SimOptions& o) {
  return std::min(o.target_ramp_frames, std::max(1, o.frames / 2));
}

}  // namespace shellcontract
