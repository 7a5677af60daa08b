// Issue "Control", item 3: the default run ends icospheres of 320 to 20,480 faces within 0.02 of
// each other after 200 frames (bear and bear split in four: tests/long/test_defaults_long.cpp);
// `--solver pbd` does not (0.99 to 0.51). Also the soft-membrane XPBD setting of
// docs/design/defaults.md ("Resolution"), `--solver xpbd --mu 0.2 --lambda 0.2`. Label long.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

#include "shellcontract/options.hpp"
#include "support/default_run_case.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

/// Records the largest one-step displacement of a run.
class LargestStep final : public RunObserver {
 public:
  void frame(const FrameView&, const FrameMetrics& m) override { largest = std::max(largest, m.max_displacement); }
  double largest = 0.0;
};

RunOptions soft_xpbd() {
  RunOptions o;
  set_run_option(o, "solver", "xpbd");
  set_run_option(o, "mu", "0.2");
  set_run_option(o, "lambda", "0.2");
  o.sim.validate = ValidateMode::End;
  return o;
}

RunResult soft_xpbd_run(const Mesh& mesh, LargestStep* steps = nullptr) {
  return run_contraction(mesh, soft_xpbd(), steps);
}

TEST(ResolutionLong, DefaultRunIcospheresEndAlike) {
  RunOptions o;
  o.sim.validate = ValidateMode::End;
  test::check_icospheres_end_alike(o, 5, "default");
}

TEST(ResolutionLong, SoftXpbdIcospheresEndAlike) {
  test::check_icospheres_end_alike(soft_xpbd(), 5, "soft xpbd");
}

/// Also the regression of the XPBD dihedral hinge's step clamp: without it this bear run blew up
/// at frame 82 (one step moved a vertex 0.41 of the diagonal; 40 frames of fail-safe reverts).
TEST(ResolutionLong, SoftXpbdBearAndBearSplitInFourEndAlikeWithBoundedSteps) {
  const std::string path = test::target_mesh_path("bear");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
  const Mesh bear = test::load_target_mesh("bear");
  LargestStep coarse_steps, split_steps;
  const RunResult coarse = soft_xpbd_run(bear, &coarse_steps);
  const RunResult split = soft_xpbd_run(test::split_in_four(bear), &split_steps);
  ASSERT_EQ(coarse.status, RunStatus::Completed) << coarse.message;
  ASSERT_EQ(split.status, RunStatus::Completed) << split.message;
  EXPECT_EQ(coarse.new_intersections, 0);
  EXPECT_EQ(split.new_intersections, 0);
  EXPECT_LE(std::abs(coarse.final_volume_ratio - split.final_volume_ratio), 0.03);
  EXPECT_LT(coarse.final_volume_ratio, 0.8);
  EXPECT_LT(coarse_steps.largest, 0.02);
  EXPECT_LT(split_steps.largest, 0.02);
  std::cout << "soft xpbd bear " << coarse.final_volume_ratio << " (largest step "
            << coarse_steps.largest << "), bear x4 " << split.final_volume_ratio
            << " (largest step " << split_steps.largest << ")\n";
}

}  // namespace
}  // namespace shellcontract
