// What `run` says when it did not end as planned besides a signal (run_interrupt.hpp): an output
// that could not be written after a run that itself failed, and a run ended by an exception (out
// of memory, a thread the system refused) after frame files were already written.
#pragma once

#include <cstddef>
#include <string>

#include "core/plural.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/run.hpp"

namespace shellcontract::cli {

/// The exit code of a run with an output that could not be written (docs/cli.md): the run's own
/// failure code when it failed (3, 4 or 5: the more specific news, which exit code 1 would hide),
/// else 1. A run cancelled without a signal was stopped by its failed frame export: 1.
inline int output_failure_exit_code(const RunResult& r) {
  switch (r.status) {
    case RunStatus::SimulationFailed:
    case RunStatus::NewIntersections:
    case RunStatus::TargetNotReached:
      return r.exit_code();
    default:
      return static_cast<int>(ExitCode::BadUsage);
  }
}

/// The run's own failure in words ("simulation failed: out of memory at step 1 ..."), "" when it
/// did not fail: printed after the list of outputs, which names the run's status only.
inline std::string run_failure_text(const RunResult& r) {
  switch (r.status) {
    case RunStatus::SimulationFailed:
      return "simulation failed: " + r.message;
    case RunStatus::NewIntersections:
      return "validation found new self-intersections: " + r.message;
    case RunStatus::TargetNotReached:
      return r.message;
    default:
      return std::string();
  }
}

/// What a run ended by an exception leaves: "nothing was written", "wrote A and B only", and the
/// --export-dir frames it had finished (`frames` in `dir`), which a rerun into that folder
/// refuses until they are removed, so the user must learn where they are.
inline std::string what_was_left(const std::string& written, std::size_t frames,
                                 const std::string& dir) {
  const std::string left = counted(frames, "finished frame", "finished frames") + " in " + dir;
  const std::string remove =
      std::string(" (remove ") + one_or_many(frames, "it", "them") + " to rerun)";
  if (frames == 0) return written.empty() ? "nothing was written" : "wrote " + written + " only";
  if (written.empty()) return "nothing was written but the " + left + remove;
  return "wrote " + written + " only; the " + left + " " + one_or_many(frames, "stays", "stay") +
         remove;
}

}  // namespace shellcontract::cli
