// The one table of run options (shellcontract/options.hpp): every entry reads back its own default,
// refuses values outside its range with a message naming it, and shows a clean default in --help.
#include <gtest/gtest.h>

#include <cstdlib>
#include <ios>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/decimal_text.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract {
namespace {

TEST(OptionTable, NamesAreUniqueAndFindableWithUnderscores) {
  std::set<std::string> names;
  for (const OptionSpec& o : run_option_table()) {
    EXPECT_TRUE(names.insert(o.name).second) << o.name;
    EXPECT_FALSE(o.help.empty()) << o.name;
    std::string python = o.name;
    for (char& c : python)
      if (c == '-') c = '_';
    EXPECT_EQ(find_run_option(python), &o);
  }
  EXPECT_EQ(find_run_option("no-such-option"), nullptr);
  RunOptions r;
  EXPECT_THROW(set_run_option(r, "no-such-option", "1"), UsageError);
}

TEST(OptionTable, EveryDefaultReadsBackUnchanged) {
  const RunOptions defaults;
  for (const OptionSpec& o : run_option_table()) {
    const std::string text = o.get(defaults);
    if (text.empty()) continue;  // an optional value with no default (--young)
    RunOptions r;
    ASSERT_NO_THROW(o.set(r, text)) << o.name << " = " << text;
    EXPECT_EQ(o.get(r), text) << o.name;
  }
}

TEST(OptionTable, DefaultsAreShownWithoutBinaryNoise) {
  // 0.3, not 0.29999999999999999: no run of five or more equal digits after a point.
  const std::regex noise("\\.[0-9]*(0{5}|9{5})[0-9]");
  const RunOptions defaults;
  for (const OptionSpec& o : run_option_table())
    EXPECT_FALSE(std::regex_search(o.get(defaults), noise)) << o.name << " = " << o.get(defaults);
  EXPECT_EQ(shortest_text(0.3), "0.3");
  EXPECT_EQ(std::stod(shortest_text(1e-4)), 1e-4);
  EXPECT_EQ(std::stod(shortest_text(0.1 + 0.2)), 0.1 + 0.2);
}

TEST(OptionTable, EveryOptionRefusesValuesOutsideItsRange) {
  for (const OptionSpec& o : run_option_table()) {
    ASSERT_FALSE(o.bad_examples.empty()) << o.name << " has no example of a bad value";
    for (const std::string& bad : o.bad_examples) {
      RunOptions r;
      try {
        o.set(r, bad);
        ADD_FAILURE() << "--" << o.name << " accepted '" << bad << "'";
      } catch (const UsageError& e) {
        // The library names the option by its field; the CLI spells it as its flag.
        EXPECT_NE(std::string(e.what()).find("`" + option_field(o.name) + "`"), std::string::npos)
            << e.what();
        EXPECT_EQ(spell_options(e.what(), OptionSpelling::Cli).rfind("--" + o.name, 0), 0u)
            << e.what();
      }
    }
  }
}

TEST(DecimalText, OneDecimalNumberAndNothingElse) {
  double x = -1.0;
  for (const auto& [text, value] : std::vector<std::pair<std::string, double>>{{"3", 3.0},
                                                                               {"+3", 3.0},
                                                                               {"-2.5", -2.5},
                                                                               {".5", 0.5},
                                                                               {"5.", 5.0},
                                                                               {"1e-3", 1e-3},
                                                                               {"2E+06", 2e6},
                                                                               {"-0", -0.0},
                                                                               {"0.1", 0.1}}) {
    EXPECT_TRUE(parse_decimal(text, x)) << text;
    EXPECT_EQ(x, value) << text;
  }
  for (const char* text :
       {"",    " 3",  "3 ",  "\t3", "3\n", "0x3", "0x1p-1", "inf", "-inf", "nan",
        "+-3", "-+3", "++3", "+",   "-",   ".",   "e5",     "1e",  "3,5",  "1e400"})
    EXPECT_FALSE(parse_decimal(text, x)) << "'" << text << "'";
  long n = -1;
  for (const auto& [text, value] :
       std::vector<std::pair<std::string, long>>{{"3", 3}, {"+3", 3}, {"-3", -3}, {"0", 0}}) {
    EXPECT_TRUE(parse_decimal_integer(text, n)) << text;
    EXPECT_EQ(n, value) << text;
  }
  for (const char* text : {"", " 3", "3 ", "3.0", "0x3", "+-3", "+", "1e3", "99999999999999999999"})
    EXPECT_FALSE(parse_decimal_integer(text, n)) << "'" << text << "'";
}

// strtod had let " 3" and "0x3" through where "3 " and the integer options (std::from_chars) were
// refused: every option that takes a number reads it the same way now.
TEST(OptionTable, NumbersAreDecimalTextOnly) {
  const RunOptions defaults;
  int numbers = 0;
  for (const OptionSpec& o : run_option_table()) {
    const std::string text = o.get(defaults);
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size()) continue;  // no number by default
    ++numbers;
    std::ostringstream hex;
    hex << std::hexfloat << x;
    for (const std::string& bad : {" " + text, text + " ", "\t" + text, text + "\n", hex.str()}) {
      RunOptions r;
      EXPECT_THROW(o.set(r, bad), UsageError) << "--" << o.name << " accepted '" << bad << "'";
    }
    if (x >= 0.0) {
      RunOptions r;
      EXPECT_NO_THROW(o.set(r, "+" + text)) << "--" << o.name << " refused '+" << text << "'";
    }
  }
  EXPECT_GE(numbers, 20);
  RunOptions r;
  EXPECT_THROW(set_run_option(r, "target-volume", "0:1, 60:0x1p-1"), UsageError);
  EXPECT_NO_THROW(set_run_option(r, "target-volume", "0:1, 60: 0.5"));
}

