// The default run contracts every mesh by a similar, recognisable amount (issue "Control",
// item 5; the rest of the meshes in tests/long), and the local contraction's strength controls
// how far regions sink (issue "Local contraction", items 1-2).
#include <gtest/gtest.h>

#include <iostream>

#include "support/default_run_case.hpp"

namespace shellcontract {
namespace {

TEST(Defaults, EightEndsBetween04And08) { test::check_default_run_range("eight"); }
TEST(Defaults, HandEndsBetween04And08) { test::check_default_run_range("hand"); }

TEST(Defaults, ThePapersSettingIsStillAvailable) {
  // --air-balance 0 --bending isometric -p 2: the paper's constant pressure crushes the hand far
  // below the default's end volume (design/defaults.md: 0.31 with collisions on).
  const std::string path = test::target_mesh_path("hand");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
  RunOptions o;
  o.sim.air_balance = 0.0;
  o.sim.bending = BendingModel::Isometric;
  o.sim.pressure = 2.0;
  const RunResult paper = run_contraction(test::load_target_mesh("hand"), o);
  ASSERT_EQ(paper.status, RunStatus::Completed) << paper.message;
  EXPECT_LT(paper.final_volume_ratio, 0.4);
}

TEST(LocalContraction, RegionsSinkMoreAsTheShrinkGrows) {
  // Monotone in the strength, and nothing at strength 0 (no pressure either: the shell is at
  // rest with the rest-aware bending).
  double previous = -1.0;
  for (double s : {0.0, 0.3, 0.6, 1.0}) {
    const RunResult r = test::bumpy_sphere_contraction(s);
    ASSERT_EQ(r.status, RunStatus::Completed) << r.message;
    EXPECT_EQ(r.regions, 3u);
    EXPECT_EQ(r.new_intersections, 0) << "shrink " << s;
    if (s == 0.0) {
      EXPECT_LE(std::abs(r.region_inward_displacement), 1e-9);
    } else {
      EXPECT_GT(r.region_inward_displacement, previous) << "shrink " << s;
    }
    previous = r.region_inward_displacement;
    std::cout << "bumpy_sphere shrink " << s << ": region sink " << r.region_inward_displacement
              << ", rest moved " << r.outside_region_displacement << " (normalized), V/V0 "
              << r.final_volume_ratio << "\n";
  }
}

}  // namespace
}  // namespace shellcontract
