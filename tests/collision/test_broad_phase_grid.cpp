// The CCD broad phase's contract beyond brute-force equality (test_broad_phase.cpp has that):
// inflation, reused output, the Grid's order for any thread count, its patching across steps, its
// float loop, and the refusal of mismatched input (test_grid_simd_loops.cpp: the AVX-512 and AVX2
// cell loops against the portable one).
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/broad_phase/grid.hpp"
#include "collision/broad_phase/scratch.hpp"
#include "collision/broad_phase_oracle.hpp"
#include "shellcontract/error.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

using namespace test;  // the oracle (broad_phase_oracle.hpp) and the mesh fixtures

// ------------------------------------------------------------------ contract checks

TEST(BroadPhase, InflationIsAddedOnEverySide) {
  // Triangle 0 in z = 0; triangle 1 lies in z = h above it, shifted so that only the z gap
  // separates the boxes. Each box grows by `inflation`, so the pair appears iff h <= 2 inflation.
  Positions x(6, 3);
  Faces f(2, 3);
  f << 0, 1, 2, 3, 4, 5;
  const double inflation = 0.01;
  for (double h : {0.5 * inflation, 1.9 * inflation, 2.1 * inflation}) {
    x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, h, 0.3, 0.2, h, 0.2, 0.3, h;
    const CollisionTopology topo = make_collision_topology(f, 6);
    for (BroadPhaseMethod m : METHODS) {
      CandidatePairs out;
      find_candidates(x, x, topo, inflation, out, nullptr, m);
      const bool hit = std::find(out.vertex_face.begin(), out.vertex_face.end(),
                                 std::array<int, 2>{3, 0}) != out.vertex_face.end();
      EXPECT_EQ(hit, h <= 2 * inflation) << "h " << h << ", " << method_name(m);
    }
  }
}

TEST(BroadPhase, ReusedOutputHoldsOnlyTheLatestCall) {
  std::mt19937 rng(3);
  const TriMesh m = test::icosphere(2);
  const CollisionTopology topo = make_collision_topology(m.faces, static_cast<int>(m.x.rows()));
  const Positions big = random_motion(m.x, 1.0, rng);
  const BruteForce want = brute_force(m.x, m.x, m.faces, 0.0);
  for (BroadPhaseMethod method : METHODS) {
    CandidatePairs out;
    find_candidates(m.x, big, topo, 0.0, out, nullptr, method);
    ASSERT_GT(out.vertex_face.size(), want.vertex_face.size());  // the first call is larger
    find_candidates(m.x, m.x, topo, 0.0, out, nullptr, method);
    EXPECT_TRUE(sorted(out.vertex_face) == want.vertex_face) << method_name(method);
    EXPECT_TRUE(sorted(out.edge_edge) == want.edge_edge) << method_name(method);
    EXPECT_EQ(out.vertex_face_close.size(), out.vertex_face.size()) << method_name(method);
    EXPECT_EQ(out.edge_edge_close.size(), out.edge_edge.size()) << method_name(method);
  }
}

