// The global volume constraint of target-volume runs (docs/math/volume-control.md): its volume
// against CGAL's and the sphere's closed form, its gradient against finite differences, the
// projection, the ramp.
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/validation.hpp"
#include "sim/volume_constraint.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

TEST(VolumeConstraint, VolumeEqualsCgalAndTendsToTheSphere) {
  for (int level : {1, 3}) {
    const test::TriMesh m = test::icosphere(level, 2.0);
    const Mesh mesh = test::to_surface_mesh(m);
    EXPECT_NEAR(signed_volume(m.x, m.faces), enclosed_volume(mesh, m.x), 1e-12);
  }
  // An inscribed polyhedron is smaller than the ball, and close to it at level 4.
  const test::TriMesh fine = test::icosphere(4, 2.0);
  const double ball = 4.0 / 3.0 * M_PI * 8.0;
  EXPECT_LT(signed_volume(fine.x, fine.faces), ball);
  EXPECT_NEAR(signed_volume(fine.x, fine.faces) / ball, 1.0, 0.01);
}

TEST(VolumeConstraint, GradientMatchesFiniteDifferences) {
  test::TriMesh m = test::icosphere(1);
  // An irregular shape, so that no symmetry hides a wrong term.
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) m.x.row(i) *= 1.0 + 0.1 * std::sin(3.0 * i);
  Positions g;
  volume_gradient(m.x, m.faces, g);
  const double h = 1e-6;
  for (Eigen::Index i = 0; i < m.x.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      Positions xp = m.x, xm = m.x;
      xp(i, k) += h;
      xm(i, k) -= h;
      const double fd = (signed_volume(xp, m.faces) - signed_volume(xm, m.faces)) / (2 * h);
      EXPECT_NEAR(g(i, k), fd, 1e-8) << "vertex " << i << " axis " << k;
    }
}

TEST(VolumeConstraint, ProjectionReachesTheTargetAndMovesByTheWeights) {
  const test::TriMesh m = test::icosphere(2);
  const double v0 = signed_volume(m.x, m.faces);
  Eigen::VectorXd w = Eigen::VectorXd::Ones(m.x.rows());
  w(0) = 0.0;  // a fixed vertex
  Positions x = m.x;
  const int steps = project_volume(x, m.faces, w, 0.6 * v0, 1e-13 * v0);
  EXPECT_GT(steps, 1) << "a cubic constraint needs more than one linear step for a 40% change";
  EXPECT_NEAR(signed_volume(x, m.faces), 0.6 * v0, 1e-12 * v0);
  EXPECT_EQ(x.row(0), m.x.row(0));
  // Every other vertex moved inward, along its direction (the gradient is the vertex normal).
  for (Eigen::Index i = 1; i < x.rows(); ++i) {
    EXPECT_LT(x.row(i).norm(), 0.95 * m.x.row(i).norm()) << "vertex " << i;
    EXPECT_NEAR(x.row(i).normalized().dot(m.x.row(i).normalized()), 1.0, 1e-3) << "vertex " << i;
  }
  // All weights zero: nothing can move, and nothing does.
  Positions y = m.x;
  project_volume(y, m.faces, Eigen::VectorXd::Zero(m.x.rows()), 0.5 * v0, 1e-12);
  EXPECT_EQ(y, m.x);
}

// A few free vertices take the whole correction: without a cap the projection sends them far
// beyond the mesh (what made a target the contacts would not allow a blow-up); with max_move none
// moves farther than it, the volume moves toward the target and stops short of it.
TEST(VolumeConstraint, MaxMoveCapsEachVertexAndStopsShortOfTheTarget) {
  const test::TriMesh m = test::icosphere(2);  // unit radius
  const double v0 = signed_volume(m.x, m.faces);
  Eigen::VectorXd w = Eigen::VectorXd::Zero(m.x.rows());
  for (Eigen::Index i : {0, 1, 2}) w(i) = 1.0;  // held by contacts but three
  Positions free_run = m.x;
  project_volume(free_run, m.faces, w, 0.1 * v0, 1e-12 * v0);
  EXPECT_GT((free_run - m.x).rowwise().norm().maxCoeff(), 1.0) << "the uncapped case this guards";
  const double cap = 0.01;
  Positions x = m.x;
  project_volume(x, m.faces, w, 0.1 * v0, 1e-12 * v0, 4, cap);
  const Eigen::VectorXd moved = (x - m.x).rowwise().norm();
  EXPECT_LE(moved.maxCoeff(), cap * (1.0 + 1e-12));
  EXPECT_GT(moved.maxCoeff(), 0.5 * cap);
  const double v = signed_volume(x, m.faces);
  EXPECT_LT(v, v0);
  EXPECT_GT(v, 0.1 * v0);
  for (Eigen::Index i = 3; i < x.rows(); ++i) EXPECT_EQ(x.row(i), m.x.row(i)) << "vertex " << i;
  // A correction within the cap is the uncapped projection, bit for bit.
  Positions a = m.x, b = m.x;
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(m.x.rows());
  project_volume(a, m.faces, ones, 0.999 * v0, 1e-12 * v0);
  project_volume(b, m.faces, ones, 0.999 * v0, 1e-12 * v0, 4, cap);
  EXPECT_EQ(a, b);
}

