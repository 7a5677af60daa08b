// A value that follows keyframes over the frames of a run (--target-volume "0:1, 60:0.5, 120:0.85",
// -p "0:4, 100:0"): the keys as an animator sets them, smooth between them, constant outside.
// docs/design/keyframes.md.
#pragma once

#include <string>
#include <vector>

namespace shellcontract {

/// One key: the value at a frame (frame 0 is the rest state, frame n the state after step n).
struct Keyframe {
  int frame = 0;
  double value = 0.0;
};

/// A value over the frames, interpolated between keys by a monotone cubic Hermite curve
/// (Fritsch-Carlson slopes, the weighted harmonic mean of the neighbouring secants as in PCHIP),
/// with zero slope at the first and last key and at every key where the curve turns:
///  - between two keys the value stays between theirs (no overshoot, so a valid range of the keys
///    is valid everywhere, and a held value, two equal keys, is exactly constant);
///  - the curve is C1: the shell is never asked for a jump in speed;
///  - two keys alone give the smoothstep 3t^2 - 2t^3 of the single-number target ramp.
/// Before the first key the value is the first key's, after the last the last key's.
class Schedule {
 public:
  Schedule() = default;
  /// @param keys  frames >= 0 and strictly increasing, values finite (check_keys) -- not checked
  ///              here; make_schedule is the checking constructor
  explicit Schedule(std::vector<Keyframe> keys);

  bool empty() const { return keys_.empty(); }
  const std::vector<Keyframe>& keys() const { return keys_; }
  /// The value at `frame` (any real frame; the run asks at integer frames).
  double at(double frame) const;
  double first_value() const { return keys_.front().value; }
  double last_value() const { return keys_.back().value; }
  int last_frame() const { return keys_.back().frame; }
  double min_value() const;
  double max_value() const;
  /// "0:1, 60:0.5, 120:0.85", each value in the shortest text that reads back exactly: parsing
  /// it gives the same schedule.
  std::string text() const;

  bool operator==(const Schedule& o) const;
  bool operator!=(const Schedule& o) const { return !(*this == o); }

 private:
  std::vector<Keyframe> keys_;
  std::vector<double> slopes_;  ///< dv/dframe at each key
};

/// What a key's value may be, for the messages: lo/hi with open or closed ends, and how the
/// message says it ("a ratio in (0, 2]").
struct KeyRange {
  double lo = 0.0, hi = 0.0;
  bool lo_open = false, hi_open = false;
  std::string text;
  bool contains(double v) const;
};

/// Whether an option's text is a schedule ("F:V, ...") rather than one number.
bool is_schedule_text(const std::string& text);

/// Parses "F:V, F:V, ..." (whitespace around the numbers is free; frames are integers >= 0,
/// strictly increasing; values in `range`).
/// @param option  the option's CLI name, for the messages ("target-volume")
/// @throws UsageError "--OPTION: key K ('TEXT'): what is wrong" (K counts from 1)
Schedule parse_schedule(const std::string& option, const std::string& text, const KeyRange& range);

/// The schedule of a target volume: parse_schedule with `range`, and frame 0 is the rest state,
/// V/V0 = 1: a first key at frame 0 must be 1 (a jump in one step would tear the shell), and a
/// first key after frame 0 gets the key 0:1 before it, so the shell eases from its rest volume.
/// @throws UsageError naming the key
Schedule parse_volume_schedule(const std::string& option, const std::string& text,
                               const KeyRange& range);

}  // namespace shellcontract
