// Thin closed shells (a 1 x 1 x t card, an icosphere squashed in z) through run_contraction: the
// stop ratio is reached by the volume a step ends with, and the run warns when the shell grows
// under an outside pressure or its volume swings from frame to frame (sim/volume_warnings.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "shellcontract/run.hpp"
#include "sim/volume_warnings.hpp"
#include "support/cgal_mesh.hpp"
#include "support/cgal_volume.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/thin_card.hpp"

namespace shellcontract {
namespace {

/// The stop ratio's tolerance above E for E >= 0.1 (the target volume's, issue "Control"), a
/// number here so that widening the code's constant does not widen the test.
constexpr double STOP_TOLERANCE = 0.005;

struct Ratios final : RunObserver {
  std::vector<double> ratios{1.0};
  void frame(const FrameView&, const FrameMetrics& m) override { ratios.push_back(m.volume_ratio); }
};

bool has_warning(const RunResult& r, const std::string& text) {
  return std::any_of(r.warnings.begin(), r.warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

TEST(ThinShell, TheStopRatioIsReachedOnlyByTheVolumeAfterTheResponse) {
  // A card 1e-3 thick under --stop-volume-ratio 0.2 --air-balance 0: the first step's prediction
  // crossed 0.2, the collision response pushed the sheets apart again, and the run stopped at
  // frame 1 with V/V0 0.32 reported as reached (exit 0). Reached now means the V/V0 the step
  // ended with; otherwise the run goes on and, if it never gets there, says so (exit 5).
  const test::TriMesh card = test::thin_card(1e-3);
  RunOptions o;
  o.sim.frames = 200;
  o.sim.stop_volume_ratio = 0.2;
  o.sim.air_balance = 0.0;
  o.sim.solver.threads = 1;
  Ratios seen;
  const RunResult r = run_contraction(test::to_surface_mesh(card), o, &seen);
  // The result's own volume, computed apart from the run.
  EXPECT_NEAR(test::cgal_volume_ratio(test::to_surface_mesh(card), r.positions),
              r.final_volume_ratio, 1e-9);
  if (r.target_reached) {
    EXPECT_LE(r.final_volume_ratio, 0.2 + STOP_TOLERANCE) << "frame " << r.frames_run;
    EXPECT_EQ(r.exit_code(), 0);
    EXPECT_EQ(r.frame_target_reached, r.frames_run);
  } else {
    EXPECT_EQ(r.status, RunStatus::TargetNotReached);
    EXPECT_EQ(r.exit_code(), 5);
    EXPECT_NE(r.message.find("stop volume ratio 0.2000 not reached"), std::string::npos)
        << r.message;
    EXPECT_GT(r.final_volume_ratio, 0.2 + STOP_TOLERANCE);
  }
  // No frame before the last ended at or below the stop ratio: the run stops on the first.
  for (std::size_t n = 1; n + 1 < seen.ratios.size(); ++n)
    EXPECT_GT(seen.ratios[n], 0.2) << "frame " << n << " reached it, the run went on";
}

TEST(ThinShell, AShellThatGrowsUnderAnOutsidePressureIsNamed) {
  // A card 2e-4 thick under the default run (-p 4, compressing) ended at V/V0 3.66 with exit 0
  // and no warning. Whatever V/V0 it ends at, the run names a growth above 1 %.
  const test::TriMesh card = test::thin_card(2e-4);
  RunOptions o;
  o.sim.frames = 200;
  o.sim.solver.threads = 1;
  ASSERT_GT(o.sim.pressure, 0.0);
  const RunResult r = run_contraction(test::to_surface_mesh(card), o);
  EXPECT_EQ(has_warning(r, "although the outside pressure compresses the shell: it grew"),
            r.final_volume_ratio > 1.01)
      << "V/V0 " << r.final_volume_ratio;
  // The scenario the warning is for: if the card no longer grows, the warning is untested here
  // (volume_warnings is below).
  EXPECT_GT(r.final_volume_ratio, 1.01);
}

TEST(ThinShell, ASwingingVolumeIsNamed) {
  // An icosphere squashed to 1e-4 of its height (--delta auto): the explicit air pressure
  // overshoots every step and V/V0 went 0.28, 14, 0.28, 12 ... on alternate frames, exit 0 and no
  // warning. The run names a rise and a fall by more than a factor 2 in its second half.
  test::TriMesh pillow = test::icosphere(2, 0.5);
  pillow.x.col(2) *= 1e-4;
  RunOptions o;
  o.sim.frames = 20;
  o.sim.auto_delta = true;
  o.sim.solver.threads = 1;
  Ratios seen;
  const RunResult r = run_contraction(test::to_surface_mesh(pillow), o, &seen);
  bool rose = false, fell = false;
  for (std::size_t n = 10; n < seen.ratios.size(); ++n) {
    rose = rose || seen.ratios[n] > 2.0 * seen.ratios[n - 1];
    fell = fell || seen.ratios[n - 1] > 2.0 * seen.ratios[n];
  }
  EXPECT_EQ(has_warning(r, "from frame to frame in the second half of the run"), rose && fell);
  EXPECT_TRUE(rose && fell) << "the pillow no longer swings: the warning is untested here";
  // Its sheets are so close that the air's spring is past the explicit step's bound at the
  // default density (sim/air_step.hpp): the run said so before its first step.
  EXPECT_TRUE(has_warning(r, "that the enclosed air is sure to take back in one step"));
}

TEST(ThinShell, VolumeWarningsFromAHistory) {
  // Growth: only under an outside pressure, only beyond a percent.
  EXPECT_EQ(volume_warnings({1.0, 0.9, 1.2}, true).size(), 1u);
  EXPECT_TRUE(volume_warnings({1.0, 0.9, 1.2}, false).empty());
  EXPECT_TRUE(volume_warnings({1.0, 0.99, 1.005}, true).empty());
  EXPECT_TRUE(volume_warnings({1.0}, true).empty());
  // A swing: up and down by more than twice in the second half (frames 2 to 4 here).
  const std::vector<std::string> w = volume_warnings({1.0, 0.9, 0.3, 0.9, 0.3}, true);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("swung between 0.3 and 0.9"), std::string::npos) << w[0];
  // A fall alone is a collapse, not a swing; so is a swing that ended in the first half.
  EXPECT_TRUE(volume_warnings({1.0, 0.9, 0.8, 0.3, 0.1}, true).empty());
  EXPECT_TRUE(volume_warnings({1.0, 0.3, 0.9, 0.3, 0.5, 0.5, 0.5, 0.5, 0.5}, true).empty());
}

// Before, only a rise and a fall by a factor 2 between two frames were a swing: a light `density`
// (bumpy_sphere at 0.002) swung between about 0.3 and 0.6 for its whole run and ended "ok" with
// no warning. A sustained swing is now also SWING_REVERSALS reversals by SWING_SHARE.

/// 100 frames of a fall from 1 to `settle`, then `tail` (the second half, frames 101 to 200).
std::vector<double> history(double settle, const std::vector<double>& tail) {
  std::vector<double> h{1.0};
  for (int n = 1; n <= 100; ++n) h.push_back(1.0 + (settle - 1.0) * n / 100.0);
  h.insert(h.end(), tail.begin(), tail.end());
  return h;
}

TEST(ThinShell, ASustainedSwingBelowAFactorTwoIsNamed) {
  // 0.35, 0.6, 0.35, ... as a light shell's air overshoots every step: each rise a factor 1.7.
  std::vector<double> tail;
  for (int n = 0; n < 100; ++n) tail.push_back(n % 2 ? 0.6 : 0.35);
  const std::vector<double> h = history(0.35, tail);
  // The first rise (frame 102) starts the count; each of the 98 frames after it turns back.
  EXPECT_EQ(swing_reversals(h, 100), 98);
  const std::vector<std::string> w = volume_warnings(h, true);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("swung between 0.35 and 0.6"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("98 times up and down by 10 % or more"), std::string::npos) << w[0];
  // A slower swing too: four frames up, four down, by a quarter.
  tail.clear();
  for (int n = 0; n < 100; ++n)
    tail.push_back(n % 8 < 4 ? 0.4 + 0.05 * (n % 4) : 0.55 - 0.05 * (n % 4));
  EXPECT_EQ(volume_warnings(history(0.4, tail), true).size(), 1u);
  // The same V/V0 where keys drive the load (a keyed target that breathes in and out) is what
  // the keys asked for: not named.
  EXPECT_TRUE(volume_warnings(history(0.4, tail), false, /*scheduled=*/true).empty());
  // A swing wholly above the rest volume under an outside pressure grew too (the thin card
  // above swings between about 3.3 and 3.9): both are named.
  tail.clear();
  for (int n = 0; n < 100; ++n) tail.push_back(n % 2 ? 3.9 : 3.3);
  const std::vector<std::string> grew = volume_warnings(history(3.3, tail), true);
  ASSERT_EQ(grew.size(), 2u);
  EXPECT_NE(grew[1].find("it grew"), std::string::npos) << grew[1];
  EXPECT_EQ(volume_warnings(history(3.3, tail), false).size(), 1u);
}

TEST(ThinShell, ASettlingOrReboundingVolumeIsNoSwing) {
  // Settling with noise of 2 % from frame to frame.
  std::vector<double> tail;
  for (int n = 0; n < 100; ++n) tail.push_back(0.5 * (1.0 + (n % 2 ? 0.02 : -0.02)));
  EXPECT_EQ(swing_reversals(history(0.5, tail), 100), 0);
  EXPECT_TRUE(volume_warnings(history(0.5, tail), true).empty());
  // A rebound when a pressure key drops, with one overshoot: one reversal.
  tail.clear();
  for (int n = 0; n < 100; ++n) tail.push_back(n < 20 ? 0.5 : n < 30 ? 0.5 + 0.04 * (n - 20) : 0.8);
  tail[30] = 0.95;
  EXPECT_LT(swing_reversals(history(0.5, tail), 100), SWING_REVERSALS);
  EXPECT_TRUE(volume_warnings(history(0.5, tail), false).empty());
  // A swing of the first half alone, and an inside-out history, are not counted.
  std::vector<double> early{1.0};
  for (int n = 0; n < 100; ++n) early.push_back(n % 2 ? 0.6 : 0.35);
  early.insert(early.end(), 100, 0.45);
  EXPECT_TRUE(volume_warnings(early, true).empty());
  EXPECT_EQ(swing_reversals({0.5, -0.5, 0.5, -0.5, 0.5}, 0), 0);
}

}  // namespace
}  // namespace shellcontract