TEST(OptionTable, RangesFromTheIssue) {
  // Values that were accepted silently before the table: each must be refused.
  const std::vector<std::pair<std::string, std::string>> refused = {{"mu", "nan"},
                                                                    {"lambda", "nan"},
                                                                    {"mu", "-1"},
                                                                    {"c10", "nan"},
                                                                    {"density", "inf"},
                                                                    {"mu-a", "nan"},
                                                                    {"k-a", "nan"},
                                                                    {"fiber-target", "0"},
                                                                    {"fiber-target", "2"},
                                                                    {"iterations", "1000000000"},
                                                                    {"frames", "1000000000"},
                                                                    {"target-volume", "1"},
                                                                    {"target-volume", "-0.5"},
                                                                    {"pressure", "nan"},
                                                                    {"dt", "0"},
                                                                    {"dt", "1e-155"},  // 1 / dt^2 overflowed: NaN
                                                                    {"damping", "1"}};
  for (const auto& [name, value] : refused) {
    RunOptions r;
    EXPECT_THROW(set_run_option(r, name, value), UsageError) << name << " " << value;
  }
}

TEST(OptionTable, RegionAtNamesTheWholeValueAndItsSeparator) {
  // "0;0;1" is read as three points; the message quoted only the first, '0'.
  RunOptions r;
  try {
    set_run_option(r, "region-at", "0;0;1");
    ADD_FAILURE() << "accepted";
  } catch (const UsageError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'0;0;1'"), std::string::npos) << m;
    EXPECT_NE(m.find("separated by ';'"), std::string::npos) << m;
  }
}

TEST(OptionTable, DeltaTakesAutoAndANumberEndsIt) {
  RunOptions r;
  set_run_option(r, "delta", "3e-5");
  set_run_option(r, "delta", "auto");
  EXPECT_TRUE(r.sim.auto_delta);
  EXPECT_EQ(r.sim.collision.delta, CollisionOptions{}.delta);  // the cap is the default again
  EXPECT_EQ(find_run_option("delta")->get(r), "auto");
  set_run_option(r, "delta", "5e-5");
  EXPECT_FALSE(r.sim.auto_delta);
  EXPECT_EQ(r.sim.collision.delta, 5e-5);
  EXPECT_EQ(find_run_option("delta")->get(r), "5e-05");
}

TEST(OptionTable, YoungAndThicknessGiveTheBendingStiffnessUnderXpbd) {
  const auto resolved = [](std::vector<std::pair<std::string, std::string>> given) {
    RunOptions r;
    for (const auto& [name, value] : given) set_run_option(r, name, value);
    resolve_run_options(r);
    return r.sim.solver.k_bending;
  };
  const double default_k_b = RunOptions().sim.solver.k_bending;
  const double E = 1000, nu = 0.25, h = 0.002;
  const double plate = E * h * h * h / (12 * (1 - nu * nu));  // D, the plate's rigidity
  const std::vector<std::pair<std::string, std::string>> material = {
      {"young", "1000"}, {"poisson", "0.25"}, {"thickness", "0.002"}};
  auto with = [&](std::vector<std::pair<std::string, std::string>> more) {
    more.insert(more.begin(), material.begin(), material.end());
    return more;
  };
  EXPECT_NEAR(resolved(with({{"solver", "xpbd"}})), plate / 3, 1e-15 * plate);
  // An explicit --k-b wins; pbd's k_B is a multiplier; other bending models have other scales.
  EXPECT_EQ(resolved(with({{"solver", "xpbd"}, {"k-b", "0.5"}})), 0.5);
  EXPECT_EQ(resolved(with({{"solver", "pbd"}})), default_k_b);
  EXPECT_EQ(resolved(with({{"solver", "xpbd"}, {"bending", "isometric"}})), default_k_b);
}

TEST(OptionTable, CrossChecksAreResolvedOnce) {
  RunOptions r;
  set_run_option(r, "young", "1000");
  r.thickness.reset();  // a caller that unsets the default thickness
  EXPECT_THROW(resolve_run_options(r), UsageError);  // --young without --thickness
  set_run_option(r, "thickness", "0.01");
  EXPECT_THROW(set_run_option(r, "poisson", "0.5"), UsageError);
  set_run_option(r, "poisson", "0.25");
  resolve_run_options(r);
  EXPECT_DOUBLE_EQ(r.sim.material_params.mu, 1000 * 0.01 / (2 * 1.25));
  RunOptions both;
  set_run_option(both, "target-volume", "0.5");
  set_run_option(both, "stop-volume-ratio", "0.5");
  EXPECT_THROW(resolve_run_options(both), UsageError);
  RunOptions stiff;
  set_run_option(stiff, "solver", "pbd");
  set_run_option(stiff, "k-b", "2");
  EXPECT_THROW(resolve_run_options(stiff), UsageError);  // pbd: a multiplier in [0, 1]
  set_run_option(stiff, "solver", "xpbd");
  EXPECT_NO_THROW(resolve_run_options(stiff));
}

