// The goal of a run's volume (sim/target_goal.hpp).
#include "sim/target_goal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/decimal_text.hpp"
#include "shellcontract/run.hpp"

namespace shellcontract {

int schedule_settles_at(const Schedule& keys, int last) {
  if (keys.empty()) return 0;
  const std::vector<Keyframe>& k = keys.keys();
  // The keys at or before `last` are k[0, i).
  std::size_t i = static_cast<std::size_t>(
      std::upper_bound(k.begin(), k.end(), last,
                       [](int f, const Keyframe& key) { return f < key.frame; }) -
      k.begin());
  if (i == 0) return 0;  // before the first key the value is the first key's
  // Past the last key the value holds; between two different keys it moves up to `last`.
  if (i < k.size() && k[i - 1].frame < last && k[i].value != k[i - 1].value) return last;
  --i;
  while (i > 0 && k[i - 1].value == k[i].value) --i;
  return i == 0 ? 0 : k[i].frame;  // a hold from the first key holds from frame 0
}

bool volume_stalled(const std::vector<double>& history, std::size_t n, double goal) {
  if (n < static_cast<std::size_t>(STALL_FRAMES) || n >= history.size()) return false;
  const double change = std::abs(history[n] - history[n - STALL_FRAMES]);
  return change < STALL_CHANGE && !target_volume_reached(history[n], goal);
}

int first_stall_before(const std::vector<double>& history, const Schedule& keys, int settled) {
  const std::size_t end = std::min(history.size(), static_cast<std::size_t>(std::max(settled, 0)));
  for (std::size_t n = 0; n < end; ++n)
    if (volume_stalled(history, n, keys.at(static_cast<double>(n)))) return static_cast<int>(n);
  return -1;
}

int frame_goal_met(const std::vector<double>& history, double goal, int from) {
  for (std::size_t n = static_cast<std::size_t>(std::max(from, 1)); n < history.size(); ++n)
    if (target_volume_reached(history[n], goal) ||
        (history[n - 1] - goal) * (history[n] - goal) < 0.0)
      return static_cast<int>(n);
  return -1;
}

std::string volume_ratio_text(double r) {
  // Four decimals hide a small ratio (a collapse to 1e-7 read as 0.0000): those get digits.
  // "%.4f" or "%.3g" as the "C" locale writes them, whatever locale a host program set.
  return r == 0.0 || std::abs(r) >= 0.01 ? fixed_text(r, 4) : general_text(r, 3);
}

std::string stall_text(double ratio, int frame) {
  return "the volume stalled at V/V0 " + volume_ratio_text(ratio) + " (less than " +
         volume_ratio_text(STALL_CHANGE) + " change over " + std::to_string(STALL_FRAMES) +
         " frames) at frame " + std::to_string(frame);
}

std::string miss_text(double ratio, double goal, bool target) {
  std::string text;
  if (goal > 0.0 && ratio > 0.0 && (ratio < 0.5 * goal || ratio > 2.0 * goal)) {
    const bool below = ratio < goal;
    const double factor = below ? goal / ratio : ratio / goal;
    // A denormal goal (or V/V0) makes the factor overflow: "inf times" reads as a broken number.
    text = (std::isfinite(factor)
                ? general_text(factor, 3) + " times "
                : "more than " + general_text(std::numeric_limits<double>::max(), 2) + " times ") +
           (below ? "smaller" : "larger") + " than the " + (target ? "target" : "stop ratio");
  } else {
    const double off = ratio - goal;
    text = volume_ratio_text(std::abs(off)) + " " + (off < 0.0 ? "below" : "above") + " it (" +
           general_text(100.0 * std::abs(off) / goal, 3) + " % of it)";
  }
  if (target)
    text += "; it counts as reached within " + volume_ratio_text(target_volume_tolerance(goal));
  return text;
}

}  // namespace shellcontract