TEST(BroadPhase, GridOrderDoesNotDependOnTheThreadCount) {
  // Grid's pairs come in cell order, unsorted; the collision step relies on that order (and the
  // close flags) being the same for any number of threads. The counting sort runs in one part
  // per thread (up to GRID_MAX_PARTS), scattered part by part and merged cell by cell: its cells
  // must list the same boxes in the same order for any number of parts. A mesh with more cells
  // than one block of the per-cell passes (GRID_CELL_GRAIN).
  std::mt19937 rng(11);
  const TriMesh m = test::icosphere(6);
  const CollisionTopology topo = make_collision_topology(m.faces, static_cast<int>(m.x.rows()));
  const Positions x0 = random_motion(m.x, 0.01, rng);
  const Positions x1 = random_motion(x0, 0.004, rng);
  const std::vector<int> threads = {1, 2, 3, 4, 7};
  std::vector<CandidatePairs> runs(threads.size());
  for (std::size_t k = 0; k < threads.size(); ++k) {
    tbb::task_arena arena(threads[k]);
    BroadPhaseStats stats;
    arena.execute([&] {
      find_candidates(x0, x1, topo, 0.002, runs[k], &stats, BroadPhaseMethod::Grid, 0.001);
    });
    ASSERT_EQ(stats.method_run, BroadPhaseMethod::Grid);
  }
  const BroadPhaseScratch& first = *runs[0].scratch;
  ASSERT_GT(first.cell_start.size(), detail::GRID_CELL_GRAIN + 1);
  ASSERT_GT(runs[0].vertex_face.size(), 100u);
  ASSERT_GT(runs[0].edge_edge.size(), 100u);
  const std::size_t n = first.cell_start.back();
  for (std::size_t k = 1; k < threads.size(); ++k) {
    const CandidatePairs& r = runs[k];
    EXPECT_TRUE(r.scratch->cell_start == first.cell_start) << threads[k] << " threads";
    EXPECT_TRUE(std::equal(first.cell_entries.begin(),
                           first.cell_entries.begin() + static_cast<std::ptrdiff_t>(n),
                           r.scratch->cell_entries.begin()))
        << threads[k] << " threads";
    EXPECT_TRUE(r.vertex_face == runs[0].vertex_face) << threads[k] << " threads";
    EXPECT_TRUE(r.edge_edge == runs[0].edge_edge) << threads[k] << " threads";
    EXPECT_TRUE(r.vertex_face_close == runs[0].vertex_face_close) << threads[k] << " threads";
    EXPECT_TRUE(r.edge_edge_close == runs[0].edge_edge_close) << threads[k] << " threads";
  }
}

TEST(BroadPhase, GridKeptAcrossStepsIsPatchedToExactlyTheRebuiltCountingSort) {
  // Step after step the grid keeps its cells and patches its counting sort for the boxes that
  // changed cell range (patch_grid). A patch must leave exactly what the counting sort builds on
  // the same grid: the same cell lists (so the same pairs in the same order, and the same
  // answers from query_kept_grid), on trajectories of small steps (patched), with jumps (too
  // many changes: rebuilt on the kept grid, or a new grid for the new cell size) and a drift.
  std::mt19937 rng(29);
  const TriMesh sphere = test::icosphere(3);
  TriMesh two = combine(test::icosphere(2), test::icosphere(2));
  two.x.bottomRows(two.x.rows() / 2).rowwise() += Vec3(1.2, 0.1, 0.0).transpose();
  int patched_steps = 0, rebuilt_steps = 0;
  for (const TriMesh* m : {&sphere, static_cast<const TriMesh*>(&two)}) {
    const CollisionTopology topo = make_collision_topology(m->faces, static_cast<int>(m->x.rows()));
    CandidatePairs patched, patched_one_thread, rebuilt;
    rebuilt.scratch->grid_patch_always_rebuild = true;
    Positions x0 = m->x;
    std::array<double, 3> last_origin{};
    int new_grids = 0;
    for (int step = 0; step < 40; ++step) {
      // Mostly small steps; a jump every 10th; steps 21-28 also drift by 0.2 along x.
      const double scale = step % 10 == 9 ? 0.1 : 0.004;
      Positions x1 = random_motion(x0, scale, rng);
      const bool drift = step >= 21 && step <= 28;
      if (drift) x1.col(0).array() += 0.2;
      const double inflation = 0.01, far = 0.005;
      BroadPhaseStats stats;
      // Two threads: past GRID_PATCH_MAX_THREADS the kept grid is rebuilt, not patched.
      tbb::task_arena two(2);
      two.execute([&] {
        find_candidates(x0, x1, topo, inflation, patched, &stats, BroadPhaseMethod::Grid, far);
      });
      find_candidates(x0, x1, topo, inflation, rebuilt, nullptr, BroadPhaseMethod::Grid, far);
      tbb::task_arena one(1);
      one.execute([&] {
        find_candidates(x0, x1, topo, inflation, patched_one_thread, nullptr,
                        BroadPhaseMethod::Grid, far);
      });
      const std::string where = "step " + std::to_string(step);
      ASSERT_EQ(stats.method_run, BroadPhaseMethod::Grid) << where;
      const BroadPhaseScratch &p = *patched.scratch, &r = *rebuilt.scratch;
      if (p.grid_patched_boxes > 0) ++patched_steps;
      if (p.grid_patched_boxes < 0 && step > 0) ++rebuilt_steps;
      if (step > 0 && p.grid_origin != last_origin) ++new_grids;
      last_origin = p.grid_origin;
      // The same grid and the same cell lists (the rebuild keeps spare slots past the end).
      ASSERT_EQ(p.grid_dims, r.grid_dims) << where;
      ASSERT_EQ(p.grid_origin, r.grid_origin) << where;
      ASSERT_EQ(p.cell_start, r.cell_start) << where;
      const std::size_t n = p.cell_start.back();
      ASSERT_GE(r.cell_entries.size(), n) << where;
      EXPECT_TRUE(std::equal(p.cell_entries.begin(),
                             p.cell_entries.begin() + static_cast<std::ptrdiff_t>(n),
                             r.cell_entries.begin()))
          << where;
      // Hence the same pairs, order and flags; exactly brute force's pairs; any thread count.
      EXPECT_TRUE(patched.vertex_face == rebuilt.vertex_face) << where;
      EXPECT_TRUE(patched.edge_edge == rebuilt.edge_edge) << where;
      EXPECT_TRUE(patched.vertex_face_close == rebuilt.vertex_face_close) << where;
      EXPECT_TRUE(patched.edge_edge_close == rebuilt.edge_edge_close) << where;
      EXPECT_TRUE(patched_one_thread.vertex_face == patched.vertex_face) << where;
      EXPECT_TRUE(patched_one_thread.edge_edge == patched.edge_edge) << where;
      const BruteForce want = brute_force(x0, x1, m->faces, inflation);
      const Pairs vf = sorted(patched.vertex_face), ee = sorted(patched.edge_edge);
      EXPECT_TRUE(vf == want.vertex_face)
          << where << ": VF " << first_difference(vf, want.vertex_face);
      EXPECT_TRUE(ee == want.edge_edge) << where << ": EE " << first_difference(ee, want.edge_edge);
      x0 = x1;
    }
    // Some calls made a new grid: the jumps' and the drift's larger boxes, then the smaller ones
    // again, ask for other cell sizes.
    EXPECT_GE(new_grids, 2);
  }
  // Both paths ran: patches with changed boxes, and rebuilds after the jumps.
  EXPECT_GE(patched_steps, 40);
  EXPECT_GE(rebuilt_steps, 4);
}

