// The end-of-run warnings on the volume (sim/volume_warnings.hpp).
#include "sim/volume_warnings.hpp"

#include <algorithm>
#include <cstddef>

#include "core/decimal_text.hpp"
#include "shellcontract/run.hpp"
#include "sim/target_goal.hpp"

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

int swing_reversals(const std::vector<double>& history, std::size_t from) {
  int reversals = 0;
  int direction = 0;  // 0 before the first move by SWING_SHARE, then +1 rising, -1 falling
  double low = 0.0, high = 0.0, extreme = 0.0;
  bool fresh = true;  // no positive value since the start or the last inside-out one
  const double keep = 1.0 - SWING_SHARE;
  for (std::size_t n = from; n < history.size(); ++n) {
    const double b = history[n];
    if (!(b > 0.0)) {  // inside out: named by the negative V/V0's own warning
      direction = 0;
      fresh = true;
      continue;
    }
    if (fresh) {
      low = high = b;
      fresh = false;
      continue;
    }
    if (direction == 0) {
      low = std::min(low, b);
      high = std::max(high, b);
      if (keep * b >= low) direction = 1;  // rose from the lowest by a share of b
      if (b <= keep * high) direction = -1;
      if (direction != 0) extreme = b;
    } else if (direction > 0 ? b > extreme : b < extreme) {
      extreme = b;  // the move goes on
    } else if (direction > 0 ? b <= keep * extreme : keep * b >= extreme) {
      direction = -direction;
      extreme = b;
      ++reversals;
    }
  }
  return reversals;
}

std::vector<std::string> volume_warnings(const std::vector<double>& history, bool compressed,
                                         bool scheduled) {
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
  const int reversals = scheduled ? 0 : swing_reversals(history, frames - frames / 2);
  if ((rose && fell) || reversals >= SWING_REVERSALS) {
    const std::string how = rose && fell
                                ? "more than a factor " + ratio_text(SWING_FACTOR) + " up and down"
                                : std::to_string(reversals) + " times up and down by " +
                                      ratio_text(100.0 * SWING_SHARE) + " % or more";
    out.push_back("V/V0 swung between " + ratio_text(low) + " and " + ratio_text(high) +
                  " from frame to frame in the second half of the run (" + how +
                  "), so its last value means little: the pressure and the air (`air_balance`) "
                  "are explicit loads, which overshoot every step where the step is too long for "
                  "the shell's mass (a light `density`, a strong `pressure`, a very thin shell; "
                  "said at the start if so); a smaller `dt`, or `air_balance` 0 on a very thin "
                  "shell, settles it");
    // A swing whose lowest value is above the rest volume grew all the same, wherever it ends.
    if (!(low > GROWTH_WARNING_RATIO)) return out;
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

std::string stop_below_warning(double final_ratio, double stop) {
  if (!(final_ratio < stop - target_volume_tolerance(stop))) return {};
  return "the run stopped at V/V0 " + volume_ratio_text(final_ratio) + ", below the stop ratio " +
         volume_ratio_text(stop) +
         ": the contacts held the shell, and the step that crossed it was lifted back toward it "
         "only a limited distance per vertex; a smaller `dt` or a lower `pressure` crosses it in "
         "smaller steps";
}

std::string inside_out_warning(double final_ratio, int frames, bool collisions) {
  if (!(frames > 0 && final_ratio <= 0.0)) return {};
  return "V/V0 ended at " + shortest_text(final_ratio) +
         ": the shell passed through itself and is inside out" +
         (collisions ? std::string() : " (`collisions` off)");
}

}  // namespace shellcontract
