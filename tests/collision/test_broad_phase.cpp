// CCD broad phase (math-spec 10.1-10.2) against brute force: every method must return exactly
// the pairs that the box test over all VF and EE pairs returns (ipc-toolkit's
// brute_force_comparison habit, house-style.md section 5). The oracle is broad_phase_oracle.hpp; the
// grid's own contract (order, reuse, the float and AVX-512 loops) is test_broad_phase_grid.cpp.
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
#include "collision/broad_phase/scratch.hpp"
#include "collision/broad_phase_oracle.hpp"
#include "shellcontract/error.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

using namespace test;  // the oracle (broad_phase_oracle.hpp) and the mesh fixtures

// ------------------------------------------------------------------ topology

TEST(CollisionTopology, EdgesAreUniqueSortedAndMatchFaceSides) {
  const TriMesh m = test::icosphere(1);
  const CollisionTopology topo = make_collision_topology(m.faces, static_cast<int>(m.x.rows()));
  const auto want = reference_edges(m.faces);
  ASSERT_EQ(topo.edges.rows(), 120);  // closed icosphere level 1: E = 3F/2 = 120
  ASSERT_EQ(static_cast<std::size_t>(topo.edges.rows()), want.size());
  for (Eigen::Index e = 0; e < topo.edges.rows(); ++e) {
    EXPECT_EQ(topo.edges(e, 0), want[static_cast<std::size_t>(e)][0]) << "edge " << e;
    EXPECT_EQ(topo.edges(e, 1), want[static_cast<std::size_t>(e)][1]) << "edge " << e;
  }
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int e = topo.face_edges(f, k);
      const int a = m.faces(f, k), b = m.faces(f, (k + 1) % 3);
      EXPECT_EQ(topo.edges(e, 0), std::min(a, b)) << "face " << f << " side " << k;
      EXPECT_EQ(topo.edges(e, 1), std::max(a, b)) << "face " << f << " side " << k;
    }
  // No-culling counts against direct enumeration (zero motion: every box test is irrelevant).
  const BruteForce bf = brute_force(m.x, m.x, m.faces, 0.0);
  EXPECT_EQ(topo.all_vertex_face_pairs, bf.all_vf);
  EXPECT_EQ(topo.all_edge_edge_pairs, bf.all_ee);
}

TEST(CollisionTopology, RejectsBadFaces) {
  Faces out_of_range(1, 3);
  out_of_range << 0, 1, 3;
  EXPECT_THROW(make_collision_topology(out_of_range, 3), InputError);
  Faces negative(1, 3);
  negative << 0, -1, 2;
  EXPECT_THROW(make_collision_topology(negative, 3), InputError);
  Faces repeated(1, 3);
  repeated << 0, 1, 1;
  EXPECT_THROW(make_collision_topology(repeated, 3), InputError);
  Faces ok(1, 3);
  ok << 0, 1, 2;
  EXPECT_THROW(make_collision_topology(ok, -1), UsageError);
  EXPECT_NO_THROW(make_collision_topology(ok, 3));
}

// ------------------------------------------------------------------ brute-force comparisons

TEST(BroadPhase, ZeroMotionUnperturbedIcosphereWithTouchingBoxes) {
  // Icosphere coordinates repeat exactly (symmetry), so many boxes only touch: this checks that
  // every method treats boxes as closed, like the brute force.
  for (int levels : {0, 1, 2}) {
    const TriMesh m = test::icosphere(levels);
    for (double inflation : {0.0, 1e-3}) {
      const BruteForce bf = expect_all_methods_match(
          m.x, m.x, m.faces, inflation, "icosphere " + std::to_string(levels) + ", zero motion");
      // Non-trivial comparison: neighbouring edges' boxes overlap. (VF boxes do not: on a
      // convex polyhedron at rest a vertex is extreme, outside the boxes of the faces around it;
      // the moving cases below cover VF.)
      if (levels > 0) {
        EXPECT_FALSE(bf.edge_edge.empty()) << "levels " << levels;
      }
    }
  }
}

