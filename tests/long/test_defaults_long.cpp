// Issue "Control", items 3 and 5, on the meshes too slow for the default suite (label long).
#include <gtest/gtest.h>

#include <iostream>

#include "support/default_run_case.hpp"

namespace shellcontract {
namespace {

// README, "How much it contracts": 0.51 (kitten); eight, hand, elk and bear are in the default
// suite (tests/scenario/test_defaults.cpp).
TEST(DefaultsLong, KittenEndsAtTheReadmesRatio) { test::check_default_run_ratio("kitten", 0.51); }

/// CGAL demo meshes that grew under the paper's flat-rest bending (dragknob V/V0 1.275, spool
/// 1.126 after 200 frames at P = 2): a compressing default must not grow them.
TEST(DefaultsLong, CurvedDemoMeshesDoNotGrow) {
  for (const char* name : {"dragknob", "spool"}) {
    const std::string path = test::demo_mesh_path(name);
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
    const RunResult r = test::default_run(read_input_mesh(path));
    ASSERT_EQ(r.status, RunStatus::Completed) << name << ": " << r.message;
    EXPECT_LT(r.final_volume_ratio, 1.0) << name;
    EXPECT_EQ(r.new_intersections, 0) << name;
    std::cout << "default run " << name << ": V/V0 " << r.final_volume_ratio << "\n";
  }
}

/// Item 3 on bear: the same default setting on bear and on bear with every triangle split in
/// four at its edge midpoints (110,592 faces) ends within 0.03 in V/V0.
TEST(DefaultsLong, BearAndBearSplitInFourEndAlike) {
  const std::string path = test::target_mesh_path("bear");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
  const Mesh bear = test::load_target_mesh("bear");
  const Mesh fine = test::split_in_four(bear);
  ASSERT_EQ(fine.number_of_faces(), 4 * bear.number_of_faces());
  const RunResult coarse = test::default_run(bear);
  const RunResult split = test::default_run(fine);
  ASSERT_EQ(coarse.status, RunStatus::Completed) << coarse.message;
  ASSERT_EQ(split.status, RunStatus::Completed) << split.message;
  EXPECT_LE(std::abs(coarse.final_volume_ratio - split.final_volume_ratio), 0.03);
  std::cout << "default run bear " << coarse.final_volume_ratio << ", bear x4 "
            << split.final_volume_ratio << "\n";
}

}  // namespace
}  // namespace shellcontract