TEST(BroadPhase, GridKeptForAnotherTopologyOfTheSameSizesIsPatchedForIt) {
  // The patch recomputes only the boxes with a vertex whose cell range changed, which holds for
  // the topology of the last call only. The same CandidatePairs given another topology of the
  // same sizes (the labels of an edge's two vertices swapped in the faces: a few faces and edges
  // now span other vertices) and the same vertex boxes must still give brute force's pairs.
  std::mt19937 rng(41);
  const TriMesh m = test::icosphere(2);
  const int a = m.faces(0, 0), b = m.faces(0, 1);
  Faces swapped = m.faces;
  for (Eigen::Index f = 0; f < swapped.rows(); ++f)
    for (Eigen::Index k = 0; k < 3; ++k)
      swapped(f, k) = swapped(f, k) == a ? b : swapped(f, k) == b ? a : swapped(f, k);
  const int nv = static_cast<int>(m.x.rows());
  const CollisionTopology first = make_collision_topology(m.faces, nv);
  const CollisionTopology second = make_collision_topology(swapped, nv);
  ASSERT_EQ(first.edges.rows(), second.edges.rows());
  ASSERT_FALSE(first.faces == second.faces);
  const Positions x0 = random_motion(m.x, 0.01, rng);
  const Positions x1 = random_motion(x0, 1e-3, rng);
  const double inflation = 0.01;
  CandidatePairs out;
  BroadPhaseStats stats;
  tbb::task_arena one(1);  // past GRID_PATCH_MAX_THREADS the kept grid is rebuilt, not patched
  one.execute([&] {
    find_candidates(x0, x1, first, inflation, out, &stats, BroadPhaseMethod::Grid);
    ASSERT_EQ(stats.method_run, BroadPhaseMethod::Grid);
    find_candidates(x0, x1, second, inflation, out, &stats, BroadPhaseMethod::Grid);
  });
  ASSERT_EQ(stats.method_run, BroadPhaseMethod::Grid);
  EXPECT_GT(out.scratch->grid_patched_boxes, 0);  // the kept grid, patched for the new topology
  const BruteForce want = brute_force(x0, x1, swapped, inflation);
  const Pairs vf = sorted(out.vertex_face), ee = sorted(out.edge_edge);
  EXPECT_TRUE(vf == want.vertex_face) << "VF " << first_difference(vf, want.vertex_face);
  EXPECT_TRUE(ee == want.edge_edge) << "EE " << first_difference(ee, want.edge_edge);
}