TEST(OptionTable, TheDefaultRunIsTheShellMaterialUnderXpbd) {
  // The default run (RunOptions) is XPBD with the shell material E = 1000, nu = 0.3, h = 0.002 and
  // damping 0.1; --solver pbd is the paper's setting (mu = lambda = 1, damping 0.2), as are given
  // Lame parameters for the membrane. Values from the closed forms of math-spec 6.
  const auto resolved = [](std::vector<std::pair<std::string, std::string>> given) {
    RunOptions r;
    for (const auto& [name, value] : given) set_run_option(r, name, value);
    resolve_run_options(r);
    return r;
  };
  const auto mu_of = [](double E, double nu, double h) { return E * h / (2 * (1 + nu)); };
  const auto lambda_of = [](double E, double nu, double h) { return E * h * nu / (1 - nu * nu); };
  const auto k_b_of = [](double E, double nu, double h) {
    return E * h * h * h / (36 * (1 - nu * nu));
  };
  const RunOptions d = resolved({});
  EXPECT_EQ(d.sim.solver.kind, SolverKind::Xpbd);
  EXPECT_DOUBLE_EQ(d.sim.material_params.mu, mu_of(1000, 0.3, 0.002));
  EXPECT_DOUBLE_EQ(d.sim.material_params.lambda, lambda_of(1000, 0.3, 0.002));
  EXPECT_DOUBLE_EQ(d.sim.solver.k_bending, k_b_of(1000, 0.3, 0.002));
  EXPECT_EQ(d.sim.damping, 0.1);

  const RunOptions pbd = resolved({{"solver", "pbd"}});
  EXPECT_FALSE(pbd.young.has_value());
  EXPECT_EQ(pbd.sim.material_params.mu, 1.0);
  EXPECT_EQ(pbd.sim.material_params.lambda, 1.0);
  EXPECT_EQ(pbd.sim.solver.k_bending, 0.01);
  EXPECT_EQ(pbd.sim.damping, 0.2);
  EXPECT_EQ(resolved({{"solver", "pbd"}, {"damping", "0.1"}}).sim.damping, 0.1);
  EXPECT_EQ(resolved({{"solver", "xpbd"}, {"damping", "0.2"}}).sim.damping, 0.2);

  const RunOptions lame = resolved({{"mu", "0.5"}});
  EXPECT_FALSE(lame.young.has_value());
  EXPECT_EQ(lame.sim.material_params.mu, 0.5);
  EXPECT_EQ(lame.sim.material_params.lambda, 1.0);
  // One of the two material values given: the other keeps its default.
  const RunOptions thick = resolved({{"thickness", "0.004"}});
  EXPECT_DOUBLE_EQ(thick.sim.material_params.mu, mu_of(1000, 0.3, 0.004));
  EXPECT_DOUBLE_EQ(thick.sim.solver.k_bending, k_b_of(1000, 0.3, 0.004));
  // A caller that writes the fields (no option table) is read the same way.
  RunOptions written;
  written.sim.material_params.mu = 0.5;
  resolve_run_options(written);
  EXPECT_EQ(written.sim.material_params.mu, 0.5);
  // Resolving twice changes nothing (the CLI resolves, then run_contraction again).
  for (RunOptions once : {d, pbd, lame, thick}) {
    RunOptions twice = once;
    resolve_run_options(twice);
    EXPECT_EQ(twice.sim.material_params.mu, once.sim.material_params.mu);
    EXPECT_EQ(twice.sim.solver.k_bending, once.sim.solver.k_bending);
    EXPECT_EQ(twice.sim.damping, once.sim.damping);
    EXPECT_EQ(twice.young, once.young);
  }
}

// A help that describes its values ("volume (each region sinks ...) | force (...)") must not
// list them again as a plain choice's does ("...; volume | projection | force | none"): --inward,
// --dimple and --bending had both.
TEST(OptionTable, NoHelpListsItsValuesTwice) {
  const std::regex plain_list("; ([a-z0-9-]+(?: \\| [a-z0-9-]+)+)$");
  for (const OptionSpec& o : run_option_table()) {
    std::smatch m;
    if (!std::regex_search(o.help, m, plain_list)) continue;
    const std::string before = o.help.substr(0, static_cast<std::size_t>(m.position(0)));
    std::istringstream values(m[1].str());
    for (std::string v; values >> v;) {
      if (v == "|") continue;
      EXPECT_EQ(before.find(v + " ("), std::string::npos)
          << "--" << o.name << " describes '" << v << "' and lists it again: " << o.help;
    }
  }
}

}  // namespace
}  // namespace shellcontract
