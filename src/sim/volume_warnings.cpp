// The end-of-run warnings on the volume (sim/volume_warnings.hpp).
#include "sim/volume_warnings.hpp"

#include <algorithm>
#include <cstddef>

#include "core/decimal_text.hpp"

namespace shellcontract {

namespace {

/// "%.3g" as the "C" locale writes it, whatever locale a host program set.
std::string ratio_text(double r) { return general_text(r, 3); }

}  // namespace

std::vector<std::string> drive_warnings(const SimOptions& s, bool regions_act) {
  std::vector<std::string> out;
  const Schedule& keys = s.pressure_schedule;
  // With keys, `pressure` is the largest key; the smallest says whether any frame inflates.
  const double most = keys.empty() ? s.pressure : keys.max_value();
  const double least = keys.empty() ? s.pressure : keys.min_value();
  const bool target = s.target_volume > 0.0 || !s.target_volume_schedule.empty();
  const bool other = target || regions_act || s.bending == BendingModel::Isometric;
  if (other || most > 0.0) return out;
  const std::string stop = s.stop_volume_ratio > 0.0
                               ? "`stop_volume_ratio` " + general_text(s.stop_volume_ratio, 6)
                               : std::string();
  if (least == 0.0) {
    out.push_back(
        "nothing drives this run: `pressure` is 0, there is no `target_volume`, and neither "
        "regions (`regions`, `region_at`, `region_weights`) nor `aniso` contract the shell, so "
        "the mesh stays at rest and the result is the input" +
        (stop.empty() ? std::string() : "; " + stop + " cannot be reached") +
        ". Give `pressure` > 0 to compress the shell (< 0 inflates it) or a `target_volume`");
  } else if (!stop.empty()) {
    out.push_back(stop + " cannot be reached: `pressure` " +
                  (keys.empty() ? general_text(s.pressure, 6) : "(its keys)") +
                  " is not > 0, so it inflates the shell (V/V0 grows) and nothing contracts it; "
                  "the run uses every frame and ends with the ratio not reached. Give `pressure` "
                  "> 0 to compress the shell");
  }
  return out;
}

std::vector<std::string> volume_warnings(const std::vector<double>& history, bool compressed) {
  std::vector<std::string> out;
  if (history.size() < 2) return out;
  // The second half of the frames: the start of a run may fall fast (a collapse under a large
  // pressure), but it does not go back up by as much.
  const std::size_t frames = history.size() - 1;
  bool rose = false, fell = false;
  double low = history.back(), high = history.back();
  for (std::size_t n = frames - frames / 2; n + 1 < history.size(); ++n) {
    const double a = history[n], b = history[n + 1];
    low = std::min({low, a, b});
    high = std::max({high, a, b});
    if (!(a > 0.0 && b > 0.0)) continue;  // inside out: named by the negative V/V0's own warning
    rose = rose || b > SWING_FACTOR * a;
    fell = fell || a > SWING_FACTOR * b;
  }
  if (rose && fell) {
    out.push_back("V/V0 swung between " + ratio_text(low) + " and " + ratio_text(high) +
                  " from frame to frame in the second half of the run (more than a factor " +
                  ratio_text(SWING_FACTOR) +
                  " up and down), so its last value means little: the pressure is an explicit "
                  "load, and on a very thin shell the air's (`air_balance`) overshoots every step; "
                  "a smaller `dt` or `air_balance` 0 settles it");
    return out;
  }
  const double last = history.back();
  if (compressed && last > GROWTH_WARNING_RATIO)
    out.push_back("V/V0 ended at " + ratio_text(last) +
                  ", above 1 although the outside pressure compresses the shell: it grew. Likely "
                  "causes: pairs of primitives that the contacts push apart beyond their rest "
                  "gap (named at the start, if any: a thin shell whose sheets lie closer than "
                  "twice `delta`), or a time step too large for a very thin shell (a smaller "
                  "`dt`)");
  return out;
}

std::string frozen_warning(double reverted, std::size_t vertices, int steps) {
  const double moves = static_cast<double>(vertices) * static_cast<double>(steps);
  if (!(steps > 0 && vertices > 0 && reverted >= FROZEN_SHARE * moves)) return {};
  return "the collision step's fail-safe reverted " + general_text(100.0 * reverted / moves, 3) +
         " % of the vertex moves (every vertex in nearly every step): the shell barely moved and "
         "the result is about the input; more `collision_rounds` (the response's rounds before "
         "the fail-safe) or a smaller `dt` let it move";
}

}  // namespace shellcontract
