// A keyed target volume over a whole run (run_contraction): the summary's frame_target_reached
// counts from where the schedule arrives at the goal the run is judged by, and the stall rule
// does not end a run that a later key still lifts (docs/design/keyframes.md, "How the run uses
// them").
#include <gtest/gtest.h>

#include <string>

#include "shellcontract/checkpoint.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"
#include "sim/target_goal.hpp"
#include "support/memory_checkpointer.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

Mesh read(const std::string& name) {
  return read_input_mesh(std::string(test::MESH_DIR) + "/" + name);
}

RunOptions keyed(const std::string& keys, int frames) {
  RunOptions o;
  set_run_option(o, "target-volume", keys);
  set_run_option(o, "frames", std::to_string(frames));
  return o;
}

Schedule keys_of(const std::string& text) { return keyed(text, 1000).sim.target_volume_schedule; }

/// How many of the run's warnings contain `part`.
int warnings_with(const RunResult& r, const std::string& part) {
  int n = 0;
  for (const std::string& w : r.warnings) n += w.find(part) != std::string::npos;
  return n;
}

/// Cancels the run after frame `at`.
struct CancelAt final : RunObserver {
  int at = 0, seen = 0;
  void frame(const FrameView&, const FrameMetrics& m) override { seen = m.frame; }
  bool cancelled() override { return seen >= at; }
};

TEST(KeyedTarget, TheScheduleSettlesAtItsLastKeyOrWhereTheHoldToTheEndBegins) {
  const Schedule dip = keys_of("0:1, 10:0.85, 20:0.5, 30:0.85");
  EXPECT_EQ(schedule_settles_at(dip, 30), 30);
  EXPECT_EQ(schedule_settles_at(dip, 100), 30);
  EXPECT_EQ(schedule_settles_at(dip, 25), 25);  // still moving at the run's last frame
  EXPECT_EQ(schedule_settles_at(dip, 20), 20);
  const Schedule hold = keys_of("0:1, 20:0.001, 200:0.001, 240:1");
  EXPECT_EQ(schedule_settles_at(hold, 240), 240);
  EXPECT_EQ(schedule_settles_at(hold, 300), 240);
  EXPECT_EQ(schedule_settles_at(hold, 210), 210);
  EXPECT_EQ(schedule_settles_at(hold, 200), 20);  // the hold from 20 lasts to the end
  EXPECT_EQ(schedule_settles_at(hold, 150), 20);
  const Schedule held_end = keys_of("0:1, 10:0.7, 30:0.7");
  EXPECT_EQ(schedule_settles_at(held_end, 30), 10);
  EXPECT_EQ(schedule_settles_at(held_end, 5), 5);
  EXPECT_EQ(schedule_settles_at(keys_of("0:1, 40:0.6"), 20), 20);
  EXPECT_EQ(schedule_settles_at(Schedule({{10, 0.5}, {20, 0.5}}), 15), 0);
  EXPECT_EQ(schedule_settles_at(Schedule(), 15), 0);
}

TEST(KeyedTarget, ReachedCountsFromTheLastKeyNotFromAnEarlierKeyOfTheSameValue) {
  // At frame 10 the shell is at 0.85 on its way down to 0.5: the target, 0.85 again at frame 30,
  // is not there yet. Counting every frame whose schedule value equals the last key's gave 10.
  const RunResult r = run_contraction(read("ico2.off"), keyed("0:1, 10:0.85, 20:0.5, 30:0.85", 30));
  ASSERT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_TRUE(r.target_reached);
  EXPECT_EQ(r.frame_target_reached, 30);
}

TEST(KeyedTarget, ARunEndingBeforeTheLastKeyIsReachedAtItsLastFrame) {
  // The end check judges the schedule's value at the last frame; the frame it was reached is
  // that frame, not -1 beside target_reached true.
  const RunResult r = run_contraction(read("ico2.off"), keyed("0:1, 40:0.6", 20));
  ASSERT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_TRUE(r.target_reached);
  EXPECT_EQ(r.frame_target_reached, 20);
  // A run cancelled on the way is judged at the frame it stopped at, and so counted there too.
  CancelAt cancel;
  cancel.at = 10;
  const RunResult c = run_contraction(read("ico2.off"), keyed("0:1, 40:0.6", 40), &cancel);
  ASSERT_EQ(c.status, RunStatus::Cancelled) << c.message;
  ASSERT_EQ(c.frames_run, 10);
  EXPECT_TRUE(c.target_reached);
  EXPECT_EQ(c.frame_target_reached, 10);
}

