// The order of find_candidates' pairs: the collision step's result depends on it, so it must come
// from the pairs alone, not from the grid a CandidatePairs keeps from its earlier calls (a run
// resumed from a checkpoint starts with a fresh one).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>

#include "collision/broad_phase.hpp"
#include "collision/broad_phase/scratch.hpp"
#include "collision/broad_phase_oracle.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

using namespace test;  // random_motion (broad_phase_oracle.hpp) and the mesh fixtures

TEST(BroadPhase, GridPairsDoNotDependOnTheGridKeptFromEarlierCalls) {
  // A call may keep the last call's grid (its origin and cell size) and emit its pairs in that
  // grid's cell order; a run resumed from a checkpoint starts with a fresh CandidatePairs. The
  // collision step's result depends on the pairs' order, so find_candidates must give the same
  // pairs in the same order, with the same flags, whatever grid it kept. Fails without the sort
  // at the end of find_candidates (checked: the kept grid's origin differs from a fresh one's and
  // the cell orders differ).
  std::mt19937 rng(5);
  const TriMesh m = test::icosphere(4);
  const CollisionTopology topo = make_collision_topology(m.faces, static_cast<int>(m.x.rows()));
  const Positions x0 = random_motion(m.x, 0.004, rng);
  const Positions x1 = random_motion(x0, 0.004, rng);
  const double inflation = 0.01, far = 0.005;
  CandidatePairs fresh, kept;
  // An earlier call on the scene shifted by a fraction of a cell: its grid still fits the
  // scene and is kept, with another origin than a fresh grid's.
  Positions s0 = x0, s1 = x1;
  s0.col(0).array() -= 0.01;
  s1.col(0).array() -= 0.01;
  find_candidates(s0, s1, topo, inflation, kept, nullptr, BroadPhaseMethod::Grid, far);
  const std::array<double, 3> earlier_origin = kept.scratch->grid_origin;
  find_candidates(x0, x1, topo, inflation, kept, nullptr, BroadPhaseMethod::Grid, far);
  find_candidates(x0, x1, topo, inflation, fresh, nullptr, BroadPhaseMethod::Grid, far);
  ASSERT_EQ(kept.scratch->grid_origin, earlier_origin);  // the kept grid was reused
  ASSERT_NE(kept.scratch->grid_origin, fresh.scratch->grid_origin);
  ASSERT_GT(fresh.vertex_face.size(), 100u);
  EXPECT_TRUE(kept.vertex_face == fresh.vertex_face);
  EXPECT_TRUE(kept.edge_edge == fresh.edge_edge);
  EXPECT_TRUE(kept.vertex_face_close == fresh.vertex_face_close);
  EXPECT_TRUE(kept.edge_edge_close == fresh.edge_edge_close);
  EXPECT_TRUE(std::is_sorted(fresh.vertex_face.begin(), fresh.vertex_face.end()));
  EXPECT_TRUE(std::is_sorted(fresh.edge_edge.begin(), fresh.edge_edge.end()));
}

}  // namespace
}  // namespace shellcontract
