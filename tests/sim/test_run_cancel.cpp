// A run's cancel request before and after its frames (shellcontract/run.hpp, observer.hpp).
// Before: the observer's cancelled() and the checkpointer's stop() were asked only after each
// step, so a run could not be stopped while its regions were selected (`regions` auto on a large
// mesh) or its Simulator built; and a cancelled run with `validate` end still ran the final
// self-intersection check, the slowest part of a large mesh's end. Each test failed on that code.
#include <gtest/gtest.h>

#include <string>

#include "shellcontract/checkpoint.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"
#include "support/cgal_mesh.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

/// Answers cancelled() with true from its `cancel_at`-th call on, and counts what it is shown.
struct Canceller final : RunObserver {
  explicit Canceller(int at) : cancel_at(at) {}
  int cancel_at;
  int checks = 0, started_calls = 0, finished_calls = 0, frames = 0;
  void started(const FrameView&) override { ++started_calls; }
  void frame(const FrameView&, const FrameMetrics&) override { ++frames; }
  bool cancelled() override { return ++checks >= cancel_at; }
  void finished(const FrameView&, const RunResult&) override { ++finished_calls; }
};

/// Saves nothing; stop() says true once the run has reached `stop_at` frames (0: from the start,
/// as the CLI's does after a signal).
struct Stopper final : RunCheckpointer {
  explicit Stopper(int at) : stop_at(at) {}
  int stop_at, frame = 0, stops = 0;
  bool save_due(int f) override {
    frame = f;
    return false;
  }
  void save(const SavedRun&) override {}
  bool stop() override {
    ++stops;
    return frame >= stop_at;
  }
};

Mesh bumpy() { return read_input_mesh(std::string(test::MESH_DIR) + "/bumpy_sphere.off"); }

RunOptions auto_regions(int frames) {
  RunOptions o;
  for (const auto& [k, v] :
       {std::pair<const char*, const char*>{"regions", "auto"}, {"pressure", "0"}})
    set_run_option(o, k, v);
  o.sim.frames = frames;
  return o;
}

TEST(RunCancel, ACancelAtTheFirstCheckEndsTheRunBeforeItsRegionsAreSelected) {
  const Mesh mesh = bumpy();
  const RunResult whole = run_contraction(mesh, auto_regions(0));
  ASSERT_GT(whole.regions, 0u) << "the mesh must have regions to select, or this cannot fail";

  Canceller c(1);
  const RunResult r = run_contraction(mesh, auto_regions(5), &c);
  EXPECT_EQ(r.status, RunStatus::Cancelled);
  EXPECT_EQ(r.exit_code(), static_cast<int>(ExitCode::Cancelled));
  EXPECT_EQ(c.checks, 1) << "asked again after it said cancelled";
  EXPECT_EQ(c.started_calls, 0) << "the run was prepared and started";
  EXPECT_EQ(c.frames, 0);
  EXPECT_EQ(c.finished_calls, 0);
  EXPECT_EQ(r.frames_run, 0);
  EXPECT_EQ(r.regions, 0u) << "the selection finished";
  EXPECT_NE(r.message.find("cancelled before the first step"), std::string::npos) << r.message;
  // Nothing ran: the result is the input.
  EXPECT_EQ(r.positions, positions_from_mesh(mesh));
}

// The selection itself asks, between its stages: a cancel at the third check still ends the run
// inside it.
TEST(RunCancel, TheSelectionAsksBetweenItsStages) {
  for (const int at : {2, 3, 4}) {
    Canceller c(at);
    const RunResult r = run_contraction(bumpy(), auto_regions(5), &c);
    EXPECT_EQ(r.status, RunStatus::Cancelled) << at;
    EXPECT_EQ(c.checks, at);
    EXPECT_EQ(c.started_calls, 0) << "cancelled at check " << at << " after the preparation";
    EXPECT_EQ(r.regions, 0u) << "cancelled at check " << at << " after the selection";
  }
}

// The CLI stops on a signal through its checkpointer's stop(): asked during the preparation too,
// with its own message (cli/run_interrupt.hpp names no frame then).
TEST(RunCancel, TheCheckpointersStopEndsThePreparationToo) {
  Canceller never(1 << 30);
  Stopper s(0);
  const RunResult r = run_contraction(bumpy(), auto_regions(5), &never, &s);
  EXPECT_EQ(r.status, RunStatus::Cancelled);
  EXPECT_EQ(s.stops, 1);
  EXPECT_EQ(never.started_calls, 0);
  EXPECT_EQ(r.frames_run, r.first_frame);
  EXPECT_EQ(r.message.rfind("interrupted before the first step", 0), 0u) << r.message;
}

/// A run of a sphere with `validate` end.
RunOptions validated(int frames) {
  RunOptions o;
  o.sim.frames = frames;
  o.sim.validate = ValidateMode::End;
  return o;
}

Mesh sphere() { return test::to_surface_mesh(test::icosphere(2)); }

// Before: the cancelled run ran the final check (new_intersections 0 here) before returning.
TEST(RunCancel, ACancelledRunSkipsTheFinalSelfIntersectionCheck) {
  const RunResult whole = run_contraction(sphere(), validated(6));
  ASSERT_EQ(whole.new_intersections, 0) << "the end must be checked, or this cannot fail";

  struct AfterFrames final : RunObserver {
    int frames = 0;
    void frame(const FrameView&, const FrameMetrics&) override { ++frames; }
    bool cancelled() override { return frames >= 2; }
  } after_two;
  const RunResult r = run_contraction(sphere(), validated(6), &after_two);
  EXPECT_EQ(r.status, RunStatus::Cancelled);
  EXPECT_EQ(r.frames_run, 2);
  EXPECT_EQ(r.new_intersections, -1) << "the cancelled run was checked";
  EXPECT_NE(r.message.find("not checked for self-intersections"), std::string::npos) << r.message;

  // Stopped by the checkpointer (the CLI's signal): the same.
  Stopper s(2);
  const RunResult i = run_contraction(sphere(), validated(6), nullptr, &s);
  EXPECT_EQ(i.status, RunStatus::Cancelled);
  EXPECT_EQ(i.frames_run, 2);
  EXPECT_EQ(i.new_intersections, -1) << "the interrupted run was checked";
}

}  // namespace
}  // namespace shellcontract
