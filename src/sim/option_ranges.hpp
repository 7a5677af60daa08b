// The accepted ranges of the run options that SimOptions holds, each written once: the option
// table (option_table.cpp) parses the CLI's and Python's text with them, and check_sim_options
// (run_plan.cpp) holds a caller that writes SimOptions' fields to the same ones, with the same
// message. Private to the library (included as "sim/option_ranges.hpp").
#pragma once

#include <cmath>
#include <limits>
#include <string>

#include "core/classic_locale.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/simulation_options.hpp"

namespace shellcontract::option_ranges {

inline constexpr double INF = std::numeric_limits<double>::infinity();

/// A number and its accepted interval; open ends are exclusive.
struct Interval {
  double lo = -INF, hi = INF;
  bool lo_open = false, hi_open = false;
  std::string text;  ///< how --help and the error say it, e.g. "a number in (0, 1]"
  bool contains(double x) const {
    return std::isfinite(x) && (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
  }
};

inline Interval positive() { return {0.0, INF, true, false, "a finite number > 0"}; }
inline Interval non_negative() { return {0.0, INF, false, false, "a finite number >= 0"}; }
inline Interval between(double lo, double hi, bool lo_open, bool hi_open) {
  ClassicOStringStream t;
  t << "a number in " << (lo_open ? '(' : '[') << shortest_text(lo) << ", " << shortest_text(hi)
    << (hi_open ? ')' : ']');
  return {lo, hi, lo_open, hi_open, t.str()};
}

/// An integer option's closed range [lo, hi].
struct IntegerRange {
  long lo = 0, hi = 0;
  std::string text() const {
    return "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  }
};

/// The bounds beyond which a run would take days rather than fail: they refuse a typo
/// (--frames 1000000000), not a long run.
inline constexpr int MAX_FRAMES = 1000000;
inline constexpr int MAX_ITERATIONS = 100000;

/// A caller's value beyond the table's bounds where those refuse a typo rather than a value the
/// run cannot take (check_sim_options: the pressure).
inline Interval any_finite() { return {-INF, INF, false, false, "a finite number"}; }

// ---- how much it contracts
inline Interval pressure() { return between(-1e6, 1e6, false, false); }
inline Interval air_balance() { return between(0.0, 1.0, false, true); }
inline Interval target_volume() { return between(0.0, 1.0, false, true); }
/// A keyframed target's values (with_keyframes): a re-inflation may go above the rest volume.
inline Interval keyed_target_volume() {
  Interval r = between(0.0, MAX_KEYED_VOLUME_RATIO, true, false);
  r.text = "a ratio V/V0 in (0, " + shortest_text(MAX_KEYED_VOLUME_RATIO) + "]";
  return r;
}
inline Interval stop_volume_ratio() { return between(0.0, 1.0, false, true); }
inline constexpr IntegerRange TARGET_RAMP{1, MAX_FRAMES};
/// run_contraction itself takes more frames (bench error's substeps multiply them): the upper
/// bound is the table's alone, as the pressure's is (the Simulator's blow-up test drives the
/// shell with 1e308).
inline constexpr IntegerRange FRAMES{0, MAX_FRAMES};
// ---- solver
inline Interval dt() { return between(MIN_DT, 1.0, false, false); }
inline constexpr IntegerRange ITERATIONS{0, MAX_ITERATIONS};
inline constexpr IntegerRange THREADS{0, 4096};
inline Interval damping() { return between(0.0, 1.0, false, true); }
// ---- material and bending (the stiffnesses' common upper bound is check_sim_options' own)
inline Interval mu() { return positive(); }
/// Negative down to -mu (a negative Poisson ratio), which check_sim_options holds: the range of
/// one option cannot name another's value.
inline Interval lambda() { return {-INF, INF, false, false, "a finite number (> -mu)"}; }
inline Interval c10() { return positive(); }
inline Interval c01() { return non_negative(); }
inline Interval k_b() { return non_negative(); }
inline Interval density() { return between(MIN_DENSITY, 1e12, false, false); }
// ---- local contraction
inline Interval region_shrink() { return between(0.0, 1.0, false, false); }
inline Interval k_a() { return non_negative(); }
inline Interval mu_a() { return non_negative(); }
inline Interval fiber_target() { return between(0.0, 1.0, true, false); }
// ---- collisions
/// The number --delta takes (or auto); the mesh may refuse it below this bound
/// (sim/contact_distance.hpp).
inline Interval delta() {
  Interval r = between(0.0, 0.1, true, false);
  r.text += " or auto";
  return r;
}
inline constexpr IntegerRange COLLISION_ROUNDS{0, 1000};

}  // namespace shellcontract::option_ranges
