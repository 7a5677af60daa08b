// CCD broad phase (math-spec 10.1-10.2) against brute force: every method must return exactly
// the pairs that the box test over all VF and EE pairs returns (ipc-toolkit's
// brute_force_comparison habit, style.md section 3).
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

#include "collision/broad_phase/scratch.hpp"
#include "shellcontract/collision/broad_phase.hpp"
#include "shellcontract/core/error.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

using Pairs = std::vector<std::array<int, 2>>;
using test::TriMesh;

const std::array<BroadPhaseMethod, 4> METHODS = {BroadPhaseMethod::PrimitiveBoxes,
                                                  BroadPhaseMethod::FacePairs,
                                                  BroadPhaseMethod::Bvh, BroadPhaseMethod::Grid};

std::string method_name(BroadPhaseMethod m) {
  switch (m) {
    case BroadPhaseMethod::PrimitiveBoxes:
      return "PrimitiveBoxes";
    case BroadPhaseMethod::FacePairs:
      return "FacePairs";
    case BroadPhaseMethod::Bvh:
      return "Bvh";
    case BroadPhaseMethod::Grid:
      return "Grid";
  }
  return "?";
}

/// Edges from the faces, written independently of the library: unique (min, max), sorted.
std::vector<std::array<int, 2>> reference_edges(const Faces& faces) {
  std::set<std::array<int, 2>> s;
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      s.insert({std::min(a, b), std::max(a, b)});
    }
  return {s.begin(), s.end()};
}

/// Swept box of a vertex list, computed directly from all start and end coordinates.
struct Box {
  double lo[3], hi[3];
};
Box swept_box(const Positions& x0, const Positions& x1, std::initializer_list<int> verts,
              double inflation) {
  Box b;
  for (int d = 0; d < 3; ++d) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int v : verts) {
      lo = std::min({lo, x0(v, d), x1(v, d)});
      hi = std::max({hi, x0(v, d), x1(v, d)});
    }
    b.lo[d] = lo - inflation;
    b.hi[d] = hi + inflation;
  }
  return b;
}
bool boxes_overlap(const Box& a, const Box& b) {
  for (int d = 0; d < 3; ++d)
    if (a.lo[d] > b.hi[d] || b.lo[d] > a.hi[d]) return false;
  return true;
}

/// The oracle: every VF and EE pair, adjacency excluded, same closed box test.
struct BruteForce {
  Pairs vertex_face, edge_edge;
  std::int64_t all_vf = 0, all_ee = 0;  // pairs tested = Table 2 "no culling"
};
BruteForce brute_force(const Positions& x0, const Positions& x1, const Faces& faces,
                       double inflation) {
  BruteForce r;
  const auto edges = reference_edges(faces);
  for (int v = 0; v < static_cast<int>(x0.rows()); ++v) {
    const Box vb = swept_box(x0, x1, {v}, inflation);
    for (int f = 0; f < static_cast<int>(faces.rows()); ++f) {
      if (faces(f, 0) == v || faces(f, 1) == v || faces(f, 2) == v) continue;
      ++r.all_vf;
      if (boxes_overlap(vb, swept_box(x0, x1, {faces(f, 0), faces(f, 1), faces(f, 2)}, inflation)))
        r.vertex_face.push_back({v, f});
    }
  }
  for (int a = 0; a < static_cast<int>(edges.size()); ++a)
    for (int b = a + 1; b < static_cast<int>(edges.size()); ++b) {
      const auto& ea = edges[static_cast<std::size_t>(a)];
      const auto& eb = edges[static_cast<std::size_t>(b)];
      if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) continue;
      ++r.all_ee;
      if (boxes_overlap(swept_box(x0, x1, {ea[0], ea[1]}, inflation),
                        swept_box(x0, x1, {eb[0], eb[1]}, inflation)))
        r.edge_edge.push_back({a, b});
    }
  return r;
}

/// The pairs in sorted order (Grid emits them in its cell order).
Pairs sorted(Pairs p) {
  std::sort(p.begin(), p.end());
  return p;
}

