// The Grid method's cell size (src/collision/broad_phase/grid.cpp): where the boxes are long
// against the spacing of the surface, the cells of GRID_CELL_FACTOR median extents hold so many
// boxes (GRID_CROWDED_WORK_PER_BOX) that it must take smaller cells, keep them for the next
// calls, and still report exactly brute force's pairs; it gives up only when even those exceed
// GRID_WORK_PER_BOX.
#include <gtest/gtest.h>

#include <string>

#include "collision/broad_phase.hpp"
#include "collision/broad_phase/grid.hpp"
#include "collision/broad_phase/scratch.hpp"
#include "collision/broad_phase_oracle.hpp"

namespace shellcontract {
namespace {

using namespace test;

/// An n x n grid of vertices at unit spacing in the plane z = 0, two triangles per square.
TriMesh flat_sheet(int n) {
  TriMesh m;
  m.x.resize(n * n, 3);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) m.x.row(j * n + i) << i, j, 0.0;
  m.faces.resize(2 * (n - 1) * (n - 1), 3);
  int f = 0;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      m.faces.row(f++) << a, b, d;
      m.faces.row(f++) << a, d, c;
    }
  return m;
}

/// The sheet's start positions and its end positions moved by `shift` along x: every vertex box
/// is `shift` long, every face box and most edge boxes 1 + shift (their largest side).
struct MovedSheet {
  TriMesh mesh = flat_sheet(40);
  CollisionTopology topo = make_collision_topology(mesh.faces, static_cast<int>(mesh.x.rows()));
  Positions x1;
  explicit MovedSheet(double shift) : x1(mesh.x) { x1.col(0).array() += shift; }
};

double cell_size(const CandidatePairs& out) { return 1.0 / out.scratch->grid_inv_h; }

/// One call of the Grid method on the sheet's step; its statistics.
BroadPhaseStats grid_call(const MovedSheet& s, double inflation, CandidatePairs& out) {
  BroadPhaseStats stats;
  find_candidates(s.mesh.x, s.x1, s.topo, inflation, out, &stats, BroadPhaseMethod::Grid);
  return stats;
}

void expect_brute_force(const MovedSheet& s, double inflation, const CandidatePairs& out,
                        const std::string& where) {
  const BruteForce want = brute_force(s.mesh.x, s.x1, s.mesh.faces, inflation);
  const Pairs vf = sorted(out.vertex_face), ee = sorted(out.edge_edge);
  EXPECT_TRUE(vf == want.vertex_face) << where << ": VF " << first_difference(vf, want.vertex_face);
  EXPECT_TRUE(ee == want.edge_edge) << where << ": EE " << first_difference(ee, want.edge_edge);
}

/// One Grid call that must keep the grid, with cells of `factor` median extents, and report
/// brute force's pairs.
void expect_grid_cells(const MovedSheet& s, double inflation, double factor, double median,
                       CandidatePairs& out, const std::string& where) {
  ASSERT_EQ(grid_call(s, inflation, out).method_run, BroadPhaseMethod::Grid) << where;
  EXPECT_NEAR(cell_size(out), factor * median, 1e-9 * median) << where;
  expect_brute_force(s, inflation, out, where);
}

TEST(BroadPhaseGridCells, UncrowdedBoxesGetTheLargeCells) {
  // Shifted by 1: the median extent is 2 + 2 inflation, and the cells hold few enough boxes.
  const double inflation = 0.01, median = 2.0 + 2.0 * inflation;
  const MovedSheet s(1.0);
  CandidatePairs out;
  expect_grid_cells(s, inflation, detail::GRID_CELL_FACTOR, median, out, "shift 1");
  EXPECT_EQ(out.scratch->grid_small_skips, 0);
}

TEST(BroadPhaseGridCells, CrowdedCellsAreHalvedBeforeTheGridGivesUp) {
  // Shifted by 2 (found by trying: from 1.5 to 2.5 the large cells exceed
  // GRID_CROWDED_WORK_PER_BOX and the small ones do not; from 2.75 both do): the median extent is
  // 3 + 2 inflation.
  const double inflation = 0.01, median = 3.0 + 2.0 * inflation;
  const MovedSheet s(2.0);
  CandidatePairs out;
  auto call = [&](const std::string& where) {
    expect_grid_cells(s, inflation, detail::GRID_SMALL_CELL_FACTOR, median, out, where);
  };
  // The first call tries the large cells, then takes the small ones; the next call starts with
  // them; the one after tries the large ones again and backs off for two calls.
  call("first call");
  EXPECT_EQ(out.scratch->grid_small_skips, 1);
  call("second call");
  EXPECT_EQ(out.scratch->grid_small_skips, 0);
  EXPECT_EQ(out.scratch->grid_small_backoff, 1);
  call("third call");
  EXPECT_EQ(out.scratch->grid_small_skips, 2);
  EXPECT_EQ(out.scratch->grid_small_backoff, 2);
}

TEST(BroadPhaseGridCells, SmallCellsAboveTheCrowdedWorkKeepTheGrid) {
  // Shifted by 4 (found by trying: from 2.75 to 7 the small cells hold 268 to 988 entry pairs per
  // box, above GRID_CROWDED_WORK_PER_BOX and below GRID_WORK_PER_BOX): the grid goes on with them,
  // where a limit at the crowded work gave up.
  const double inflation = 0.01, median = 5.0 + 2.0 * inflation;
  const MovedSheet s(4.0);
  CandidatePairs out;
  expect_grid_cells(s, inflation, detail::GRID_SMALL_CELL_FACTOR, median, out, "shift 4");
}

TEST(BroadPhaseGridCells, BoxesTooCrowdedForEitherCellSizeGoToPrimitiveBoxes) {
  // Shifted by 10 (from 8 on, even the small cells exceed GRID_WORK_PER_BOX); the pairs are still
  // exact.
  const double inflation = 0.01;
  const MovedSheet s(10.0);
  CandidatePairs out;
  EXPECT_EQ(grid_call(s, inflation, out).method_run, BroadPhaseMethod::PrimitiveBoxes);
  expect_brute_force(s, inflation, out, "shift 10");
}

}  // namespace
}  // namespace shellcontract
