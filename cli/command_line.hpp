// Command-line plumbing shared by the subcommands: parsing options plus one positional INPUT,
// and the one way a subcommand reports bad usage (README "Exit codes": 1).
#pragma once

#include <boost/program_options.hpp>
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

/// Parses the arguments of a subcommand that takes the options of `visible` and one positional
/// INPUT (stored into `input` unless help was asked for).
/// @throws boost::program_options::error for an unknown option or a bad value
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
  if (!vm.count("help")) po::notify(vm);
  return vm;
}

}  // namespace shellcontract::cli