/// Compares a grid's pairs `got` (a superset) with brute force's `want`: how many pairs of want
/// got misses, how many it adds, and the widest gap (on any axis) between the two boxes of an
/// added pair; prim_box(id) is the box of grid primitive id (vertex v, face V + f, edge V + F + e).
struct SupersetCheck {
  int missing = 0;
  int extra = 0;
  double widest_gap = 0.0;
};
template <class PrimBox>
SupersetCheck check_superset(const CandidatePairs& got, const BruteForce& want, std::size_t nv,
                             std::size_t nf, PrimBox prim_box) {
  SupersetCheck r;
  auto compare = [&](const Pairs& got_pairs, const Pairs& want_pairs, std::size_t first_base,
                     std::size_t second_base) {
    const Pairs g = sorted(got_pairs);
    Pairs missing, extra;
    std::set_difference(want_pairs.begin(), want_pairs.end(), g.begin(), g.end(),
                        std::back_inserter(missing));
    std::set_difference(g.begin(), g.end(), want_pairs.begin(), want_pairs.end(),
                        std::back_inserter(extra));
    r.missing += static_cast<int>(missing.size());
    r.extra += static_cast<int>(extra.size());
    for (const auto& p : extra) {
      const Box a = prim_box(first_base + static_cast<std::size_t>(p[0]));
      const Box b = prim_box(second_base + static_cast<std::size_t>(p[1]));
      for (int d = 0; d < 3; ++d)
        r.widest_gap = std::max({r.widest_gap, b.lo[d] - a.hi[d], a.lo[d] - b.hi[d]});
    }
  };
  compare(got.vertex_face, want.vertex_face, 0, nv);
  compare(got.edge_edge, want.edge_edge, nv + nf, nv + nf);
  return r;
}

