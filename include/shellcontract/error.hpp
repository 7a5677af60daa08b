// Error types with the exit codes documented in README.md ("Exit codes").
#pragma once

#include <stdexcept>
#include <string>

namespace shellcontract {

/// Process exit codes of the `shellcontract` tool (docs/cli.md, "Exit codes").
enum class ExitCode : int {
  Success = 0,
  BadUsage = 1,              ///< unknown option, missing argument, unwritable output path
  BadInput = 2,              ///< the input mesh cannot be used; the message says what and where
  SimulationFailed = 3,      ///< NaN, blow-up, out of memory or a refused resource (docs/cli.md)
  NewSelfIntersections = 4,  ///< validation found intersections that the input did not have
  TargetNotReached =
      5,  ///< --target-volume or --stop-volume-ratio not reached (stalled, or out of frames)
  Cancelled = 130,  ///< interrupted by the caller (the shell's code for SIGINT)
};

/// Bad usage of the library or the tool (exit code 1).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The input mesh cannot be used (exit code 2). The message names the file and, where it
/// applies, the line, face or vertex.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The simulation produced non-finite values or blew up (exit code 3).
class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace shellcontract