std::string first_difference(const Pairs& got, const Pairs& want) {
  std::ostringstream os;
  Pairs missing, extra;
  std::set_difference(want.begin(), want.end(), got.begin(), got.end(),
                      std::back_inserter(missing));
  std::set_difference(got.begin(), got.end(), want.begin(), want.end(),
                      std::back_inserter(extra));
  os << got.size() << " pairs, brute force " << want.size() << "; missing " << missing.size()
     << ", extra " << extra.size();
  if (!missing.empty()) os << " (first missing " << missing[0][0] << "," << missing[0][1] << ")";
  if (!extra.empty()) os << " (first extra " << extra[0][0] << "," << extra[0][1] << ")";
  return os.str();
}

/// How often Grid ran its own algorithm and how often it fell back to PrimitiveBoxes, over all
/// comparisons of this test binary (tests below check that both paths are exercised).
int g_grid_runs = 0;
int g_grid_fallbacks = 0;

/// Runs every method and compares with brute force; returns the oracle for further checks.
BruteForce expect_all_methods_match(const Positions& x0, const Positions& x1, const Faces& faces,
                                    double inflation, const std::string& label) {
  const BruteForce want = brute_force(x0, x1, faces, inflation);
  const CollisionTopology topo = make_collision_topology(faces, static_cast<int>(x0.rows()));
  for (BroadPhaseMethod m : METHODS) {
    CandidatePairs got;
    BroadPhaseStats stats;
    find_candidates(x0, x1, topo, inflation, got, &stats, m);
    const std::string where = label + ", method " + method_name(m) +
                              ", inflation " + std::to_string(inflation);
    // Sorted, the output must equal brute force; and only Grid may emit out of order.
    const Pairs vf = sorted(got.vertex_face), ee = sorted(got.edge_edge);
    EXPECT_TRUE(vf == want.vertex_face) << where << ": VF " << first_difference(vf, want.vertex_face);
    EXPECT_TRUE(ee == want.edge_edge) << where << ": EE " << first_difference(ee, want.edge_edge);
    if (m != BroadPhaseMethod::Grid) {
      EXPECT_TRUE(vf == got.vertex_face && ee == got.edge_edge) << where << ": not sorted";
    }
    EXPECT_EQ(stats.no_culling_vertex_face, want.all_vf) << where;
    EXPECT_EQ(stats.no_culling_edge_edge, want.all_ee) << where;
    EXPECT_EQ(stats.vertex_face, static_cast<std::int64_t>(want.vertex_face.size())) << where;
    EXPECT_EQ(stats.edge_edge, static_cast<std::int64_t>(want.edge_edge.size())) << where;
    // The box search reports adjacent pairs too, so it is at least the number emitted.
    EXPECT_GE(stats.box_overlaps, m != BroadPhaseMethod::FacePairs
                                      ? stats.vertex_face + stats.edge_edge
                                      : std::int64_t{1})
        << where;
    EXPECT_GT(stats.seconds, 0.0) << where << ": the search ran, so it took time";
    if (m == BroadPhaseMethod::Grid) {
      ++(stats.method_run == BroadPhaseMethod::Grid ? g_grid_runs : g_grid_fallbacks);
      // The portable cell loop (Auto may have run the AVX-512 one): the same pairs, in the same
      // order.
      CandidatePairs portable;
      portable.scratch->grid_isa = detail::GridIsa::Portable;
      find_candidates(x0, x1, topo, inflation, portable, nullptr, m);
      EXPECT_TRUE(portable.vertex_face == got.vertex_face) << where << ": portable VF differs";
      EXPECT_TRUE(portable.edge_edge == got.edge_edge) << where << ": portable EE differs";
    } else {
      EXPECT_EQ(stats.method_run, m) << where;
    }
    EXPECT_EQ(has_any_candidate(x0, x1, topo, inflation, got),
              !want.vertex_face.empty() || !want.edge_edge.empty())
        << where;
  }
  return want;
}

Positions random_motion(const Positions& x0, double scale, std::mt19937& rng) {
  Positions x1 = x0;
  for (Eigen::Index v = 0; v < x1.rows(); ++v)
    x1.row(v) += test::random_vec3(rng, scale).transpose();
  return x1;
}

