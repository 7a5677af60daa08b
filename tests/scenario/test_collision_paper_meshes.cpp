// Issue "self-collision", acceptance: the paper's meshes and the two-sheet mesh contracted with
// strong pressure for 300 frames with collisions on. CGAL finds no new self-intersection at any
// frame, and the shell still contracts (V/V0 <= 0.7 at frame 300). Label "scenario" (~80 s).
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <string>

#include "shellcontract/mesh/io.hpp"
#include "shellcontract/sim/simulator.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

/// The strong pressure of this scenario (normalized units; the default is 2).
constexpr double STRONG_PRESSURE = 4.0;

std::string path_of(const std::string& name) {
  return name == "two_sheet" ? std::string(test::MESH_DIR) + "/two_sheet.off"
                             : std::string(test::PAPER_MESH_DIR) + "/" + name + ".off";
}

class StrongPressure : public ::testing::TestWithParam<std::string> {};

TEST_P(StrongPressure, NoNewSelfIntersectionAtAnyFrameAndStillContracts) {
  const std::string path = path_of(GetParam());
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << path << " is absent: run scripts/fetch_paper_meshes.sh";
  const Mesh mesh = read_input_mesh(path);
  SimOptions opt;
  opt.pressure = STRONG_PRESSURE;
  opt.frames = 300;
  opt.collisions = true;
  Simulator sim(mesh, opt);
  double collision_s = 0, solve_s = 0;
  long failsafe = 0;
  while (!sim.finished()) {
    const FrameMetrics m = sim.step();
    collision_s += m.collision.seconds;
    solve_s += m.solve_seconds;
    failsafe += m.collision.failsafe_vertices;
    ASSERT_EQ(sim.count_new_intersections(), 0u) << GetParam() << " frame " << m.frame;
  }
  EXPECT_LE(sim.volume_ratio(), 0.7) << GetParam();
  std::cout << GetParam() << ": V/V0 at frame 300 " << sim.volume_ratio() << "; collision / solve time per step "
            << 1e3 * collision_s / 300 << " / " << 1e3 * solve_s / 300 << " ms; fail-safe vertices "
            << failsafe << "\n";
}

INSTANTIATE_TEST_SUITE_P(Long, StrongPressure,
                         ::testing::Values("eight", "hand", "elk", "bear", "two_sheet"),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace shellcontract
