// The run's frame following the rest of the shell (sim/rest_frame.hpp): the outside vertices'
// shift and turn taken out of every vertex, nothing else.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "sim/rest_frame.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

struct Cloud {
  Positions prev;
  Eigen::VectorXd inv_mass;
  std::vector<int> outside;
};

/// 40 random points with masses in [0.5, 2]; every third one is "in a region" (not outside).
Cloud cloud(std::mt19937& rng) {
  Cloud c;
  c.prev.resize(40, 3);
  c.inv_mass.resize(40);
  std::uniform_real_distribution<double> mass(0.5, 2.0);
  for (Eigen::Index i = 0; i < 40; ++i) {
    c.prev.row(i) = (Vec3(0.3, -0.2, 0.5) + test::random_vec3(rng)).transpose();
    c.inv_mass(i) = 1.0 / mass(rng);
    if (i % 3 != 0) c.outside.push_back(static_cast<int>(i));
  }
  return c;
}

/// The outside vertices' mass-weighted displacement sum and angular displacement about their
/// mass centre at prev.
std::pair<Vec3, Vec3> rigid_sums(const Cloud& c, const Positions& x) {
  Vec3 centre = Vec3::Zero(), shift = Vec3::Zero(), turn = Vec3::Zero();
  double mass = 0.0;
  for (int v : c.outside) {
    if (!(c.inv_mass(v) > 0.0)) continue;
    centre += Vec3(c.prev.row(v)) / c.inv_mass(v);
    mass += 1.0 / c.inv_mass(v);
  }
  centre /= mass;
  for (int v : c.outside) {
    if (!(c.inv_mass(v) > 0.0)) continue;
    const Vec3 d = x.row(v) - c.prev.row(v);
    shift += d / c.inv_mass(v);
    turn += (Vec3(c.prev.row(v)) - centre).cross(d) / c.inv_mass(v);
  }
  return {shift, turn};
}

TEST(RestFrame, AnyStepEndsWithoutNetShiftOrTurnOfTheRest) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const Cloud c = cloud(rng);
    Positions x = c.prev;
    for (Eigen::Index i = 0; i < x.rows(); ++i) x.row(i) += test::random_vec3(rng, 0.01).transpose();
    const auto [shift0, turn0] = rigid_sums(c, x);
    ASSERT_GT(shift0.norm(), 1e-3);  // the random step has a rigid part to take out
    ASSERT_GT(turn0.norm(), 1e-3);
    follow_rest_frame(x, c.prev, c.inv_mass, c.outside);
    const auto [shift, turn] = rigid_sums(c, x);
    EXPECT_LE(shift.norm(), 1e-14) << trial;
    EXPECT_LE(turn.norm(), 1e-14) << trial;
  }
}

TEST(RestFrame, TheCorrectionIsAnAffineMapOfTheCurrentPositions) {
  // Whether two triangles intersect does not change under an invertible affine map, so a
  // correction that is one cannot create an intersection after the collision response. The end
  // positions are fitted by an affine map of the positions given: the residual must be rounding.
  // (A turn with its lever at the step's start is not affine in the current positions: its
  // residual here is of the order of the turn times the step, about 1e-4.)
  std::mt19937 rng(13);
  for (int trial = 0; trial < 10; ++trial) {
    const Cloud c = cloud(rng);
    Positions x = c.prev;
    for (Eigen::Index i = 0; i < x.rows(); ++i) x.row(i) += test::random_vec3(rng, 0.01).transpose();
    const Positions before = x;
    follow_rest_frame(x, c.prev, c.inv_mass, c.outside);
    Eigen::MatrixXd design(x.rows(), 4);
    design << Eigen::MatrixXd(before), Eigen::VectorXd::Ones(x.rows());
    const Eigen::MatrixXd map = design.colPivHouseholderQr().solve(Eigen::MatrixXd(x));
    const double residual = (design * map - Eigen::MatrixXd(x)).cwiseAbs().maxCoeff();
    ASSERT_GT((x - before).cwiseAbs().maxCoeff(), 1e-4);  // the correction is not trivial
    EXPECT_LE(residual, 1e-13) << trial;
  }
}

