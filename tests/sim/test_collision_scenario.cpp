// The shell never passes through itself (issue "self-collision"): a thin two-sheet shape that
// makes contact at once, validated by CGAL at every frame; without collision handling the same
// run does create intersections (so the check can fail).
#include <gtest/gtest.h>

#include <string>

#include "shellcontract/mesh_io.hpp"
#include "sim/simulator.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

Mesh two_sheet() { return read_input_mesh(std::string(test::MESH_DIR) + "/two_sheet.off"); }

TEST(CollisionScenario, TwoSheetShapeNeverIntersectsItself) {
  SimOptions opt;
  opt.frames = 150;
  // The paper's constant pressure (no air to stop it near V/V0 = 0.5) presses the sheets together.
  opt.air_balance = 0.0;
  opt.pressure = 2.0;
  opt.collisions = true;
  Simulator sim(two_sheet(), opt);
  ASSERT_EQ(sim.input_intersections(), 0u);
  long contacts = 0;
  while (!sim.finished()) {
    const FrameMetrics m = sim.step();
    contacts += m.collision.contacts;
    ASSERT_EQ(sim.count_new_intersections(), 0u) << "frame " << m.frame;
  }
  EXPECT_GT(contacts, 0) << "the sheets must actually touch in this scenario";
  EXPECT_LT(sim.volume_ratio(), 0.5) << "and the shell must still contract";
}

TEST(CollisionScenario, WithoutCollisionHandlingTheSheetsPassThrough) {
  SimOptions opt;
  opt.frames = 150;
  opt.collisions = false;
  Simulator sim(two_sheet(), opt);
  std::size_t worst = 0;
  while (!sim.finished()) {
    sim.step();
    worst = std::max(worst, sim.count_new_intersections());
  }
  EXPECT_GT(worst, 0u);
}

}  // namespace
}  // namespace shellcontract