TEST(BroadPhase, RandomMotionsSmallToLarge) {
  std::mt19937 rng(20200531);
  const int grid_runs_before = g_grid_runs;
  for (int levels : {1, 2}) {
    const TriMesh m = test::icosphere(levels);
    for (int trial = 0; trial < 4; ++trial) {
      // Jitter the start so that coordinates are generic (and, for the larger jitter, the surface
      // is locally concave so that VF boxes overlap even at small motion), then move.
      const double jitter = trial % 2 == 0 ? 0.02 : 0.15;
      const Positions x0 = random_motion(m.x, jitter, rng);
      for (double scale : {0.0, 1e-3, 0.05, 0.3, 1.5}) {
        const Positions x1 = random_motion(x0, scale, rng);
        for (double inflation : {0.0, 1e-4, 0.02}) {
          std::ostringstream label;
          label << "icosphere " << levels << ", trial " << trial << ", jitter " << jitter
                << ", motion " << scale;
          const BruteForce bf = expect_all_methods_match(x0, x1, m.faces, inflation, label.str());
          EXPECT_FALSE(bf.edge_edge.empty()) << label.str();
          if (scale >= 0.3 || (jitter > 0.1 && levels == 2)) {
            EXPECT_FALSE(bf.vertex_face.empty()) << label.str();
          }
          // Large motions make (almost) everything a candidate; the test must cover that regime.
          if (scale == 1.5) {
            EXPECT_GT(static_cast<double>(bf.vertex_face.size()),
                      0.2 * static_cast<double>(bf.all_vf))
                << label.str();
          }
        }
      }
    }
  }
  // The comparisons above must have exercised Grid's own algorithm, not only its fallback.
  EXPECT_GT(g_grid_runs - grid_runs_before, 100);
}

/// Largest per-axis gap between the swept boxes (not inflated) of the two primitives of a pair.
double pair_gap(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                bool vertex_face, const std::array<int, 2>& p) {
  const Box a = vertex_face ? swept_box(x0, x1, {p[0]}, 0.0)
                            : swept_box(x0, x1, {topo.edges(p[0], 0), topo.edges(p[0], 1)}, 0.0);
  const Box b = vertex_face ? swept_box(x0, x1, {topo.faces(p[1], 0), topo.faces(p[1], 1),
                                                 topo.faces(p[1], 2)}, 0.0)
                            : swept_box(x0, x1, {topo.edges(p[1], 0), topo.edges(p[1], 1)}, 0.0);
  double gap = -std::numeric_limits<double>::infinity();
  for (int d = 0; d < 3; ++d) gap = std::max({gap, b.lo[d] - a.hi[d], a.lo[d] - b.hi[d]});
  return gap;
}

TEST(BroadPhase, CloseFlagsMarkFarOnlyPairsFartherThanTheDistance) {
  // The collision step skips the first test of pairs flagged far: a pair within the distance
  // flagged far would be a missed contact. Grid must also flag the far pairs (up to rounding),
  // or the flags would save nothing; the other methods flag every pair close.
  std::mt19937 rng(20261123);
  const TriMesh m = test::icosphere(2);
  const CollisionTopology topo = make_collision_topology(m.faces, static_cast<int>(m.x.rows()));
  std::int64_t far_seen = 0, grid_far = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const Positions x0 = random_motion(m.x, 0.15, rng);
    const Positions x1 = random_motion(x0, trial % 2 == 0 ? 0.01 : 0.1, rng);
    const double inflation = 0.05, far = trial < 3 ? 0.02 : 0.0;
    for (BroadPhaseMethod method : METHODS) {
      CandidatePairs out;
      BroadPhaseStats stats;
      find_candidates(x0, x1, topo, inflation, out, &stats, method, far);
      ASSERT_EQ(out.vertex_face_close.size(), out.vertex_face.size());
      ASSERT_EQ(out.edge_edge_close.size(), out.edge_edge.size());
      const bool grid = stats.method_run == BroadPhaseMethod::Grid;
      for (int list = 0; list < 2; ++list) {
        const Pairs& pairs = list == 0 ? out.vertex_face : out.edge_edge;
        const auto& close = list == 0 ? out.vertex_face_close : out.edge_edge_close;
        for (std::size_t i = 0; i < pairs.size(); ++i) {
          const double gap = pair_gap(x0, x1, topo, list == 0, pairs[i]);
          const std::string where = method_name(method) + " trial " + std::to_string(trial) +
                                    (list == 0 ? " VF " : " EE ") + std::to_string(pairs[i][0]) +
                                    "," + std::to_string(pairs[i][1]);
          if (!close[i]) {
            EXPECT_GT(gap, far) << where;
          }
          if (!grid) {
            EXPECT_EQ(close[i], 1) << where;
          } else if (gap > far * (1.0 + 1e-9) + 1e-12) {
            EXPECT_EQ(close[i], 0) << where << ": gap " << gap;
          }
          if (method == BroadPhaseMethod::Grid) {
            far_seen += gap > far;
            grid_far += !close[i];
          }
        }
      }
      // Without a distance, nothing is flagged far.
      find_candidates(x0, x1, topo, inflation, out, nullptr, method);
      EXPECT_EQ(std::count(out.vertex_face_close.begin(), out.vertex_face_close.end(), 0), 0);
      EXPECT_EQ(std::count(out.edge_edge_close.begin(), out.edge_edge_close.end(), 0), 0);
    }
  }
  EXPECT_GT(far_seen, 1000);  // the scenes have many far pairs ...
  EXPECT_GT(grid_far, 1000);  // ... and the grid ran its own algorithm on them
}

