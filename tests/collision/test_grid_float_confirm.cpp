// The Grid method's exact pairs from a float cell loop (AVX-512 or AVX2) plus a confirmation of
// each pair (BroadPhaseScratch::grid_float_confirm, grid.cpp's confirm_keys) against an exact
// cell loop (AVX-512's double loop, or the portable one) and brute force: the same pairs, in the
// same order, with the same close flags, so every result downstream keeps its bits.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/broad_phase/grid.hpp"
#include "collision/broad_phase/scratch.hpp"
#include "collision/broad_phase_oracle.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

using namespace test;

/// The float loops this CPU runs: AVX-512 (GridIsa::Auto) and AVX2.
std::vector<detail::GridIsa> float_loops() {
  std::vector<detail::GridIsa> out;
  if (detail::grid_avx512_available()) out.push_back(detail::GridIsa::Auto);
  if (detail::grid_avx2_available()) out.push_back(detail::GridIsa::Avx2);
  return out;
}

/// find_candidates (Grid) twice, with the confirmed float loop of `isa` (the default) and with
/// an exact loop; asserts equal sequences and flags, and equality with brute force. Returns the
/// pairs.
std::size_t compare_loops(detail::GridIsa isa, const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                          const Faces& faces, double inflation, double far,
                          const std::string& where, std::int64_t* far_flags = nullptr,
                          bool against_brute_force = true) {
  CandidatePairs confirmed, exact;
  confirmed.scratch->grid_isa = isa;
  exact.scratch->grid_float_confirm = false;
  BroadPhaseStats cs, es;
  find_candidates(x0, x1, topo, inflation, confirmed, &cs, BroadPhaseMethod::Grid, far);
  find_candidates(x0, x1, topo, inflation, exact, &es, BroadPhaseMethod::Grid, far);
  EXPECT_EQ(cs.method_run, es.method_run) << where;
  EXPECT_TRUE(confirmed.vertex_face == exact.vertex_face) << where;
  EXPECT_TRUE(confirmed.edge_edge == exact.edge_edge) << where;
  EXPECT_TRUE(confirmed.vertex_face_close == exact.vertex_face_close) << where;
  EXPECT_TRUE(confirmed.edge_edge_close == exact.edge_edge_close) << where;
  if (against_brute_force) {
    const BruteForce want = brute_force(x0, x1, faces, inflation);
    EXPECT_EQ(sorted(confirmed.vertex_face), want.vertex_face) << where;
    EXPECT_EQ(sorted(confirmed.edge_edge), want.edge_edge) << where;
  }
  if (far_flags)
    for (const auto* flags : {&confirmed.vertex_face_close, &confirmed.edge_edge_close})
      for (const std::uint8_t f : *flags) *far_flags += f == 0;
  return confirmed.vertex_face.size() + confirmed.edge_edge.size();
}

TEST(GridFloatConfirm, EqualsTheDoubleLoopOverManySteps) {
  // A level-3 sphere and two touching level-2 spheres over many steps: random jitter of every
  // size (none: boxes only touching; small; large jumps that cross the whole scene), with
  // inflations from 0 and far distances from 0 (every gap counts) to none.
  if (float_loops().empty()) GTEST_SKIP() << "no AVX-512 or AVX2: the portable loop runs";
  std::mt19937 rng(58);
  const TriMesh sphere = icosphere(3);
  TriMesh apart = combine(icosphere(2), icosphere(2));
  apart.x.bottomRows(apart.x.rows() / 2).rowwise() += Vec3(2.0, 0.0, 0.0).transpose();
  const TriMesh& two = apart;
  std::size_t pairs = 0;
  std::int64_t far_flags = 0;
  for (const detail::GridIsa isa : float_loops())
  for (const TriMesh* m : {&sphere, &two}) {
    const CollisionTopology topo = make_collision_topology(m->faces, static_cast<int>(m->x.rows()));
    Positions x0 = m->x;
    for (int step = 0; step < 8; ++step) {
      const double scale = step % 4 == 0 ? 0.0 : step % 4 == 3 ? 0.5 : 0.01 * step;
      const Positions x1 = random_motion(x0, scale, rng);
      for (const double inflation : {0.0, 0.01})
        for (const double far : {-1.0, 0.0, 0.004})
          pairs += compare_loops(isa, x0, x1, topo, m->faces, inflation, far,
                                 "step " + std::to_string(step) + " inflation " +
                                     std::to_string(inflation) + " far " + std::to_string(far),
                                 &far_flags, far < 0.0);  // brute force once per scene
      x0 = x1;
    }
  }
  EXPECT_GT(pairs, 100000u);  // not vacuous
  EXPECT_GT(far_flags, 100);  // flags set by the confirmation, not left at the float loop's 1
}

TEST(GridFloatConfirm, CoplanarAndDegenerateScenes) {
  // A sphere squashed flat into z = 0 (every face coplanar, boxes flat on z), and the same
  // with every vertex at one of a few points (zero-size and coinciding boxes).
  if (float_loops().empty()) GTEST_SKIP() << "no AVX-512 or AVX2: the portable loop runs";
  const TriMesh sphere = icosphere(2);
  const CollisionTopology topo =
      make_collision_topology(sphere.faces, static_cast<int>(sphere.x.rows()));
  Positions flat = sphere.x;
  flat.col(2).setZero();
  Positions flat1 = flat;
  flat1.col(0).array() += 0.01;
  Positions points = sphere.x;
  for (Eigen::Index i = 0; i < points.rows(); ++i) points.row(i) = Vec3(static_cast<double>(i % 3), 0.0, 0.0).transpose();
  for (const detail::GridIsa isa : float_loops()) {
    compare_loops(isa, flat, flat, topo, sphere.faces, 0.0, 0.0, "flat, still");
    compare_loops(isa, flat, flat1, topo, sphere.faces, 0.001, 0.001, "flat, sliding");
    compare_loops(isa, points, points, topo, sphere.faces, 0.0, 0.0, "three points");
  }
}

TEST(GridFloatConfirm, DropsThePairsOnlyFloatRoundingJoins) {
  // Two spheres 1e-13 apart on x (no motion, no inflation): the float loop alone joins facing
  // primitives (GridFloatSupersetAddsOnlyPairsApartByRounding shows it does), the exact pairs
  // must not hold them. Checked to fail with confirm_keys' overlap test removed (the extra
  // pairs stay; the other two tests fail too). EqualsTheDoubleLoopOverManySteps fails with the
  // close flag left at the float loop's 1.
  if (float_loops().empty()) GTEST_SKIP() << "no AVX-512 or AVX2: the portable loop runs";
  const TriMesh one = icosphere(2);
  TriMesh two = combine(one, one);
  const double x_max = one.x.col(0).maxCoeff(), x_min = one.x.col(0).minCoeff();
  two.x.bottomRows(one.x.rows()).col(0).array() += x_max - x_min + 1e-13;
  const CollisionTopology topo = make_collision_topology(two.faces, static_cast<int>(two.x.rows()));
  ASSERT_GT(two.x.bottomRows(one.x.rows()).col(0).minCoeff() - x_max, 0.0);
  for (const detail::GridIsa isa : float_loops())
    for (const double far : {-1.0, 0.0}) compare_loops(isa, two.x, two.x, topo, two.faces, 0.0, far, "gap");
}

}  // namespace
}  // namespace shellcontract
