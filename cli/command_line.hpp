// Command-line plumbing shared by the subcommands: parsing options plus one positional INPUT,
// and the one way a subcommand reports bad usage (README "Exit codes": 1).
#pragma once

#include <algorithm>
#include <boost/program_options.hpp>
#include <cctype>
#include <filesystem>
#include <iostream>
#include <string>

#include "mesh/formats.hpp"  // lower_extension, for the subcommands
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
/// INPUT (stored into `input` unless help was asked for). Every command parses the same way
/// (command_line.cpp): an option's name in full (no prefix of it taken for it; an unknown name is
/// refused with the nearest names), no second positional argument (the message names it), no
/// `-o=FILE` taken as the file "=FILE".
/// @throws boost::program_options::error for an unknown option or a bad value; UsageError for
///         an empty value (refuse_empty_values), a stray argument or `-X=VALUE`
/// @return the parsed values; `vm.count("help")` tells whether --help was given
boost::program_options::variables_map parse_command_line(
    int argc, char** argv, const boost::program_options::options_description& visible,
    std::string& input);

/// parse_command_line for a command without a positional argument (bench ccd): any is refused.
boost::program_options::variables_map parse_options_only(
    int argc, char** argv, const boost::program_options::options_description& visible);

/// " (did you mean --frames?)" for an unknown option name ("--frame"): the options of `visible`
/// that it begins (a prefix, which some parsers take for the option), or else the nearest by
/// edit distance (at most 2, and less than half the name); empty when none is near.
std::string option_suggestion(const std::string& unknown,
                              const boost::program_options::options_description& visible);

}  // namespace shellcontract::cli