TEST(BroadPhase, GridOnGivenVertexBoxesAndItsQueriesMatchBruteForce) {
  // SelfCollision's speculative broad phase: the grid on given vertex boxes must emit the box
  // pairs of find_candidates for the same boxes, and a query of the kept grid must return every
  // primitive whose box meets the query box, once.
  std::mt19937 rng(424242);
  const TriMesh m = test::icosphere(2);
  const CollisionTopology topo = make_collision_topology(m.faces, static_cast<int>(m.x.rows()));
  const std::size_t nv = static_cast<std::size_t>(m.x.rows());
  const std::size_t nf = static_cast<std::size_t>(topo.faces.rows());
  const std::size_t ne = static_cast<std::size_t>(topo.edges.rows());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int queries_with_hits = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const Positions x0 = random_motion(m.x, 0.15, rng);
    const Positions x1 = random_motion(x0, trial < 3 ? 1e-3 : 0.05, rng);
    const double inflation = trial % 2 == 0 ? 0.0 : 0.01;
    std::vector<detail::GridVertexBox> boxes(nv);
    for (std::size_t v = 0; v < nv; ++v)
      for (int d = 0; d < 3; ++d) {
        const Eigen::Index i = static_cast<Eigen::Index>(v);
        boxes[v].lo[static_cast<std::size_t>(d)] = std::min(x0(i, d), x1(i, d)) - inflation;
        boxes[v].hi[static_cast<std::size_t>(d)] = std::max(x0(i, d), x1(i, d)) + inflation;
      }
    // Query boxes around random points, from a point to a tenth of the sphere.
    auto prim_box = [&](std::size_t gid) {
      std::vector<int> verts;
      if (gid < nv) verts = {static_cast<int>(gid)};
      else if (gid < nv + nf)
        verts = {topo.faces(static_cast<Eigen::Index>(gid - nv), 0),
                 topo.faces(static_cast<Eigen::Index>(gid - nv), 1),
                 topo.faces(static_cast<Eigen::Index>(gid - nv), 2)};
      else
        verts = {topo.edges(static_cast<Eigen::Index>(gid - nv - nf), 0),
                 topo.edges(static_cast<Eigen::Index>(gid - nv - nf), 1)};
      Box b;
      for (int d = 0; d < 3; ++d) {
        b.lo[d] = std::numeric_limits<double>::infinity();
        b.hi[d] = -b.lo[d];
        for (int v : verts) {
          b.lo[d] = std::min(b.lo[d], boxes[static_cast<std::size_t>(v)].lo[static_cast<std::size_t>(d)]);
          b.hi[d] = std::max(b.hi[d], boxes[static_cast<std::size_t>(v)].hi[static_cast<std::size_t>(d)]);
        }
      }
      return b;
    };
    // The exact cell loop: brute force's pairs. The float one (the default): those, and pairs
    // whose boxes are apart by at most float rounding (coordinates within 2 of the scene's
    // minimum here, so a float's spacing is at most 2 FLT_EPSILON).
    CandidatePairs given, exact;
    exact.scratch->grid_float_superset = false;
    ASSERT_TRUE(find_candidates_in_vertex_boxes(boxes, topo, given));
    ASSERT_TRUE(find_candidates_in_vertex_boxes(boxes, topo, exact));
    const BruteForce bf = brute_force(x0, x1, m.faces, inflation);
    EXPECT_EQ(sorted(exact.vertex_face), bf.vertex_face) << "trial " << trial;
    EXPECT_EQ(sorted(exact.edge_edge), bf.edge_edge) << "trial " << trial;
    const SupersetCheck check = check_superset(given, bf, nv, nf, prim_box);
    EXPECT_EQ(check.missing, 0) << "trial " << trial;
    EXPECT_LE(check.widest_gap, 4.0 * FLT_EPSILON) << "trial " << trial;
    for (int q = 0; q < 40; ++q) {
      detail::GridVertexBox query;
      Box qb;
      const double size = q % 4 == 0 ? 0.0 : 0.2 * unit(rng);
      for (std::size_t d = 0; d < 3; ++d) {
        // Some query boxes reach outside the grid (the scene bounds).
        const double c = 2.6 * unit(rng) - 1.3;
        query.lo[d] = qb.lo[d] = c - size;
        query.hi[d] = qb.hi[d] = c + size;
      }
      std::vector<std::uint32_t> hits;
      query_kept_grid(given, topo, query, hits);
      std::vector<std::uint32_t> expected;
      for (std::size_t g = 0; g < nv + nf + ne; ++g)
        if (boxes_overlap(qb, prim_box(g))) expected.push_back(static_cast<std::uint32_t>(g));
      std::sort(hits.begin(), hits.end());
      EXPECT_EQ(hits, expected) << "trial " << trial << ", query " << q;
      queries_with_hits += !expected.empty();
      // An id range: the vertices, the faces, the edges, and one that cuts through the faces
      // and edges (each cell's run of entries must be found, not assumed to start at a kind).
      const std::uint32_t total = static_cast<std::uint32_t>(nv + nf + ne);
      const std::uint32_t cut = static_cast<std::uint32_t>(nv + nf / 2);
      const std::array<std::array<std::uint32_t, 2>, 4> ranges = {
          {{0, static_cast<std::uint32_t>(nv)},
           {static_cast<std::uint32_t>(nv), static_cast<std::uint32_t>(nv + nf)},
           {static_cast<std::uint32_t>(nv + nf), total},
           {cut, cut + static_cast<std::uint32_t>(nf)}}};
      for (const auto& range : ranges) {
        std::vector<std::uint32_t> ranged, expected_ranged;
        query_kept_grid(given, topo, query, ranged, range[0], range[1]);
        for (const std::uint32_t g : expected)
          if (g >= range[0] && g < range[1]) expected_ranged.push_back(g);
        std::sort(ranged.begin(), ranged.end());
        EXPECT_EQ(ranged, expected_ranged)
            << "trial " << trial << ", query " << q << ", ids [" << range[0] << ", " << range[1]
            << ")";
      }
    }
  }
  EXPECT_GT(queries_with_hits, 40);
  // A CandidatePairs that holds no grid refuses queries.
  CandidatePairs none;
  std::vector<std::uint32_t> hits;
  EXPECT_THROW(query_kept_grid(none, topo, detail::GridVertexBox{}, hits), UsageError);
  EXPECT_THROW(find_candidates_in_vertex_boxes({}, topo, none), UsageError);
}

