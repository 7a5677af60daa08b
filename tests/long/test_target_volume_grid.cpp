// The target-volume grid in full: eight, hand, elk, bear, the kitten, bumpy_sphere and
// torus, each at R in {0.9, 0.7, 0.5, 0.3}, 400 frames; CGAL validation at the end, and at every
// frame for the paper meshes at R = 0.5. Label "long" (ctest -L long).
#include "support/target_volume_case.hpp"

namespace shellcontract {
namespace {

struct Case {
  std::string mesh;
  double target;
};

class TargetVolumeGrid : public ::testing::TestWithParam<Case> {};

TEST_P(TargetVolumeGrid, ReachesAndHoldsTheTarget) {
  const Case& c = GetParam();
  const bool paper = c.mesh == "eight" || c.mesh == "hand" || c.mesh == "elk" || c.mesh == "bear";
  test::check_target_volume(c.mesh, c.target, paper && c.target == 0.5);
}

std::vector<Case> grid() {
  std::vector<Case> cases;
  for (const char* mesh : {"eight", "hand", "elk", "bear", "kitten", "bumpy_sphere", "torus"})
    for (double r : {0.9, 0.7, 0.5, 0.3}) cases.push_back({mesh, r});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(AllMeshes, TargetVolumeGrid, ::testing::ValuesIn(grid()),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return info.param.mesh + "_" +
                                  std::to_string(static_cast<int>(info.param.target * 10));
                         });

}  // namespace
}  // namespace shellcontract
