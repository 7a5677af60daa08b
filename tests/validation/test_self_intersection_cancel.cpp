// self_intersecting_pairs during a run's preparation (core/cancellation.hpp): the Simulator's
// baseline of the input's own intersections is one CGAL call that cannot be interrupted, and
// took seconds on a large mesh with no question to the run's cancel; under a scope the faces are
// checked slab by slab. Before, the cancel below was not heard (no throw): the test failed.
#include <gtest/gtest.h>

#include <vector>

#include "core/cancellation.hpp"
#include "shellcontract/validation.hpp"
#include "support/cgal_mesh.hpp"

namespace shellcontract {
namespace {

/// Two ellipsoids, three times as long along x as across, one raised by half its height: their
/// intersection runs along the whole length, across every slab boundary (slabs split x, where
/// the mesh spans most). Level 5: 2 x 20480 faces, more than two CANCELLATION_CHUNKs.
Mesh crossing_ellipsoids() {
  const test::TriMesh one = test::icosphere(5);
  test::TriMesh both;
  const Eigen::Index nv = one.x.rows(), nf = one.faces.rows();
  both.x.resize(2 * nv, 3);
  both.faces.resize(2 * nf, 3);
  for (Eigen::Index i = 0; i < nv; ++i) {
    both.x.row(i) << 3.0 * one.x(i, 0), one.x(i, 1), one.x(i, 2);
    both.x.row(nv + i) << 3.0 * one.x(i, 0), one.x(i, 1), one.x(i, 2) + 0.5;
  }
  both.faces.topRows(nf) = one.faces;
  both.faces.bottomRows(nf) = one.faces.array() + static_cast<int>(nv);
  return test::to_surface_mesh(both);
}

TEST(SelfIntersectionCancel, SlabsUnderARunsScopeFindTheSamePairs) {
  const Mesh mesh = crossing_ellipsoids();
  const Positions x = positions_from_mesh(mesh);
  const std::vector<FacePair> alone = self_intersecting_pairs(mesh, x);
  ASSERT_GT(alone.size(), 100u) << "the ellipsoids must cross";
  int asked = 0;
  const CancellationScope scope([&] {
    ++asked;
    return false;
  });
  EXPECT_EQ(self_intersecting_pairs(mesh, x), alone);
  EXPECT_GE(asked, 3) << "not checked in slabs";
  // A pair whose faces are both in two slabs is visited in the first only (the pairs are no
  // longer held, sorted and made unique: self_intersecting_pairs above keeps all it visits).
  const SelfIntersectionCount counted = count_self_intersections(mesh, x, 10);
  EXPECT_EQ(counted.count, alone.size());
  EXPECT_EQ(counted.first, std::vector<FacePair>(alone.begin(), alone.begin() + 10));
}

TEST(SelfIntersectionCancel, ACancelIsHeardBetweenTheSlabs) {
  const Mesh mesh = crossing_ellipsoids();
  const Positions x = positions_from_mesh(mesh);
  for (const int at : {1, 2}) {
    int asked = 0;
    const CancellationScope scope([&] { return ++asked >= at; });
    EXPECT_THROW(self_intersecting_pairs(mesh, x), PreparationCancelled) << at;
    EXPECT_EQ(asked, at);
  }
}

}  // namespace
}  // namespace shellcontract