TriMesh combine(const TriMesh& a, const TriMesh& b) {
  TriMesh m;
  m.x.resize(a.x.rows() + b.x.rows(), 3);
  m.x << a.x, b.x;
  m.faces.resize(a.faces.rows() + b.faces.rows(), 3);
  m.faces << a.faces, (b.faces.array() + static_cast<int>(a.x.rows())).matrix();
  return m;
}

Positions translated(const Positions& x, const Vec3& t) {
  Positions y = x;
  y.rowwise() += t.transpose();
  return y;
}

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
  // close flags) being the same for any number of threads.
  std::mt19937 rng(11);
  const TriMesh m = test::icosphere(3);
  const CollisionTopology topo = make_collision_topology(m.faces, static_cast<int>(m.x.rows()));
  const Positions x0 = random_motion(m.x, 0.05, rng);
  const Positions x1 = random_motion(x0, 0.02, rng);
  std::vector<CandidatePairs> runs(3);
  const int threads[3] = {1, 2, 4};
  for (int k = 0; k < 3; ++k) {
    tbb::task_arena arena(threads[k]);
    BroadPhaseStats stats;
    arena.execute([&] {
      find_candidates(x0, x1, topo, 0.01, runs[static_cast<std::size_t>(k)], &stats,
                      BroadPhaseMethod::Grid, 0.005);
    });
    ASSERT_EQ(stats.method_run, BroadPhaseMethod::Grid);
  }
  ASSERT_GT(runs[0].vertex_face.size(), 100u);
  ASSERT_GT(runs[0].edge_edge.size(), 100u);
  for (int k = 1; k < 3; ++k) {
    const CandidatePairs& r = runs[static_cast<std::size_t>(k)];
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
      // Mostly small steps; a jump every 10th; steps 21-28 also drift by 0.1 along x.
      const double scale = step % 10 == 9 ? 0.1 : 0.004;
      Positions x1 = random_motion(x0, scale, rng);
      const bool drift = step >= 21 && step <= 28;
      if (drift) x1.col(0).array() += 0.1;
      const double inflation = 0.01, far = 0.005;
      BroadPhaseStats stats;
      find_candidates(x0, x1, topo, inflation, patched, &stats, BroadPhaseMethod::Grid, far);
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
  find_candidates(x0, x1, first, inflation, out, &stats, BroadPhaseMethod::Grid);
  ASSERT_EQ(stats.method_run, BroadPhaseMethod::Grid);
  find_candidates(x0, x1, second, inflation, out, &stats, BroadPhaseMethod::Grid);
  ASSERT_EQ(stats.method_run, BroadPhaseMethod::Grid);
  EXPECT_GT(out.scratch->grid_patched_boxes, 0);  // the kept grid, patched for the new topology
  const BruteForce want = brute_force(x0, x1, swapped, inflation);
  const Pairs vf = sorted(out.vertex_face), ee = sorted(out.edge_edge);
  EXPECT_TRUE(vf == want.vertex_face) << "VF " << first_difference(vf, want.vertex_face);
  EXPECT_TRUE(ee == want.edge_edge) << "EE " << first_difference(ee, want.edge_edge);
}

TEST(BroadPhase, GridAvx512LoopEqualsThePortableLoop) {
  // The AVX-512 cell loop must emit exactly the portable loop's pairs, in its order, with its
  // close flags: random motions from none (every box touching its neighbours) to large, cells
  // of every size (so every tail of the 8-lane loop), inflation 0 (boxes that only touch),
  // and far distances from 0 (every gap counts) to none.
  if (!detail::grid_avx512_available()) GTEST_SKIP() << "no AVX-512 on this CPU";
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
              grid_runs % 2 ? detail::GridIsa::Portable : detail::GridIsa::Auto;
          find_candidates(x0, x1, topo, inflation, switching, nullptr, BroadPhaseMethod::Grid, far);
          EXPECT_TRUE(switching.vertex_face == portable.vertex_face) << where;
          EXPECT_TRUE(switching.edge_edge_close == portable.edge_edge_close) << where;
          // Exact overlaps, never more than the portable loop's float ones.
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