TEST(BroadPhase, GridFloatSupersetAddsOnlyPairsApartByRounding) {
  // Two spheres whose boxes are 1e-13 apart on x where they face each other (inflation 0, no
  // motion: point boxes for vertices): too close for floats to separate. The exact cell loop
  // must not report those pairs; the float loop (AVX-512 only) must keep every exact pair, and
  // may add only pairs apart by rounding, which this scene has by construction.
  const TriMesh one = test::icosphere(2);
  TriMesh two = combine(one, one);
  const Eigen::Index half = one.x.rows();
  const double x_max = one.x.col(0).maxCoeff(), x_min = one.x.col(0).minCoeff();
  two.x.bottomRows(half).col(0).array() += x_max - x_min + 1e-13;
  const CollisionTopology topo = make_collision_topology(two.faces, static_cast<int>(two.x.rows()));
  const std::size_t nv = static_cast<std::size_t>(two.x.rows());
  std::vector<detail::GridVertexBox> boxes(nv);
  for (std::size_t v = 0; v < nv; ++v)
    for (std::size_t d = 0; d < 3; ++d)
      boxes[v].lo[d] = boxes[v].hi[d] =
          two.x(static_cast<Eigen::Index>(v), static_cast<Eigen::Index>(d));
  // The gap is there in double: the nearest vertices of the two spheres are apart on x.
  const double gap = two.x.bottomRows(half).col(0).minCoeff() - x_max;
  ASSERT_GT(gap, 0.0);
  ASSERT_LT(gap, 1e-12);
  CandidatePairs given, exact;
  exact.scratch->grid_float_superset = false;
  ASSERT_TRUE(find_candidates_in_vertex_boxes(boxes, topo, given));
  ASSERT_TRUE(find_candidates_in_vertex_boxes(boxes, topo, exact));
  const BruteForce bf = brute_force(two.x, two.x, two.faces, 0.0);
  EXPECT_EQ(sorted(exact.vertex_face), bf.vertex_face);
  EXPECT_EQ(sorted(exact.edge_edge), bf.edge_edge);
  const std::size_t nf = static_cast<std::size_t>(topo.faces.rows());
  auto prim_box = [&](std::size_t gid) {
    const std::array<int, 3> v = detail::primitive_vertices(topo, gid);
    const detail::GridVertexBox g = detail::primitive_box(boxes, v);
    Box b;
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = g.lo[static_cast<std::size_t>(d)];
      b.hi[d] = g.hi[static_cast<std::size_t>(d)];
    }
    return b;
  };
  const SupersetCheck check = check_superset(given, bf, nv, nf, prim_box);
  EXPECT_EQ(check.missing, 0);
  if (!detail::grid_avx512_available()) {  // the portable loop runs: exact either way
    EXPECT_EQ(check.extra, 0);
    GTEST_SKIP() << "no AVX-512 on this CPU: the float cell loop did not run";
  }
  EXPECT_GT(check.extra, 0);  // the facing primitives, 1e-13 apart
  EXPECT_LE(check.widest_gap, 1e-12);
}

TEST(BroadPhase, RejectsMismatchedInput) {
  const TriMesh m = test::icosphere(0);
  const CollisionTopology topo = make_collision_topology(m.faces, static_cast<int>(m.x.rows()));
  CandidatePairs out;
  const Positions shorter = m.x.topRows(m.x.rows() - 1);
  EXPECT_THROW(find_candidates(m.x, shorter, topo, 0.0, out), UsageError);
  EXPECT_THROW(find_candidates(shorter, m.x, topo, 0.0, out), UsageError);
  EXPECT_THROW(find_candidates(m.x, m.x, topo, -1e-3, out), UsageError);
  EXPECT_THROW(find_candidates(m.x, m.x, topo, std::nan(""), out), UsageError);
  EXPECT_THROW(has_any_candidate(m.x, shorter, topo, 0.0, out), UsageError);
}

}  // namespace
}  // namespace shellcontract