// smooth_moves: the cap rises to k |V - target| / A, the move a smooth shell of area A needs. A
// free sphere's projection moves about that much, so with k = 4 it is not capped at all, where
// the plain cap stops it short; the few free vertices of the test above move no farther than
// the raised cap.
TEST(VolumeConstraint, SmoothMovesRaiseTheCapToWhatASmoothShellNeeds) {
  const test::TriMesh m = test::icosphere(2);  // unit radius
  const double v0 = signed_volume(m.x, m.faces);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(m.x.rows());
  const double cap = 0.01;
  Positions free_run = m.x, capped = m.x, lifted = m.x;
  project_volume(free_run, m.faces, ones, 0.3 * v0, 1e-12 * v0);
  project_volume(capped, m.faces, ones, 0.3 * v0, 1e-12 * v0, 4, cap);
  project_volume(lifted, m.faces, ones, 0.3 * v0, 1e-12 * v0, 4, cap, 4.0);
  EXPECT_GT(signed_volume(capped, m.faces), 0.9 * v0) << "the plain cap stops far short";
  EXPECT_EQ(lifted, free_run);
  // Four Newton steps of the cubic V from V0 to 0.3 V0 (the call's max_steps): close, not exact.
  EXPECT_NEAR(signed_volume(lifted, m.faces), 0.3 * v0, 1e-6 * v0);
  // Three free vertices: the raised cap bounds them.
  Eigen::VectorXd w = Eigen::VectorXd::Zero(m.x.rows());
  for (Eigen::Index i : {0, 1, 2}) w(i) = 1.0;
  Positions few = m.x;
  const double c = v0 - 0.9 * v0;
  const double raised = 4.0 * c / surface_area(m.x, m.faces);
  ASSERT_GT(raised, cap);
  project_volume(few, m.faces, w, 0.9 * v0, 1e-12 * v0, 4, cap, 4.0);
  const double moved = (few - m.x).rowwise().norm().maxCoeff();
  EXPECT_LE(moved, raised * (1.0 + 1e-12));
  EXPECT_GT(moved, 0.5 * raised);
}

TEST(VolumeConstraint, SurfaceAreaOfATetrahedronAndOfTheSphere) {
  Positions x(4, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  Faces f(4, 3);
  f << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  // Three right triangles of area 1/2 and an equilateral one of side sqrt(2).
  EXPECT_NEAR(surface_area(x, f), 1.5 + std::sqrt(3.0) / 2.0, 1e-15);
  const test::TriMesh fine = test::icosphere(4);
  EXPECT_NEAR(surface_area(fine.x, fine.faces) / (4.0 * M_PI), 1.0, 0.01);
}

TEST(VolumeConstraint, RampStartsAtV0EndsAtTheTargetAndIsMonotone) {
  EXPECT_DOUBLE_EQ(target_volume_at(0, 100, 2.0, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(target_volume_at(100, 100, 2.0, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(target_volume_at(250, 100, 2.0, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(target_volume_at(50, 100, 2.0, 0.5), 1.5);  // smoothstep(1/2) = 1/2
  for (int n = 0; n < 100; ++n)
    EXPECT_GT(target_volume_at(n, 100, 1.0, 0.3), target_volume_at(n + 1, 100, 1.0, 0.3));
  // Zero rate at both ends: the first and last steps are smaller than the middle one.
  const auto change = [](int n) {
    return target_volume_at(n, 100, 1.0, 0.3) - target_volume_at(n + 1, 100, 1.0, 0.3);
  };
  EXPECT_LT(change(0), 0.1 * change(50));
  EXPECT_LT(change(99), 0.1 * change(50));
}

}  // namespace
}  // namespace shellcontract
