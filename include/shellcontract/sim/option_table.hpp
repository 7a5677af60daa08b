// The one table of run options: name, help, default and accepted range of every option of
// `shellcontract run`. The CLI builds its parser and --help from it, the Python module its keyword
// arguments, and a test walks it; no second list exists to fall out of step (design.md).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "shellcontract/sim/run_options.hpp"

namespace shellcontract {

/// One option. Values travel as text so that the CLI and Python parse them the same way (the same
/// double from the same digits, hence the same run).
struct OptionSpec {
  std::string name;        ///< CLI spelling without dashes, e.g. "k-b"; Python uses k_b
  char short_name = 0;     ///< one-letter alias, 0 for none
  std::string value_name;  ///< what the value is, e.g. "P" or "N"; empty for a switch
  std::string help;        ///< one sentence or two, ending with the accepted range
  bool is_switch = false;  ///< a flag without a value ("on" when given)
  /// May be given several times on the command line: the values, joined by ';', are set at once.
  bool repeatable = false;
  /// Parses `value` into `options`. @throws UsageError naming the option and the accepted range
  std::function<void(RunOptions&, const std::string&)> set;
  /// The option's value in `options` as text ("" for an unset optional value); get(RunOptions{})
  /// is the default shown in --help, in the shortest form that reads back exactly (0.3).
  std::function<std::string(const RunOptions&)> get;
  /// Example values outside the accepted range, for the test that walks the table.
  std::vector<std::string> bad_examples;
};

/// Every option of a run, in --help order.
const std::vector<OptionSpec>& run_option_table();

/// The option named `name` (CLI spelling; Python's underscores are accepted too), or nullptr.
const OptionSpec* find_run_option(const std::string& name);

/// Sets one option from text. @throws UsageError for an unknown name or a bad value
void set_run_option(RunOptions& options, const std::string& name, const std::string& value);

/// How a front end names the options. The library's messages name an option by its field, in
/// backquotes (`k_b`: the table's name with underscores, as RunOptions::given records it); each
/// front end spells it its own way.
enum class OptionSpelling {
  Cli,     ///< the table's name ("k-b"); "--k-b" in a message
  Python,  ///< the field's name ("k_b"), as contract() takes it
};

/// The field name of a table name: "k-b" -> "k_b".
std::string option_field(const std::string& name);

/// The option's name in a spelling: "k-b" (Cli) or "k_b" (Python).
std::string option_name(const OptionSpec& option, OptionSpelling spelling);

/// A library message with every backquoted option field (`target_volume`) spelled for the front
/// end: "--target-volume" (Cli) or "target_volume" (Python). Backquotes around anything but a
/// table option's field are left as they are.
std::string spell_options(const std::string& message, OptionSpelling spelling);

/// The shortest decimal text that reads back as exactly `x` (0.3, 1e-4, 2).
std::string shortest_text(double x);

}  // namespace shellcontract
