// The Grid method's vector cell loops (grid_avx512.cpp, grid_avx2.cpp) against its portable
// loop: the same pairs, in the same order, with the same close flags, so every result downstream
// keeps its bits on any CPU.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "collision/broad_phase.hpp"
#include "collision/broad_phase/grid.hpp"
#include "collision/broad_phase/scratch.hpp"
#include "collision/broad_phase_oracle.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

using namespace test;

/// The cell loop that `isa` selects must emit exactly the portable loop's pairs, in its order,
/// with its close flags: random motions from none (every box touching its neighbours) to large,
/// cells of every size (so every tail of the 8-lane loops), inflation 0 (boxes that only touch),
/// and far distances from 0 (every gap counts) to none.
void expect_loop_equals_portable(detail::GridIsa isa) {
  std::mt19937 rng(23);
  const TriMesh sphere = test::icosphere(3);
  const TriMesh two = combine(test::icosphere(2), test::icosphere(2));
  std::int64_t compared = 0, far_flags = 0, close_flags = 0;
  int grid_runs = 0;
  // One object whose loop alternates call by call: each loop must size its own cell buffers,
  // whatever the other left behind in the shared scratch.
  CandidatePairs switching;
  switching.scratch->grid_patch = false;  // a fresh grid each call, as `portable`'s
  for (const TriMesh* m : {&sphere, &two}) {
    const CollisionTopology topo = make_collision_topology(m->faces, static_cast<int>(m->x.rows()));
    for (double scale : {0.0, 0.01, 0.05, 0.12}) {
      Positions x0 = m->x;
      if (m == &two) x0.bottomRows(m->x.rows() / 2).rowwise() += Vec3(1.5, 0.2, 0.1).transpose();
      x0 = random_motion(x0, 0.5 * scale, rng);
      const Positions x1 = random_motion(x0, scale, rng);
      for (double inflation : {0.0, 0.01, 0.05})
        for (double far : {-1.0, 0.0, 0.005, 0.02}) {
          CandidatePairs fast, portable;
          BroadPhaseStats fast_stats, portable_stats;
          fast.scratch->grid_isa = isa;
          portable.scratch->grid_isa = detail::GridIsa::Portable;
          find_candidates(x0, x1, topo, inflation, fast, &fast_stats, BroadPhaseMethod::Grid, far);
          find_candidates(x0, x1, topo, inflation, portable, &portable_stats,
                          BroadPhaseMethod::Grid, far);
          const std::string where = "scale " + std::to_string(scale) + ", inflation " +
                                    std::to_string(inflation) + ", far " + std::to_string(far);
          // Large motions with a large inflation make the grid fall back to PrimitiveBoxes
          // (both calls alike); only the grid's own runs compare the two loops.
          ASSERT_EQ(fast_stats.method_run, portable_stats.method_run) << where;
          if (fast_stats.method_run != BroadPhaseMethod::Grid) continue;
          ++grid_runs;
          EXPECT_TRUE(fast.vertex_face == portable.vertex_face) << where;
          EXPECT_TRUE(fast.edge_edge == portable.edge_edge) << where;
          EXPECT_TRUE(fast.vertex_face_close == portable.vertex_face_close) << where;
          EXPECT_TRUE(fast.edge_edge_close == portable.edge_edge_close) << where;
          switching.scratch->grid_isa =
              grid_runs % 2 ? detail::GridIsa::Portable : isa;
          find_candidates(x0, x1, topo, inflation, switching, nullptr, BroadPhaseMethod::Grid, far);
          EXPECT_TRUE(switching.vertex_face == portable.vertex_face) << where;
          EXPECT_TRUE(switching.edge_edge_close == portable.edge_edge_close) << where;
          // Exact overlaps (the AVX-512 double loop) or overlaps of floats rounded to nearest
          // (the float loops), never more than the portable loop's, rounded outward.
          EXPECT_LE(fast_stats.box_overlaps, portable_stats.box_overlaps) << where;
          compared += static_cast<std::int64_t>(fast.vertex_face.size() + fast.edge_edge.size());
          for (const auto* flags : {&fast.vertex_face_close, &fast.edge_edge_close})
            for (std::uint8_t f : *flags) ++(f ? close_flags : far_flags);
        }
    }
  }
  // The comparisons were not vacuous: most scenes ran the grid, many pairs, both flag values.
  EXPECT_GE(grid_runs, 80);
  EXPECT_GT(compared, 100000);
  EXPECT_GT(far_flags, 1000);
  EXPECT_GT(close_flags, 1000);
}


TEST(BroadPhase, GridAvx512LoopEqualsThePortableLoop) {
  if (!detail::grid_avx512_available()) GTEST_SKIP() << "no AVX-512 on this CPU";
  expect_loop_equals_portable(detail::GridIsa::Auto);
}

TEST(BroadPhase, GridAvx2LoopEqualsThePortableLoop) {
  // Checked to fail with the adjacency test left out of grid_avx2.cpp's rows, and with the
  // lanes past a row's end left live.
  if (!detail::grid_avx2_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  expect_loop_equals_portable(detail::GridIsa::Avx2);
}

}  // namespace
}  // namespace shellcontract