TEST(BroadPhase, CloseFlagAtTheExactDistance) {
  // A vertex above a triangle, both static: per-axis gap exactly `far` (binary fractions, so the
  // gap is exact) is close; 1% farther is far (Grid; the others never flag far).
  TriMesh m;
  m.x.resize(4, 3);
  m.faces.resize(1, 3);
  m.faces << 0, 1, 2;
  const double far = 0.0625;
  const CollisionTopology topo = make_collision_topology(m.faces, 4);
  for (double gap : {far, far * 1.01}) {
    m.x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.25, 0.25, gap;
    CandidatePairs out;
    BroadPhaseStats stats;
    find_candidates(m.x, m.x, topo, 0.125, out, &stats, BroadPhaseMethod::Grid, far);
    ASSERT_EQ(out.vertex_face.size(), 1u);
    EXPECT_EQ(out.vertex_face_close[0], gap == far ? 1 : 0) << "gap " << gap;
  }
}

TEST(BroadPhase, CloseFlagSurvivesTheRoundingOfInflatedBoxesFarFromTheOrigin) {
  // Exact gap == far (binary fractions), but coordinates near 2^10..2^20 and inflations that are
  // not binary fractions: the inflated bounds round by up to an ulp of the coordinates, far more
  // than any ulp of the gap. Without the rounding allowance in the threshold, some of these
  // pairs come out flagged far (tried: the test fails then).
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> fraction(0.0, 1.0);
  TriMesh m;
  m.x.resize(4, 3);
  m.faces.resize(1, 3);
  m.faces << 0, 1, 2;
  const CollisionTopology topo = make_collision_topology(m.faces, 4);
  int far_flagged = 0, cases = 0;
  for (int e = 10; e <= 20; ++e)
    for (int trial = 0; trial < 200; ++trial) {
      const double base = std::ldexp(1.0, e) + std::ldexp(std::floor(fraction(rng) * 4096), -8);
      const double far = 0.125;
      const double inflation = 0.1 + 0.3 * fraction(rng);  // > far / 2: far pairs are emitted
      // The triangle spans x in [base - 1, base]; the vertex sits at base + far on x.
      m.x << base - 1, 0, 0, base, 0, 0, base - 1, 1, 0, base + far, 0.25, 0;
      CandidatePairs out;
      BroadPhaseStats stats;
      find_candidates(m.x, m.x, topo, inflation, out, &stats, BroadPhaseMethod::Grid, far);
      ASSERT_EQ(out.vertex_face.size(), 1u);
      far_flagged += out.vertex_face_close[0] == 0;
      ++cases;
    }
  EXPECT_EQ(far_flagged, 0) << "of " << cases << " pairs exactly `far` apart";
}

TEST(BroadPhase, TwoSpheresPushedIntoEachOther) {
  // Two unit spheres 0.1 apart move 0.25 towards each other each, ending 0.4 interpenetrated.
  const TriMesh s = test::icosphere(2);
  const TriMesh both = combine(s, s);
  const int nv = static_cast<int>(s.x.rows());
  const int nf = static_cast<int>(s.faces.rows());
  Positions x0(2 * nv, 3), x1(2 * nv, 3);
  x0 << translated(s.x, Vec3(-1.05, 0, 0)), translated(s.x, Vec3(1.05, 0, 0));
  x1 << translated(s.x, Vec3(-0.8, 0, 0)), translated(s.x, Vec3(0.8, 0, 0));
  for (double inflation : {0.0, 1e-3}) {
    const BruteForce bf = expect_all_methods_match(x0, x1, both.faces, inflation, "two spheres");
    // There must be pairs between the spheres (vertex of one, face of the other).
    const auto cross = std::count_if(bf.vertex_face.begin(), bf.vertex_face.end(),
                                     [&](const std::array<int, 2>& p) {
                                       return (p[0] < nv) != (p[1] < nf);
                                     });
    EXPECT_GT(cross, 0) << "inflation " << inflation;
  }
  // Far apart and still: only pairs within each sphere, none between them.
  const Positions far0 =
      (Positions(2 * nv, 3) << translated(s.x, Vec3(-5, 0, 0)), translated(s.x, Vec3(5, 0, 0)))
          .finished();
  const BruteForce apart = expect_all_methods_match(far0, far0, both.faces, 1e-3, "apart");
  for (const auto& p : apart.vertex_face) EXPECT_EQ(p[0] < nv, p[1] < nf);
}

