// check_sim_options (run_plan.cpp) against the option table: a caller that writes SimOptions'
// fields is held to the ranges the table holds the CLI and Python to (sim/option_ranges.hpp,
// their one source), with the same message. The table is walked, so that a numeric option added
// to it is either checked here or said to be no field of SimOptions.
#include <gtest/gtest.h>

#include <climits>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/decimal_text.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract {
namespace {

using Writer = std::function<void(SimOptions&, double)>;

/// The SimOptions field of each numeric option of the table.
const std::map<std::string, Writer>& sim_fields() {
  static const std::map<std::string, Writer> fields = {
      {"pressure", [](SimOptions& s, double x) { s.pressure = x; }},
      {"air-balance", [](SimOptions& s, double x) { s.air_balance = x; }},
      {"target-volume", [](SimOptions& s, double x) { s.target_volume = x; }},
      {"target-ramp", [](SimOptions& s, double x) { s.target_ramp_frames = static_cast<int>(x); }},
      {"stop-volume-ratio", [](SimOptions& s, double x) { s.stop_volume_ratio = x; }},
      {"frames", [](SimOptions& s, double x) { s.frames = static_cast<int>(x); }},
      {"dt", [](SimOptions& s, double x) { s.dt = x; }},
      {"iterations", [](SimOptions& s, double x) { s.solver.iterations = static_cast<int>(x); }},
      {"threads", [](SimOptions& s, double x) { s.solver.threads = static_cast<int>(x); }},
      {"damping", [](SimOptions& s, double x) { s.damping = x; }},
      {"mu", [](SimOptions& s, double x) { s.material_params.mu = x; }},
      {"lambda", [](SimOptions& s, double x) { s.material_params.lambda = x; }},
      {"c10", [](SimOptions& s, double x) { s.material_params.c10 = x; }},
      {"c01", [](SimOptions& s, double x) { s.material_params.c01 = x; }},
      {"k-b", [](SimOptions& s, double x) { s.solver.k_bending = x; }},
      {"density", [](SimOptions& s, double x) { s.density = x; }},
      {"k-a", [](SimOptions& s, double x) { s.anisotropy.kappa_a = x; }},
      {"region-shrink", [](SimOptions& s, double x) { s.region_shrink = x; }},
      {"mu-a", [](SimOptions& s, double x) { s.material_params.mu_aniso = x; }},
      {"fiber-target", [](SimOptions& s, double x) { s.material_params.fiber_target = x; }},
      {"delta", [](SimOptions& s, double x) { s.collision.delta = x; }},
      {"collision-rounds",
       [](SimOptions& s, double x) { s.collision.rounds = static_cast<int>(x); }},
  };
  return fields;
}

/// Numeric options of the table that are RunOptions' own, not SimOptions' (check_table_ranges
/// holds them).
const std::set<std::string> RUN_ONLY = {"young", "poisson", "thickness", "region-max-area"};

/// The builders' own bad examples tell a number ("nan") and an integer ("1.5") from the rest.
bool has_bad_example(const OptionSpec& o, const char* example) {
  for (const std::string& b : o.bad_examples)
    if (b == example) return true;
  return false;
}
bool numeric(const OptionSpec& o) { return has_bad_example(o, "nan") || has_bad_example(o, "1.5"); }
bool integral(const OptionSpec& o) { return has_bad_example(o, "1.5"); }

/// The message of a refusal, "" when accepted.
std::string refusal(const std::function<void()>& f) {
  try {
    f();
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

TEST(SimOptionRanges, EveryNumericOptionOfTheTableIsCheckedOrRunOptionsOwn) {
  int numbers = 0;
  for (const OptionSpec& o : run_option_table()) {
    if (!numeric(o)) continue;
    ++numbers;
    EXPECT_TRUE(sim_fields().count(o.name) || RUN_ONLY.count(o.name))
        << "--" << o.name << " takes a number: add its SimOptions field to this test's list, or "
        << "to RUN_ONLY if it is no field of SimOptions";
  }
  EXPECT_EQ(numbers, static_cast<int>(sim_fields().size() + RUN_ONLY.size()));
  for (const auto& [name, writer] : sim_fields()) {
    const OptionSpec* o = find_run_option(name);
    EXPECT_TRUE(o && numeric(*o)) << name;
  }
}

// Before: check_sim_options kept its own copy of some ranges and not others, so that a caller of
// plan_simulation or Simulator ran with dt = 2, delta = 0.5, mu = -1 or 5000 threads, values the
// table refuses, and the messages of the two differed for the same value.
TEST(SimOptionRanges, CheckSimOptionsRefusesWhatTheTableRefusesWithItsMessage) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> probes = {
      std::nan(""), inf,     -inf, -2e6,    -1e6, -1.5, -1,   -1e-300, 0,     1e-300, 1e-100,
      0.05,         0.1,     0.5,  1,       1.5,  2,    3,    1000,    1001,  4096,   4097,
      1e5,          1e5 + 1, 1e6,  1e6 + 1, 1e12, 2e12, 1e90, 1e101,   -1e101};
  for (const auto& [name, write] : sim_fields()) {
    const OptionSpec& o = *find_run_option(name);
    std::vector<double> values = probes;
    for (const std::string& b : o.bad_examples) {
      double x = 0.0;
      if (parse_decimal(b, x)) values.push_back(x);
    }
    for (double x : values) {
      if (integral(o) && !(std::isfinite(x) && x == std::floor(x) && std::abs(x) < INT_MAX))
        continue;  // an int field holds no such value
      const std::string text =
          integral(o) ? std::to_string(static_cast<long>(x)) : shortest_text(x);
      RunOptions parsed;
      const std::string by_table = refusal([&] { o.set(parsed, text); });
      SimOptions s;
      s.solver.kind = SolverKind::Xpbd;  // the table's default (its pbd bounds k_B by 1, a rule)
      write(s, x);
      const std::string by_check = refusal([&] { check_sim_options(s); });
      // Where the two differ on purpose: the stiffnesses' common bound (1e100, beyond the table's
      // open ranges), lambda's rule with mu (mu + lambda > 0), and the two bounds of the table
      // that refuse a typo, not a value a run cannot take: frames beyond a million (bench
      // error's substeps multiply them), iterations beyond the table's (bench error's reference
      // runs) and a finite pressure beyond 1e6.
      // The bound holds only what the table lets through: a value the table refuses (mu = -1e101,
      // not > 0) gets the table's message (before, the bound's).
      if (std::abs(x) > 1e100 && by_table.empty() &&
          by_check.find("must be at most") != std::string::npos)
        continue;
      if (name == "lambda" && std::isfinite(x) && !(s.material_params.mu + x > 0.0)) {
        EXPECT_NE(by_check.find("`lambda` must be greater than -mu"), std::string::npos) << x;
        continue;
      }
      if ((name == "frames" && x > 1e6) || (name == "iterations" && x > 1e5) ||
          (name == "pressure" && std::isfinite(x) && std::abs(x) > 1e6)) {
        EXPECT_EQ(by_check, "") << "--" << name << " " << text;
        continue;
      }
      if ((name == "frames" || name == "iterations") &&
          x < 0) {  // the table's names its upper bound too
        EXPECT_EQ(by_check, "`" + name + "`: '" + text + "' is not an integer >= 0");
        EXPECT_EQ(by_table.rfind("`" + name + "`: '" + text + "' is not an integer in [0, ", 0),
                  0u);
        continue;
      }
      if (name == "pressure" && !std::isfinite(x)) {
        EXPECT_EQ(by_check, "`pressure`: '" + text + "' is not a finite number");
        continue;
      }
      EXPECT_EQ(by_check, by_table) << "--" << name << " " << text;
    }
  }
}

}  // namespace
}  // namespace shellcontract
