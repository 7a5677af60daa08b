// The entry builders of the run-option table (src/sim/option_table.cpp): parsing with ranges
// and error messages that name the option, and one builder per kind of value. Private to the
// library (included as "sim/option_builders.hpp").
#pragma once

#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/classic_locale.hpp"
#include "core/decimal_text.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"
#include "sim/option_ranges.hpp"

namespace shellcontract::option_builders {

using option_ranges::between;
using option_ranges::INF;
using option_ranges::IntegerRange;
using option_ranges::Interval;
using option_ranges::non_negative;
using option_ranges::positive;

/// The error names the option by its field (`k_b`), which each front end spells its own way
/// (spell_options).
[[noreturn]] inline void bad(const std::string& name, const std::string& value,
                             const std::string& range) {
  throw UsageError("`" + option_field(name) + "`: '" + value + "' is not " + range);
}

inline double parse_number(const std::string& name, const std::string& value,
                           const Interval& range) {
  double x = 0.0;
  if (!parse_decimal(value, x) || !range.contains(x)) bad(name, value, range.text);
  return x;
}

inline int parse_integer(const std::string& name, const std::string& value, IntegerRange range) {
  long x = 0;
  if (!parse_decimal_integer(value, x) || x < range.lo || x > range.hi)
    bad(name, value, range.text());
  return static_cast<int>(x);
}

/// on or off, the words the docs and --help give, and nothing else: 1/0 and true/false were
/// taken too, in run alone (bench error refused them), and yes/ON were not.
inline bool parse_on_off(const std::string& name, const std::string& value) {
  if (value == "on") return true;
  if (value == "off") return false;
  bad(name, value, "on or off");
}

inline std::string on_off(bool b) { return b ? "on" : "off"; }

/// A choice between names; each table entry maps a name to a value of T.
template <class T>
using Choices = std::vector<std::pair<std::string, T>>;

template <class T>
std::string choices_text(const Choices<T>& choices) {
  std::string s;
  for (std::size_t i = 0; i < choices.size(); ++i) s += (i ? " | " : "") + choices[i].first;
  return s;
}

template <class T>
T parse_choice(const std::string& name, const std::string& value, const Choices<T>& choices) {
  for (const auto& [n, v] : choices)
    if (n == value) return v;
  bad(name, value, "one of " + choices_text(choices));
}

template <class T>
std::string choice_name(const T& v, const Choices<T>& choices) {
  for (const auto& [n, c] : choices)
    if (c == v) return n;
  return "?";
}

// ------------------------------------------------------------------------------- entry builders

/// A double member reached by `field`.
template <class Field>
OptionSpec number(std::string name, char short_name, std::string value_name, std::string help,
                  Interval range, Field field, std::vector<std::string> bad_examples = {}) {
  OptionSpec o;
  o.name = name;
  o.short_name = short_name;
  o.value_name = std::move(value_name);
  o.help = std::move(help) + "; " + range.text;
  o.set = [name, range, field](RunOptions& r, const std::string& v) {
    field(r) = parse_number(name, v, range);
  };
  o.get = [field](const RunOptions& r) { return shortest_text(field(const_cast<RunOptions&>(r))); };
  o.bad_examples = {"nan", "inf", "-inf", "x"};
  for (double edge : {range.lo, range.hi})
    if (std::isfinite(edge)) {
      const double outside = edge == range.lo ? (range.lo_open ? edge : edge - 1.0)
                                              : (range.hi_open ? edge : edge + 1.0);
      o.bad_examples.push_back(shortest_text(outside));
    }
  for (std::string& b : bad_examples) o.bad_examples.push_back(std::move(b));
  return o;
}

template <class Field>
OptionSpec integer(std::string name, char short_name, std::string value_name, std::string help,
                   IntegerRange range, Field field) {
  OptionSpec o;
  o.name = name;
  o.short_name = short_name;
  o.value_name = std::move(value_name);
  o.help = std::move(help) + "; " + range.text();
  o.set = [name, range, field](RunOptions& r, const std::string& v) {
    field(r) = parse_integer(name, v, range);
  };
  o.get = [field](const RunOptions& r) {
    return std::to_string(field(const_cast<RunOptions&>(r)));
  };
  o.bad_examples = {std::to_string(range.lo - 1), std::to_string(range.hi + 1), "1.5", "x", ""};
  return o;
}

template <class T, class Field>
OptionSpec choice(std::string name, std::string help, Choices<T> choices, Field field) {
  OptionSpec o;
  o.name = name;
  o.value_name = "NAME";
  o.help = std::move(help) + "; " + choices_text(choices);
  o.set = [name, choices, field](RunOptions& r, const std::string& v) {
    field(r) = parse_choice(name, v, choices);
  };
  o.get = [choices, field](const RunOptions& r) {
    return choice_name(field(const_cast<RunOptions&>(r)), choices);
  };
  o.bad_examples = {"", "nonsense"};
  return o;
}

/// A choice and what each of its names means, in one list that the parser and --help are both
/// made from: "isometric (the paper's, flat rest) | dihedral (rest-aware) | none".
template <class T>
struct DescribedChoice {
  std::string name;
  T value;
  std::string description;  ///< "" for a name that needs none
};

template <class T, class Field>
OptionSpec described_choice(std::string name, std::string help,
                            const std::vector<DescribedChoice<T>>& choices, Field field) {
  Choices<T> plain;
  std::string list;
  for (const DescribedChoice<T>& c : choices) {
    plain.emplace_back(c.name, c.value);
    list += (list.empty() ? "" : " | ") + c.name;
    if (!c.description.empty()) list += " (" + c.description + ")";
  }
  OptionSpec o = choice(std::move(name), std::string(), std::move(plain), field);
  o.help = std::move(help) + ": " + list;
  return o;
}

template <class Field>
OptionSpec on_off_option(std::string name, std::string help, Field field) {
  OptionSpec o;
  o.name = name;
  o.value_name = "on|off";
  o.help = std::move(help);
  o.set = [name, field](RunOptions& r, const std::string& v) { field(r) = parse_on_off(name, v); };
  o.get = [field](const RunOptions& r) { return on_off(field(const_cast<RunOptions&>(r))); };
  o.bad_examples = {"", "maybe", "1", "0", "true", "false", "ON"};
  return o;
}

/// An on|off option given as a bare switch (on when present).
template <class Field>
OptionSpec flag(std::string name, std::string help, Field field) {
  OptionSpec o = on_off_option(std::move(name), std::move(help), field);
  o.value_name.clear();
  o.is_switch = true;
  o.bad_examples = {"maybe", "1", "true"};
  return o;
}

template <class Field>
OptionSpec optional_number(std::string name, std::string value_name, std::string help,
                           Interval range, Field field) {
  OptionSpec o;
  o.name = name;
  o.value_name = std::move(value_name);
  o.help = std::move(help) + "; " + range.text;
  o.set = [name, range, field](RunOptions& r, const std::string& v) {
    field(r) = parse_number(name, v, range);
  };
  o.get = [field](const RunOptions& r) {
    const auto& f = field(const_cast<RunOptions&>(r));
    return f ? shortest_text(*f) : std::string();
  };
  o.bad_examples = {"nan", "inf", "0", "-1", "x"};
  return o;
}

}  // namespace shellcontract::option_builders