// ico3 deflated toward 0.001 folds onto itself and its contacts hold it near V/V0 0.025, where
// the volume stalls (frame 66); the last keys lift it back to the rest volume.
const char* UNREACHABLE_HOLD = "0:1, 20:0.001, 100:0.001, 140:1";

TEST(KeyedTarget, AStallBeforeALaterKeyDoesNotEndTheRun) {
  const RunResult r = run_contraction(read("ico3.off"), keyed(UNREACHABLE_HOLD, 140));
  EXPECT_EQ(r.frames_run, 140) << r.message;
  EXPECT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_TRUE(r.target_reached);
  EXPECT_NEAR(r.final_volume_ratio, 1.0, TARGET_VOLUME_TOLERANCE);
  EXPECT_GE(r.frame_target_reached, 140);
  // Once, naming the key's value where the shell stalled.
  EXPECT_EQ(warnings_with(r, "the target volume's keys were not followed"), 1);
  EXPECT_EQ(warnings_with(r, "where the keys ask for 0.001"), 1);
}

TEST(KeyedTarget, AStallEndsTheRunOnceTheGoalHoldsToTheEnd) {
  // The same keys with the run ending inside the hold: nothing later changes the goal, so the
  // stall ends the run as with a single target, and no key warning is added.
  const RunResult r = run_contraction(read("ico3.off"), keyed(UNREACHABLE_HOLD, 90));
  EXPECT_LT(r.frames_run, 90);
  EXPECT_EQ(r.status, RunStatus::TargetNotReached);
  EXPECT_NE(r.message.find("target volume 0.001 not reached: the volume stalled"),
            std::string::npos)
      << r.message;
  EXPECT_EQ(warnings_with(r, "were not followed"), 0);
  EXPECT_EQ(r.frame_target_reached, -1);
}

TEST(KeyedTarget, AStopRatioRunIsNotEndedByAStallWhileThePressureKeysChange) {
  // Under -p 0.3 the air of ico2 holds it near V/V0 0.96, where the volume stalls (frame 59); the
  // keys after frame 100 raise the pressure to 20, which takes the shell to the stop ratio.
  RunOptions o;
  set_run_option(o, "pressure", "0:0.3, 100:0.3, 150:20");
  set_run_option(o, "stop-volume-ratio", "0.7");
  set_run_option(o, "frames", "200");
  const RunResult r = run_contraction(read("ico2.off"), o);
  EXPECT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_TRUE(r.target_reached);
  EXPECT_GT(r.frames_run, 100);
  EXPECT_LE(r.final_volume_ratio, 0.7 + target_volume_tolerance(0.7));
  // The pressure held at 0.3 to the end: the stall ends the run as with a single -p.
  set_run_option(o, "pressure", "0:0.3, 100:0.3");
  const RunResult held = run_contraction(read("ico2.off"), o);
  EXPECT_LT(held.frames_run, 100);
  EXPECT_EQ(held.status, RunStatus::TargetNotReached);
  EXPECT_NE(held.message.find("stalled"), std::string::npos) << held.message;
}

TEST(KeyedTarget, AResumedRunWarnsOfTheStallBeforeItsCheckpoint) {
  // The warning comes from the volume history, which the checkpoint carries: a run stopped after
  // the stall and resumed says it as the run never stopped does, and ends the same.
  const Mesh mesh = read("ico3.off");
  const RunOptions options = keyed(UNREACHABLE_HOLD, 140);
  const RunResult whole = run_contraction(mesh, options);
  test::MemoryCheckpointer saver(mesh, options, 80, /*stop=*/true);
  const RunResult first = run_contraction(mesh, options, nullptr, &saver);
  ASSERT_EQ(first.frames_run, 80) << first.message;
  ASSERT_TRUE(saver.saved.has_value());
  test::MemoryCheckpointer resumer(&*saver.saved);
  const RunResult rest =
      run_contraction(mesh, options_for_resume(*saver.saved, options), nullptr, &resumer);
  EXPECT_EQ(rest.status, whole.status) << rest.message;
  EXPECT_EQ(rest.frames_run, whole.frames_run);
  EXPECT_EQ(rest.frame_target_reached, whole.frame_target_reached);
  EXPECT_EQ(rest.final_volume_ratio, whole.final_volume_ratio);
  EXPECT_EQ(warnings_with(rest, "the target volume's keys were not followed"), 1);
}

}  // namespace
}  // namespace shellcontract
