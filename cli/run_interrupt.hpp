// What `run` says when SIGINT or SIGTERM stopped it (exit 130): the frame it stopped at, what
// was saved (--checkpoint) and what is left (the finished --export-dir frames); nothing else is
// written (docs/cli.md). Printed with -q too: -q silences the progress, not why a run ended.
#pragma once

#include <iostream>
#include <string>
#include <utility>

#include "core/plural.hpp"
#include "export_observer.hpp"
#include "run_checkpoint.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/run.hpp"

namespace shellcontract::cli {

/// The outputs asked for that a resumed run cannot write (they need the frames before the
/// checkpoint, which it does not hold: `--resume` refuses them), "" when none.
inline std::string lost_on_resume(const ExportRequest& exports, bool fields) {
  std::string lost;
  for (const auto& [asked, name] : {std::pair<bool, const char*>{!exports.gltf.empty(), "--gltf"},
                                    {fields, "--fields"},
                                    {!exports.dir.empty(), "--export-dir"}})
    if (asked) lost += (lost.empty() ? "" : ", ") + std::string(name);
  return lost;
}

/// The message of an interrupted run, one line on stderr; returns the exit code (130).
/// @param fields  whether --fields was given
inline int report_interrupted(const RunResult& r, const CliCheckpointer& checkpointer,
                              const std::string& output, const ExportRequest& exports,
                              const ExportStats& frames, bool fields) {
  // Stopped while its regions were selected or its Simulator built (run_contraction asks the
  // checkpointer between those stages): no step ran, so nothing was saved or exported.
  if (r.frames_run == r.first_frame) {
    std::cerr << "shellcontract run: interrupted before the first step, while preparing the run; "
                 "nothing was written";
    if (const Checkpoint* c = checkpointer.resume_from())
      std::cerr << " (the checkpoint it resumed from, " << c->path << ", is as it was)";
    std::cerr << '\n';
    return static_cast<int>(ExitCode::Cancelled);
  }
  std::cerr << "shellcontract run: interrupted at frame " << r.frames_run;
  // The resumed run goes on saving to the file it resumed from (and as often), so the command
  // below is all a job that is preempted again needs.
  const std::string resume_with = " (continue with: shellcontract run --resume " +
                                  checkpointer.path() + " -o " + output +
                                  " ..., which goes on saving there)";
  const bool saved = !checkpointer.path().empty() && checkpointer.saved_frame() == r.frames_run;
  if (saved)
    std::cerr << "; the state is saved in " << checkpointer.path() << resume_with;
  else if (!checkpointer.path().empty())
    // A failed save leaves the file as it was: whether that is an older checkpoint to go on from
    // is the user's next question.
    std::cerr << "; the checkpoint could not be written"
              << (checkpointer.first_failure().empty() ? ""
                                                       : " (" + checkpointer.first_failure() + ")")
              << "; " << checkpointer.left_in_place()
              << (checkpointer.frame_in_place() >= 0 ? resume_with : std::string());
  // The command above gives the mesh only: say so, rather than let a studio find the animation
  // missing after the resume.
  if (const std::string lost = lost_on_resume(exports, fields);
      !checkpointer.path().empty() && !lost.empty())
    std::cerr << "; a resumed run writes the mesh only, not " << lost
              << " (they need the frames before the checkpoint: rerun from the start for them)";
  // The frames stay (each complete) and a rerun into the same folder is refused until they are
  // removed: the user must learn where they are.
  const auto n = static_cast<std::size_t>(frames.frames_written);
  const std::string left =
      exports.dir.empty() || n == 0
          ? std::string()
          : counted(n, "finished frame", "finished frames") + " in " + exports.dir;
  if (checkpointer.path().empty())
    std::cerr << "; nothing was written"
              << (left.empty() ? ""
                               : " but the " + left + " (remove " + one_or_many(n, "it", "them") +
                                     " to rerun)");
  else if (!left.empty())
    std::cerr << "; the " << left << ' ' << one_or_many(n, "stays", "stay") << " (remove "
              << one_or_many(n, "it", "them") << " to rerun)";
  std::cerr << '\n';
  return static_cast<int>(ExitCode::Cancelled);
}

}  // namespace shellcontract::cli
