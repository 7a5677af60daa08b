// Command-line plumbing shared by the subcommands: parsing options plus one positional INPUT,
// and the one way a subcommand reports bad usage (README "Exit codes": 1).
#pragma once

#include <algorithm>
#include <boost/program_options.hpp>
#include <cctype>
#include <filesystem>
#include <iostream>
#include <string>

#include "shellcontract/error.hpp"

namespace shellcontract::cli {

/// Prints "shellcontract COMMAND: WHAT" and where to find help on stderr.
/// @param command  the subcommand as typed, e.g. "run" or "bench ccd"
/// @return the bad-usage exit code
inline int usage_error(const std::string& command, const std::string& what) {
  std::cerr << "shellcontract " << command << ": " << what << "\n(see 'shellcontract " << command
            << " --help')\n";
  return static_cast<int>(ExitCode::BadUsage);
}

/// A path's extension in lower case without its dot ("OBJ" -> "obj"; "" when it has none): the
/// name by which the readers and writers pick a format.
inline std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// Refuses an option given with an empty value (`--log ""`): a script whose variable is unset
/// would otherwise turn that output off, or a --resume into a fresh run, without a word. No
/// option of any command takes an empty string.
/// @throws UsageError naming the option ("INPUT" for the positional one)
inline void refuse_empty_values(const boost::program_options::variables_map& vm) {
  for (const auto& [name, value] : vm) {
    if (value.defaulted()) continue;
    const auto* text = boost::any_cast<std::string>(&value.value());
    if (text != nullptr && text->empty())
      throw UsageError(name == "input" ? std::string("INPUT: an empty file name")
                                       : "--" + name + ": empty; give a value or leave the option out");
  }
}

/// Parses the arguments of a subcommand that takes the options of `visible` and one positional
/// INPUT (stored into `input` unless help was asked for).
/// @throws boost::program_options::error for an unknown option or a bad value; UsageError for
///         an empty value (refuse_empty_values)
/// @return the parsed values; `vm.count("help")` tells whether --help was given
inline boost::program_options::variables_map parse_command_line(
    int argc, char** argv, const boost::program_options::options_description& visible,
    std::string& input) {
  namespace po = boost::program_options;
  po::options_description hidden;
  hidden.add_options()("input", po::value(&input), "input mesh");
  po::options_description all;
  all.add(visible).add(hidden);
  po::positional_options_description positional;
  positional.add("input", 1);
  po::variables_map vm;
  po::store(po::command_line_parser(argc, argv).options(all).positional(positional).run(), vm);
  if (vm.count("help")) return vm;
  refuse_empty_values(vm);
  po::notify(vm);
  return vm;
}

}  // namespace shellcontract::cli
