// What a long piece of work is doing, for whoever waits on it: reading a large mesh, selecting its
// regions, building a run's rest state or repairing a mesh each take seconds to tens of seconds
// on hundreds of thousands of faces, and the CLI printed nothing all that time. The library
// prints nothing itself: the work calls progress_stage() as it enters each stage, and the caller
// that opened a ProgressStageScope on that thread hears it (run_contraction passes it to its
// observer's stage(), the CLI to its stage line, cli/stage_notice.hpp).
#pragma once

#include <functional>
#include <string>

namespace shellcontract {

/// While alive, progress_stage() on the thread that made it calls `tell`. A nested scope takes
/// over until it ends. Per thread, as the cancellation scope (cancellation.hpp): two runs on two
/// threads hear their own, and a TBB worker's calls are heard by nobody.
class ProgressStageScope {
 public:
  explicit ProgressStageScope(std::function<void(const std::string&)> tell);
  ~ProgressStageScope();
  ProgressStageScope(const ProgressStageScope&) = delete;
  ProgressStageScope& operator=(const ProgressStageScope&) = delete;

 private:
  std::function<void(const std::string&)> tell_;
  const ProgressStageScope* previous_;
  friend void progress_stage(const std::string& what);
};

/// Tells this thread's scope that the work enters the stage `what` (a few words: "reading
/// bear.off", "building the rest state"); does nothing without one. Called as a stage starts,
/// not as it ends: the stage lasts until the next call, or until the scope's owner moves on.
void progress_stage(const std::string& what);

}  // namespace shellcontract
