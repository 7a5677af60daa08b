// symmetric_hausdorff_distance against closed forms on an icosphere (a convex polyhedron with
// its vertices on the sphere of radius r): identical positions give 0, scaling by 1 + e about
// the centre gives e r (the vertices are the farthest points), a translation by d along minus a
// face normal gives d, and a rotation (vertices slide along the surface) gives much less than
// the vertex displacement.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "shellcontract/validation.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

constexpr double BOUND = 1e-8;

TEST(Hausdorff, IdenticalPositionsGiveZero) {
  const test::TriMesh s = test::icosphere(3, 0.7);
  const Mesh mesh = test::to_surface_mesh(s);
  EXPECT_EQ(symmetric_hausdorff_distance(mesh, s.x, s.x, BOUND), 0.0);
  EXPECT_EQ(max_vertex_distance(s.x, s.x), 0.0);
}

TEST(Hausdorff, ScaledSphereGivesERadius) {
  const double r = 0.7;
  const test::TriMesh s = test::icosphere(3, r);
  const Mesh mesh = test::to_surface_mesh(s);
  for (double e : {1e-4, 1e-2, 0.1}) {
    const Positions scaled = (1.0 + e) * s.x;
    const double h = symmetric_hausdorff_distance(mesh, s.x, scaled, BOUND);
    EXPECT_NEAR(h, e * r, 2 * BOUND) << "e = " << e;
    // Symmetric: the argument order does not matter.
    EXPECT_NEAR(symmetric_hausdorff_distance(mesh, scaled, s.x, BOUND), h, 2 * BOUND);
    EXPECT_NEAR(max_vertex_distance(s.x, scaled), e * r, 1e-12);
  }
}

TEST(Hausdorff, TranslationAlongMinusAFaceNormalGivesItsLength) {
  const test::TriMesh s = test::icosphere(2, 1.0);
  const Mesh mesh = test::to_surface_mesh(s);
  // Moving the copy by -d m (m: outward unit normal of face 0) leaves the centre of face 0
  // outside the copy at distance d from the moved face's interior; no point is farther than
  // the translation length, so the distance is exactly d.
  const Vec3 a = s.x.row(s.faces(0, 0)), b = s.x.row(s.faces(0, 1)), c = s.x.row(s.faces(0, 2));
  const Vec3 m = (b - a).cross(c - a).normalized();
  const double d = 0.01;
  const Positions moved = s.x.rowwise() - d * m.transpose();
  EXPECT_NEAR(symmetric_hausdorff_distance(mesh, s.x, moved, BOUND), d, 2 * BOUND);
  EXPECT_NEAR(max_vertex_distance(s.x, moved), d, 1e-15);
}

TEST(Hausdorff, RotationIsTangentialSoMuchSmallerThanTheVertexDistance) {
  const test::TriMesh s = test::icosphere(3, 1.0);
  const Mesh mesh = test::to_surface_mesh(s);
  const double angle = 0.05;
  Mat3 R;
  R << std::cos(angle), -std::sin(angle), 0, std::sin(angle), std::cos(angle), 0, 0, 0, 1;
  const Positions rotated = s.x * R.transpose();
  const double h = symmetric_hausdorff_distance(mesh, s.x, rotated, BOUND);
  const double v = max_vertex_distance(s.x, rotated);
  EXPECT_GT(h, 0.0);
  EXPECT_LT(h, 0.2 * v) << "h " << h << " vertex distance " << v;
}

TEST(Hausdorff, RejectsMismatchedArraysAndBadBound) {
  const test::TriMesh s = test::icosphere(1);
  const Mesh mesh = test::to_surface_mesh(s);
  const Positions fewer = s.x.topRows(s.x.rows() - 1);
  EXPECT_THROW(symmetric_hausdorff_distance(mesh, s.x, fewer), std::invalid_argument);
  EXPECT_THROW(symmetric_hausdorff_distance(mesh, s.x, s.x, 0.0), std::invalid_argument);
  EXPECT_THROW(max_vertex_distance(s.x, fewer), std::invalid_argument);
}

}  // namespace
}  // namespace shellcontract
