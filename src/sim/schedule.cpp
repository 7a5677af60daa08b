#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <string_view>
#include <utility>

#include "core/decimal_text.hpp"
#include "core/list_text.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/simulation_options.hpp"

namespace shellcontract {

namespace {

/// The PCHIP slopes (Fritsch and Carlson 1980; Fritsch and Butland's weighted harmonic mean):
/// zero at the ends and where the secants change sign or one is flat, otherwise
/// (w1 + w2) / (w1 / d0 + w2 / d1) with w1 = 2 h1 + h0, w2 = h1 + 2 h0, which lies between 0
/// and 3 min(d0, d1) and so keeps each piece monotone.
std::vector<double> monotone_slopes(const std::vector<Keyframe>& k) {
  const std::size_t n = k.size();
  std::vector<double> m(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double h0 = k[i].frame - k[i - 1].frame, h1 = k[i + 1].frame - k[i].frame;
    const double d0 = (k[i].value - k[i - 1].value) / h0;
    const double d1 = (k[i + 1].value - k[i].value) / h1;
    if (!(d0 * d1 > 0.0)) continue;  // a turn or a flat side: the curve stops at the key
    const double w1 = 2.0 * h1 + h0, w2 = h1 + 2.0 * h0;
    m[i] = (w1 + w2) / (w1 / d0 + w2 / d1);
  }
  return m;
}

[[noreturn]] void bad_key(const std::string& option, std::size_t index, const std::string& key,
                          const std::string& what) {
  // The option by its field (`target_volume`), as the option table's errors name it.
  std::string field = option;
  for (char& c : field)
    if (c == '-') c = '_';
  throw UsageError("`" + field + "`: key " + std::to_string(index + 1) + " ('" + key +
                   "'): " + what);
}

}  // namespace

Schedule::Schedule(std::vector<Keyframe> keys) : keys_(std::move(keys)) {
  slopes_ = monotone_slopes(keys_);
}

double Schedule::at(double frame) const {
  if (keys_.empty()) return 0.0;
  if (!(frame > keys_.front().frame)) return keys_.front().value;
  if (!(frame < keys_.back().frame)) return keys_.back().value;
  // The segment [k_i, k_{i+1}) holding the frame.
  const auto next = std::upper_bound(keys_.begin(), keys_.end(), frame,
                                     [](double f, const Keyframe& k) { return f < k.frame; });
  const std::size_t i = static_cast<std::size_t>(next - keys_.begin()) - 1;
  const Keyframe& a = keys_[i];
  const Keyframe& b = keys_[i + 1];
  const double h = b.frame - a.frame;  // > 0: frames strictly increase
  const double t = (frame - a.frame) / h;
  const double t2 = t * t, t3 = t2 * t;
  const double h00 = 2.0 * t3 - 3.0 * t2 + 1.0, h10 = t3 - 2.0 * t2 + t;
  const double h01 = 3.0 * t2 - 2.0 * t3, h11 = t3 - t2;
  const double v = h00 * a.value + h10 * h * slopes_[i] + h01 * b.value + h11 * h * slopes_[i + 1];
  // Rounding may put a held value a few ulps off; the curve never leaves its keys' interval.
  return std::clamp(v, std::min(a.value, b.value), std::max(a.value, b.value));
}

double Schedule::min_value() const {
  double v = std::numeric_limits<double>::infinity();
  for (const Keyframe& k : keys_) v = std::min(v, k.value);
  return v;
}

double Schedule::max_value() const {
  double v = -std::numeric_limits<double>::infinity();
  for (const Keyframe& k : keys_) v = std::max(v, k.value);
  return v;
}

std::string Schedule::text() const {
  std::string s;
  for (const Keyframe& k : keys_)
    s += (s.empty() ? "" : ", ") + std::to_string(k.frame) + ":" + shortest_text(k.value);
  return s;
}

bool Schedule::operator==(const Schedule& o) const {
  if (keys_.size() != o.keys_.size()) return false;
  for (std::size_t i = 0; i < keys_.size(); ++i)
    if (keys_[i].frame != o.keys_[i].frame || keys_[i].value != o.keys_[i].value) return false;
  return true;
}

bool KeyRange::contains(double v) const {
  return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
}

bool is_schedule_text(const std::string& text) { return text.find(':') != std::string::npos; }

Schedule parse_schedule(const std::string& option, const std::string& text, const KeyRange& range) {
  std::vector<Keyframe> keys;
  // The keys in order, empty ones too: each key's problem is named where it comes (list_text.hpp's
  // rule of items and blanks, as the other list options read theirs).
  const std::vector<std::string> items = list_items(text);
  for (std::size_t index = 0; index < items.size(); ++index) {
    const std::string& key = items[index];
    if (key.empty()) bad_key(option, index, key, "empty key; expected FRAME:VALUE");
    const std::size_t colon = key.find(':');
    if (colon == std::string::npos) bad_key(option, index, key, "expected FRAME:VALUE");
    const std::string frame_text(trim_blanks(std::string_view(key).substr(0, colon)));
    const std::string value_text(trim_blanks(std::string_view(key).substr(colon + 1)));
    long frame = -1;
    if (!parse_decimal_integer(frame_text, frame) || frame < 0 ||
        frame > std::numeric_limits<int>::max())
      bad_key(option, index, key, "the frame '" + frame_text + "' is not an integer in [0, " +
                                      std::to_string(std::numeric_limits<int>::max()) + "]");
    double value = 0.0;
    if (!parse_decimal(value_text, value) || !std::isfinite(value))
      bad_key(option, index, key, "the value '" + value_text + "' is not a finite number");
    if (!range.contains(value))
      bad_key(option, index, key, "the value " + value_text + " is not " + range.text);
    if (!keys.empty() && frame <= keys.back().frame)
      bad_key(option, index, key,
              "frame " + std::to_string(frame) + " does not come after the previous key's frame " +
                  std::to_string(keys.back().frame) + " (frames must increase)");
    keys.push_back({static_cast<int>(frame), value});
  }
  return Schedule(std::move(keys));
}

Schedule parse_volume_schedule(const std::string& option, const std::string& text,
                               const KeyRange& range) {
  Schedule s = parse_schedule(option, text, range);
  std::vector<Keyframe> keys = s.keys();
  if (keys.front().frame == 0 && keys.front().value != 1.0)
    bad_key(option, 0, text.substr(0, text.find(',')),
            "at frame 0 the shell is at its rest volume, V/V0 = 1 (start with 0:1, or key a later "
            "frame and the schedule starts from 0:1)");
  if (keys.front().frame > 0) keys.insert(keys.begin(), Keyframe{0, 1.0});
  return Schedule(std::move(keys));
}

}  // namespace shellcontract
