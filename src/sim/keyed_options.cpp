#include "sim/keyed_options.hpp"

#include <string>
#include <utility>

#include "shellcontract/error.hpp"
#include "shellcontract/simulation_options.hpp"
#include "sim/option_ranges.hpp"

namespace shellcontract {

OptionSpec with_keyframes(OptionSpec o, KeyedValue which) {
  const bool volume = which == KeyedValue::TargetVolume;
  // The key values' ranges are option_ranges.hpp's, which check_sim_options holds too.
  const option_ranges::Interval keys =
      volume ? option_ranges::keyed_target_volume() : option_ranges::pressure();
  KeyRange range{keys.lo, keys.hi, keys.lo_open, keys.hi_open, keys.text};
  if (volume) {
    o.help +=
        "; or keyframes FRAME:R, ... (\"0:1, 60:0.5, 120:0.85\": deflate, then re-inflate), "
        "smooth between keys and held after the last, R in (0, " +
        shortest_text(MAX_KEYED_VOLUME_RATIO) + "] (frame 0 is the rest volume, 1)";
  } else {
    range.text = "a pressure" + keys.text.substr(std::string("a number").size());  // "in [...]"
    o.help += "; or keyframes FRAME:P, ... (\"0:4, 100:0\"), smooth between keys, constant outside";
  }
  o.value_name += "|KEYS";
  const auto set_number = o.set;
  const std::string name = o.name;
  o.set = [set_number, name, range, volume](RunOptions& r, const std::string& v) {
    Schedule& keys = volume ? r.sim.target_volume_schedule : r.sim.pressure_schedule;
    if (!is_schedule_text(v)) {
      set_number(r, v);
      keys = Schedule();
      return;
    }
    keys = volume ? parse_volume_schedule(name, v, range) : parse_schedule(name, v, range);
    if (volume)
      r.sim.target_volume = keys.last_value();
    else
      r.sim.pressure = keys.max_value();
  };
  const auto get_number = o.get;
  o.get = [get_number, volume](const RunOptions& r) {
    const Schedule& keys = volume ? r.sim.target_volume_schedule : r.sim.pressure_schedule;
    return keys.empty() ? get_number(r) : keys.text();
  };
  for (const char* b : {"0:1, 0:0.5", "0:1,, 60:0.5", "0:1, 60:x", "x:1", "-5:1", "0:1, 60:nan",
                        "0:1, 60:", ":", "0:1, 60:1e9"})
    o.bad_examples.push_back(b);
  if (volume)
    for (const char* b : {"0:0.5", "0:1, 60:0", "0:1, 60:-0.5", "0:1, 60:2.5"})
      o.bad_examples.push_back(b);
  return o;
}

}  // namespace shellcontract
