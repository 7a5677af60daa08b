// The broad phase's test oracle (tests/collision/test_broad_phase*.cpp): brute force over every
// VF and EE pair with the same closed box test, and the comparison of every method against it
// (ipc-toolkit's brute_force_comparison habit, house-style.md section 5).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/broad_phase/scratch.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract::test {

using Pairs = NoZeroVector<std::array<int, 2>>;  // CandidatePairs' list type

inline const std::array<BroadPhaseMethod, 4> METHODS = {BroadPhaseMethod::PrimitiveBoxes,
                                                  BroadPhaseMethod::FacePairs,
                                                  BroadPhaseMethod::Bvh, BroadPhaseMethod::Grid};

inline std::string method_name(BroadPhaseMethod m) {
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
inline std::vector<std::array<int, 2>> reference_edges(const Faces& faces) {
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
inline Box swept_box(const Positions& x0, const Positions& x1, std::initializer_list<int> verts,
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
inline bool boxes_overlap(const Box& a, const Box& b) {
  for (int d = 0; d < 3; ++d)
    if (a.lo[d] > b.hi[d] || b.lo[d] > a.hi[d]) return false;
  return true;
}

/// The oracle: every VF and EE pair, adjacency excluded, same closed box test.
struct BruteForce {
  Pairs vertex_face, edge_edge;
  std::int64_t all_vf = 0, all_ee = 0;  // pairs tested = Table 2 "no culling"
};
inline BruteForce brute_force(const Positions& x0, const Positions& x1, const Faces& faces,
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

/// The pairs in sorted order.
inline Pairs sorted(Pairs p) {
  std::sort(p.begin(), p.end());
  return p;
}

inline std::string first_difference(const Pairs& got, const Pairs& want) {
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
inline int g_grid_runs = 0;
inline int g_grid_fallbacks = 0;

/// Runs every method and compares with brute force; returns the oracle for further checks.
inline BruteForce expect_all_methods_match(const Positions& x0, const Positions& x1, const Faces& faces,
                                    double inflation, const std::string& label) {
  const BruteForce want = brute_force(x0, x1, faces, inflation);
  const CollisionTopology topo = make_collision_topology(faces, static_cast<int>(x0.rows()));
  for (BroadPhaseMethod m : METHODS) {
    CandidatePairs got;
    BroadPhaseStats stats;
    find_candidates(x0, x1, topo, inflation, got, &stats, m);
    const std::string where = label + ", method " + method_name(m) +
                              ", inflation " + std::to_string(inflation);
    // Sorted, the output must equal brute force; and every method emits it sorted (Grid by
    // its counting sort: test_grid_sorted_output.cpp).
    const Pairs vf = sorted(got.vertex_face), ee = sorted(got.edge_edge);
    EXPECT_TRUE(vf == want.vertex_face) << where << ": VF " << first_difference(vf, want.vertex_face);
    EXPECT_TRUE(ee == want.edge_edge) << where << ": EE " << first_difference(ee, want.edge_edge);
    EXPECT_TRUE(vf == got.vertex_face && ee == got.edge_edge) << where << ": not sorted";
    EXPECT_EQ(stats.no_culling_vertex_face, want.all_vf) << where;
    EXPECT_EQ(stats.no_culling_edge_edge, want.all_ee) << where;
    EXPECT_EQ(stats.vertex_face, static_cast<std::int64_t>(want.vertex_face.size())) << where;
    EXPECT_EQ(stats.edge_edge, static_cast<std::int64_t>(want.edge_edge.size())) << where;
    // The box search reports adjacent pairs too, so it is at least the number emitted.
    EXPECT_GE(stats.box_overlaps, m != BroadPhaseMethod::FacePairs
                                      ? stats.vertex_face + stats.edge_edge
                                      : std::int64_t{1})
        << where;
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

inline Positions random_motion(const Positions& x0, double scale, std::mt19937& rng) {
  Positions x1 = x0;
  for (Eigen::Index v = 0; v < x1.rows(); ++v)
    x1.row(v) += random_vec3(rng, scale).transpose();
  return x1;
}

inline TriMesh combine(const TriMesh& a, const TriMesh& b) {
  TriMesh m;
  m.x.resize(a.x.rows() + b.x.rows(), 3);
  m.x << a.x, b.x;
  m.faces.resize(a.faces.rows() + b.faces.rows(), 3);
  m.faces << a.faces, (b.faces.array() + static_cast<int>(a.x.rows())).matrix();
  return m;
}

inline Positions translated(const Positions& x, const Vec3& t) {
  Positions y = x;
  y.rowwise() += t.transpose();
  return y;
}

}  // namespace shellcontract::test