TEST(BroadPhase, FacePairsKeepsPairsWhoseFacesAllShareAVertex) {
  // In a tetrahedron every two faces share a vertex, so math-spec 10.2's "face pairs that share
  // no vertex" would yield nothing, yet opposite edges and vertex/opposite face do overlap here.
  Positions x(4, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  Faces f(4, 3);
  f << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  const BruteForce bf = expect_all_methods_match(x, x, f, 0.0, "tetrahedron");
  // Only the origin lies in its opposite face's box [0,1]^3 (face 3); every other vertex is at
  // x, y or z = 1 while its opposite face lies in that coordinate's 0 plane.
  EXPECT_TRUE(bf.vertex_face == (Pairs{{0, 3}}));
  // The three opposite edge pairs have touching boxes, e.g. (0,1) and (2,3) both contain 0.
  EXPECT_EQ(bf.edge_edge.size(), 3u);
}

TEST(BroadPhase, RandomTetrahedraBothAnswersOfTheEarlyExit) {
  // Random small meshes: some have no candidate at all, some do; has_any_candidate must agree
  // with brute force on both (checked inside expect_all_methods_match).
  std::mt19937 rng(7);
  Faces f(4, 3);
  f << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  int empty = 0, nonempty = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Positions x0(4, 3);
    for (int v = 0; v < 4; ++v) x0.row(v) = test::random_vec3(rng).transpose();
    const Positions x1 = random_motion(x0, 0.05, rng);
    const BruteForce bf =
        expect_all_methods_match(x0, x1, f, 0.01, "tetrahedron " + std::to_string(trial));
    (bf.vertex_face.empty() && bf.edge_edge.empty() ? empty : nonempty) += 1;
  }
  EXPECT_GT(empty, 0);
  EXPECT_GT(nonempty, 0);
}

TEST(BroadPhase, GridFarFromTheOriginAndFallback) {
  // Coordinates near 1e5 with tiny boxes: Grid's float prefilter works relative to the scene
  // minimum, so it must still agree with brute force, touching boxes included (zero motion).
  const TriMesh s = test::icosphere(2);
  const Positions far = translated(s.x, Vec3(1e5, -2e5, 3e5));
  const int fallbacks_before = g_grid_fallbacks, runs_before = g_grid_runs;
  expect_all_methods_match(far, far, s.faces, 0.0, "icosphere at 1e5, zero motion");
  std::mt19937 rng(11);
  expect_all_methods_match(far, random_motion(far, 0.01, rng), s.faces, 1e-4,
                           "icosphere at 1e5, small motion");
  EXPECT_EQ(g_grid_runs - runs_before, 2);

  // A tiny tetrahedron 1e6 away: the grid's cell count cap makes the sphere fall into a few
  // cells, so Grid must take its fallback, and still match brute force.
  TriMesh tet;
  tet.x.resize(4, 3);
  tet.x << 0, 0, 0, 1e-3, 0, 0, 0, 1e-3, 0, 0, 0, 1e-3;
  tet.faces.resize(4, 3);
  tet.faces << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  tet.x = translated(tet.x, Vec3(1e6, 1e6, 1e6));
  const TriMesh both = combine(test::icosphere(3), tet);
  expect_all_methods_match(both.x, random_motion(both.x, 1e-3, rng), both.faces, 1e-3,
                           "icosphere and a far tetrahedron");
  EXPECT_EQ(g_grid_fallbacks - fallbacks_before, 1);
}

TEST(BroadPhase, VerticesNoFaceReferencesAreStillVertexFaceCandidates) {
  // Face-pair methods find VF pairs through the faces around the vertex; a vertex without faces
  // has none and needs its own search. Place 40 of them on and near the sphere, moving.
  const TriMesh s = test::icosphere(2);
  const int nv = static_cast<int>(s.x.rows());
  std::mt19937 rng(5);
  Positions x(nv + 40, 3);
  x.topRows(nv) = s.x;
  for (int i = 0; i < 40; ++i) x.row(nv + i) = s.x.row(i * 3) * (0.97 + 0.0015 * i);
  const CollisionTopology topo = make_collision_topology(s.faces, nv + 40);
  ASSERT_EQ(topo.orphan_vertices.size(), 40u);
  EXPECT_EQ(topo.orphan_vertices.front(), nv);
  for (double motion : {0.0, 0.01, 0.05})
    expect_all_methods_match(x, random_motion(x, motion, rng), s.faces, 1e-3,
                             "icosphere and 40 unreferenced vertices, motion " + std::to_string(motion));
  // Some of them must be candidates, or the case is not exercised.
  const BruteForce bf = brute_force(x, x, s.faces, 1e-3);
  EXPECT_TRUE(std::any_of(bf.vertex_face.begin(), bf.vertex_face.end(),
                          [&](const std::array<int, 2>& p) { return p[0] >= nv; }));
}

}  // namespace
}  // namespace shellcontract
