// A run's cancel inside the single long calls of the Simulator's preparation
// (core/cancellation.hpp): the contact distance's rest-gap surveys (`delta` auto, a given delta's
// check), the collision step's rest pairs and the baseline of the input's own self-intersections.
// Before, each ran to its end on a large mesh without a question, and a cancel during the
// baseline, the last stage, was heard only after the first step. Each test failed there.
#include <gtest/gtest.h>

#include <functional>

#include "collision/self_collision.hpp"
#include "core/cancellation.hpp"
#include "mesh/eigen_point_map.hpp"
#include "shellcontract/run.hpp"
#include "sim/contact_distance.hpp"
#include "sim/rest_state.hpp"
#include "sim/run_plan.hpp"
#include "support/cancel_probe.hpp"
#include "support/cgal_mesh.hpp"

namespace shellcontract {
namespace {

/// Level 6: 81920 faces, several CANCELLATION_CHUNKs of faces and of rest pairs.
const Mesh& sphere() {
  static const Mesh mesh = test::to_surface_mesh(test::icosphere(6));
  return mesh;
}

/// The sphere at the run's normalized positions, as the contact distance sees it.
const Mesh& normalized_sphere() {
  static const Mesh mesh = [] {
    SimOptions o;
    o.collisions = false;
    return plan_simulation(sphere(), o).mesh;
  }();
  return mesh;
}

using test::stops_at;

/// Heard at its start and at its third question.
void expect_heard_inside(const char* what, const std::function<void()>& call) {
  test::expect_heard_inside(what, call, 3);
}

TEST(RunCancelCalls, TheContactDistanceHearsACancel) {
  for (const bool automatic : {true, false}) {
    SimOptions o;
    o.auto_delta = automatic;
    resolve_sim_options(o);
    expect_heard_inside(automatic ? "delta auto" : "a given delta",
                        [&] { choose_contact_distance(normalized_sphere(), o); });
  }
}

TEST(RunCancelCalls, TheRestPairsOfTheCollisionStepHearACancel) {
  SimOptions o;
  o.auto_delta = true;
  resolve_sim_options(o);
  o.collision.delta = choose_contact_distance(normalized_sphere(), o).delta;
  const Faces faces = faces_array(normalized_sphere());
  const Positions rest = positions_from_mesh(normalized_sphere());
  EXPECT_TRUE(stops_at(1, [&] { SelfCollision c(faces, rest, o.collision); }));
  EXPECT_TRUE(stops_at(2, [&] { SelfCollision c(faces, rest, o.collision); }));
}

/// Counts the questions of a run's preparation (those before started()) and its frames.
struct Counter final : RunObserver {
  explicit Counter(int at) : cancel_at(at) {}
  int cancel_at, checks = 0, checks_before_start = -1, started_calls = 0, frames = 0;
  void started(const FrameView&) override {
    ++started_calls;
    checks_before_start = checks;
  }
  void frame(const FrameView&, const FrameMetrics&) override { ++frames; }
  bool cancelled() override { return ++checks >= cancel_at; }
};

RunOptions without_contacts(ValidateMode validate) {
  RunOptions o;
  o.sim.frames = 3;
  o.sim.collisions = false;  // the baseline is then the only stage after the constraints'
  o.sim.validate = validate;
  return o;
}

// The baseline is checked in slabs, with a question between them: a cancel at the first
// question after the stages that a run without validation has is heard before the first step.
TEST(RunCancelCalls, ACancelDuringTheSelfIntersectionBaselineEndsTheRunBeforeItsFirstStep) {
  Counter plain(1 << 30), validated(1 << 30);
  run_contraction(sphere(), without_contacts(ValidateMode::Off), &plain);
  run_contraction(sphere(), without_contacts(ValidateMode::End), &validated);
  ASSERT_EQ(plain.started_calls, 1);
  ASSERT_EQ(validated.started_calls, 1);
  EXPECT_GT(validated.checks_before_start, plain.checks_before_start + 1)
      << "the baseline asks nothing, or only at its end";

  Counter c(plain.checks_before_start + 1);
  const RunResult r = run_contraction(sphere(), without_contacts(ValidateMode::End), &c);
  EXPECT_EQ(r.status, RunStatus::Cancelled);
  EXPECT_EQ(c.checks, plain.checks_before_start + 1);
  EXPECT_EQ(c.started_calls, 0) << "heard after the baseline ended and the run started";
  EXPECT_EQ(c.frames, 0);
  EXPECT_NE(r.message.find("before the first step"), std::string::npos) << r.message;
}

}  // namespace
}  // namespace shellcontract