TEST(RestFrame, ASmallRigidMotionOfEveryVertexIsUndoneToSecondOrder) {
  // x = prev moved by the rotation exp(eps [a]) about a point and a translation: the rule takes
  // out the linear part, so what is left is the rotation's second-order term, O(eps^2 |r|).
  std::mt19937 rng(5);
  const Cloud c = cloud(rng);
  for (const double eps : {1e-2, 1e-3, 1e-4}) {
    const Vec3 axis = test::random_vec3(rng).normalized();
    const Mat3 rot = Eigen::AngleAxisd(eps, axis).toRotationMatrix();
    const Vec3 pivot(1.0, 2.0, -1.0), t = eps * Vec3(0.7, -0.3, 0.2);
    Positions x = c.prev;
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      x.row(i) = (rot * (Vec3(c.prev.row(i)) - pivot) + pivot + t).transpose();
    follow_rest_frame(x, c.prev, c.inv_mass, c.outside);
    // The rotation's second-order term is at most eps^2 |p - pivot| / 2 (up to about 4.4 here);
    // the shift takes out its mean, and what is left of it is about eps^2 |p - c| / 2, c the
    // cloud's mass centre (|p - c| < 2): under 2 eps^2 either way but for the largest lever.
    EXPECT_LE((x - c.prev).rowwise().norm().maxCoeff(), 2.0 * eps * eps) << eps;
  }
}

TEST(RestFrame, AStepWithoutRigidPartIsLeftAlone) {
  // A uniform scaling about the rest's mass centre has no net shift and no net turn: nothing is
  // taken out, to rounding. (A check against false positives: the two tests above catch a wrong
  // centre, sign or inertia; this one catches a rule that moves a step with no rigid part.)
  std::mt19937 rng(7);
  const Cloud c = cloud(rng);
  Vec3 centre = Vec3::Zero();
  double mass = 0.0;
  for (int v : c.outside) centre += Vec3(c.prev.row(v)) / c.inv_mass(v), mass += 1.0 / c.inv_mass(v);
  centre /= mass;
  Positions x = c.prev;
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    x.row(i) = (centre + 0.97 * (Vec3(c.prev.row(i)) - centre)).transpose();
  const Positions scaled = x;
  follow_rest_frame(x, c.prev, c.inv_mass, c.outside);
  EXPECT_LE((x - scaled).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(RestFrame, TheRegionsMoveWithTheRestAndMasslessVerticesDoNotCount) {
  std::mt19937 rng(9);
  Cloud c = cloud(rng);
  // A rigid shift of the whole cloud, and one massless outside vertex (inv_mass 0: infinite mass,
  // as a vertex fixed by the caller) moved far: it must not count, so the shift is taken out of
  // every vertex, the regions' and the massless one's included, and the massless one keeps its
  // own offset.
  c.inv_mass(c.outside.front()) = 0.0;
  const Vec3 t(0.01, -0.02, 0.005);
  Positions x = c.prev;
  x.rowwise() += t.transpose();
  x.row(c.outside.front()) += Vec3(1.0, 1.0, 1.0).transpose();
  follow_rest_frame(x, c.prev, c.inv_mass, c.outside);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const Vec3 expected = i == c.outside.front() ? Vec3(1.0, 1.0, 1.0) : Vec3::Zero();
    EXPECT_LE((Vec3(x.row(i) - c.prev.row(i)) - expected).norm(), 1e-14) << i;
  }
}

TEST(RestFrame, ARestOnALineKeepsItsTurn) {
  // Outside vertices on a line have no defined turn about it, so the rule takes out only the
  // shift: a turn of the line about its own mass centre (an axis across the line, whose turn a
  // pseudo-inverse would find and take out) stays, and nothing becomes non-finite. Nearly on a
  // line (1e-13 off it), the same: the guard is relative, not an exact zero.
  for (const double off : {0.0, 1e-13}) {
    Cloud c;
    c.prev.resize(6, 3);
    c.inv_mass = Eigen::VectorXd::Ones(6);
    for (int i = 0; i < 6; ++i)
      c.prev.row(i) = Vec3(0.1 * i, 0.2 * i + (i % 2 ? off : -off), -0.1 * i).transpose();
    c.outside = {0, 1, 2, 3};
    const Vec3 centre = (c.prev.topRows(4).colwise().sum() / 4.0).transpose();
    const Vec3 omega = 1e-3 * Vec3(0.2, -0.1, 0.0).normalized().cross(Vec3(1.0, 2.0, -1.0));
    Positions x = c.prev;
    for (int i = 0; i < 6; ++i) x.row(i) += omega.cross(Vec3(c.prev.row(i)) - centre).transpose();
    const Positions turned = x;
    follow_rest_frame(x, c.prev, c.inv_mass, c.outside);
    ASSERT_TRUE(x.allFinite());
    EXPECT_LE((x - turned).cwiseAbs().maxCoeff(), 1e-15) << off;
  }
}

TEST(RestFrame, NoMassOutsideMovesNothing) {
  std::mt19937 rng(11);
  Cloud c = cloud(rng);
  c.inv_mass.setZero();
  Positions x = c.prev;
  x.rowwise() += Vec3(0.1, 0.1, 0.1).transpose();
  const Positions before = x;
  follow_rest_frame(x, c.prev, c.inv_mass, c.outside);
  EXPECT_EQ(x, before);
}

}  // namespace
}  // namespace shellcontract
