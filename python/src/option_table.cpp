// The option table as Python sees it (shellcontract.options()): names and help by Python's
// spelling.
#include <cctype>
#include <string>

#include "contract.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract::python {

std::string python_option_name(std::string cli_name) {
  for (char& c : cli_name)
    if (c == '-') c = '_';
  return cli_name;
}

namespace {

/// The table's help with the other options named as Python names them: "--young" and "-p" are
/// the CLI's spellings, and contract() has no argument "--young". Only names of run options
/// change ("--help" or a command's "regions --region-at" keep their dashes where no run option
/// matches).
std::string python_help(const std::string& help) {
  const auto is_name_char = [](char c) { return std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '-'; };
  std::string out;
  std::size_t i = 0;
  while (i < help.size()) {
    const bool start = i == 0 || !is_name_char(help[i - 1]);
    if (start && help.compare(i, 2, "--") == 0) {
      std::size_t end = i + 2;
      while (end < help.size() && is_name_char(help[end])) ++end;
      while (end > i + 2 && help[end - 1] == '-') --end;  // "--frames-" ends a phrase, not a name
      const OptionSpec* o = find_run_option(help.substr(i + 2, end - i - 2));
      if (o && o->name == help.substr(i + 2, end - i - 2)) {
        out += python_option_name(o->name);
        i = end;
        continue;
      }
    } else if (start && help[i] == '-' && i + 1 < help.size() &&
               (i + 2 == help.size() || !is_name_char(help[i + 2]))) {
      const OptionSpec* o = nullptr;
      for (const OptionSpec& candidate : run_option_table())
        if (candidate.short_name != 0 && candidate.short_name == help[i + 1]) o = &candidate;
      if (o) {  // "-p > 0"
        out += python_option_name(o->name);
        i += 2;
        continue;
      }
    }
    out += help[i++];
  }
  return out;
}

}  // namespace

py::list option_table() {
  const RunOptions defaults;
  py::list out;
  for (const OptionSpec& o : run_option_table())
    out.append(py::make_tuple(python_option_name(o.name), o.get(defaults), python_help(o.help), o.name));
  return out;
}

}  // namespace shellcontract::python
