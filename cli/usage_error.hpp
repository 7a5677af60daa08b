// The one way a subcommand reports bad usage (README "Exit codes": 1).
#pragma once

#include <iostream>
#include <string>

#include "shellcontract/core/error.hpp"

namespace shellcontract::cli {

/// Prints "shellcontract COMMAND: WHAT" and where to find help on stderr.
/// @param command  the subcommand as typed, e.g. "run" or "bench ccd"
/// @return the bad-usage exit code
inline int usage_error(const std::string& command, const std::string& what) {
  std::cerr << "shellcontract " << command << ": " << what << "\n(see 'shellcontract " << command
            << " --help')\n";
  return static_cast<int>(ExitCode::BadUsage);
}

}  // namespace shellcontract::cli
