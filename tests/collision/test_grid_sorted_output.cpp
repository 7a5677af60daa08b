// The Grid method's sorted output (grid_pairs' counting sort by first id, then each id's pairs
// sorted among themselves): exactly brute force's pairs, in brute force's (sorted) order, on
// degenerate inputs and on a scene where one primitive has many partners (the per-id sort's
// comparison-sort branch). broad_phase_oracle.hpp's comparison requires the order of every
// method, Grid included. Checked to fail: with the per-id sort removed from sort_chunk_keys,
// the oracle reports "not sorted" for Grid here and in test_broad_phase.cpp; with only its
// comparison-sort branch (ids with more than 32 pairs) skipped, OnePrimitiveWithManyPartners
// fails.
#include <gtest/gtest.h>

#include "broad_phase_oracle.hpp"

namespace shellcontract {
namespace {

using test::BruteForce;
using test::expect_all_methods_match;
using test::TriMesh;

/// An n by n sheet of squares in the plane z = 0 (two triangles each), corners (0,0)-(1,1),
/// its vertices numbered from `first`.
TriMesh sheet(int n, int first = 0) {
  TriMesh m;
  m.x.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.x.row(j * (n + 1) + i) << double(i) / n, double(j) / n, 0.0;
  m.faces.resize(2 * n * n, 3);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = first + j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      m.faces.row(2 * (j * n + i)) << a, b, d;
      m.faces.row(2 * (j * n + i) + 1) << a, d, c;
    }
  return m;
}

/// Runs the oracle comparison and checks that Grid ran its own algorithm (not the fallback).
BruteForce expect_grid_matches(const Positions& x0, const Positions& x1, const Faces& faces,
                               double inflation, const std::string& label) {
  const int runs = test::g_grid_runs;
  const BruteForce bf = expect_all_methods_match(x0, x1, faces, inflation, label);
  EXPECT_EQ(test::g_grid_runs, runs + 1) << label << ": Grid fell back";
  return bf;
}

TEST(GridSortedOutput, CoplanarSheetAtRestAndMovingInItsPlane) {
  const TriMesh m = sheet(12);
  // At rest, touching boxes only (inflation 0), and with a small inflation.
  for (double inflation : {0.0, 0.01}) {
    const BruteForce bf = expect_grid_matches(m.x, m.x, m.faces, inflation,
                                              "coplanar sheet at rest, inflation " +
                                                  std::to_string(inflation));
    EXPECT_FALSE(bf.edge_edge.empty());
  }
  // Moving in its own plane (every box flat in z).
  Positions x1 = m.x;
  std::mt19937 rng(7);
  for (Eigen::Index v = 0; v < x1.rows(); ++v) {
    x1(v, 0) += std::uniform_real_distribution<double>(-0.05, 0.05)(rng);
    x1(v, 1) += std::uniform_real_distribution<double>(-0.05, 0.05)(rng);
  }
  const BruteForce bf = expect_grid_matches(m.x, x1, m.faces, 0.0, "coplanar sheet, in-plane");
  EXPECT_FALSE(bf.vertex_face.empty());
}

TEST(GridSortedOutput, SingleFaceAndItsOrphanVertices) {
  // One face: no pair at all (its vertices are its corners, its edges share vertices).
  TriMesh one;
  one.x.resize(3, 3);
  one.x << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  one.faces.resize(1, 3);
  one.faces << 0, 1, 2;
  // (Not through the oracle's comparison, which expects FacePairs to find a face pair.)
  const BruteForce none = test::brute_force(one.x, one.x, one.faces, 0.1);
  EXPECT_TRUE(none.vertex_face.empty() && none.edge_edge.empty());
  const CollisionTopology topo = make_collision_topology(one.faces, 3);
  CandidatePairs got;
  BroadPhaseStats stats;
  find_candidates(one.x, one.x, topo, 0.1, got, &stats, BroadPhaseMethod::Grid, 0.05);
  EXPECT_TRUE(got.vertex_face.empty() && got.edge_edge.empty());
  EXPECT_EQ(stats.method_run, BroadPhaseMethod::Grid);
  // The same face with two vertices no face holds, one above it, one at a corner (coincident).
  Positions x(5, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, 0.05, 0, 0, 0;
  const BruteForce bf = expect_all_methods_match(x, x, one.faces, 0.0, "face and orphans");
  EXPECT_EQ(bf.vertex_face.size(), 1u);  // the coincident orphan touches; the other is above
  expect_all_methods_match(x, x, one.faces, 0.1, "face and orphans, inflated");
}

TEST(GridSortedOutput, CoincidentVerticesOfTwoCopies) {
  // Two copies of a sphere at the same coordinates: every vertex coincides with one of the
  // other copy, so every primitive meets its twin and the twin's neighbours.
  const TriMesh s = test::icosphere(2);
  const TriMesh both = test::combine(s, s);
  const BruteForce bf =
      expect_grid_matches(both.x, both.x, both.faces, 0.0, "two coincident spheres at rest");
  EXPECT_GT(bf.vertex_face.size(), static_cast<std::size_t>(s.x.rows()));
  std::mt19937 rng(3);
  expect_grid_matches(both.x, test::random_motion(both.x, 0.01, rng), both.faces, 1e-3,
                      "two coincident spheres, moving");
}

TEST(GridSortedOutput, OnePrimitiveWithManyPartners) {
  // A triangle (vertices 0-2, so its vertex and edges come first in their pairs) whose vertex 0
  // sweeps across a 24 by 24 sheet in its plane: vertex 0 meets a long row of faces, edges 0 and
  // 1 a long row of edges, far more than the per-id insertion sort takes.
  const TriMesh s = sheet(24, 3);
  TriMesh m;
  m.x.resize(3 + s.x.rows(), 3);
  m.x.topRows(3) << 0.02, 0.51, 0.0, 0.0, 0.53, 0.0, 0.0, 0.49, 0.0;
  m.x.bottomRows(s.x.rows()) = s.x;
  m.faces.resize(1 + s.faces.rows(), 3);
  m.faces.row(0) << 0, 1, 2;
  m.faces.bottomRows(s.faces.rows()) = s.faces;
  Positions x1 = m.x;
  x1(0, 0) = 0.98;
  const BruteForce bf = expect_grid_matches(m.x, x1, m.faces, 1e-3, "a vertex across a sheet");
  const auto count_first = [](const test::Pairs& p, int id) {
    return std::count_if(p.begin(), p.end(), [&](const std::array<int, 2>& q) { return q[0] == id; });
  };
  EXPECT_GT(count_first(bf.vertex_face, 0), 40);
  EXPECT_GT(count_first(bf.edge_edge, 0), 40);
}

}  // namespace
}  // namespace shellcontract
