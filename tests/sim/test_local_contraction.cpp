// The local contraction's force (sim/local_contraction.hpp): a region pressure with no net force
// and no net torque.
#include <gtest/gtest.h>

#include <random>

#include "sim/local_contraction.hpp"
#include "sim/pressure.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

Vec3 net_force(const Positions& f) { return f.colwise().sum().transpose(); }

Vec3 net_torque(const Positions& x, const Eigen::VectorXd& inv_mass, const Positions& f) {
  Vec3 c = Vec3::Zero();
  double M = 0.0;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    c += Vec3(x.row(i)) / inv_mass(i);
    M += 1.0 / inv_mass(i);
  }
  c /= M;
  Vec3 t = Vec3::Zero();
  for (Eigen::Index i = 0; i < x.rows(); ++i) t += (Vec3(x.row(i)) - c).cross(Vec3(f.row(i)));
  return t;
}

struct Scene {
  test::TriMesh m;
  Eigen::VectorXd inv_mass;
  Faces cap;  ///< the faces with a vertex above z = 0.5: an open patch
};

Scene scene() {
  std::mt19937 rng(3);
  Scene s{test::icosphere(2, 1.0), {}, {}};
  s.inv_mass.resize(s.m.x.rows());
  for (Eigen::Index i = 0; i < s.m.x.rows(); ++i) s.inv_mass(i) = 0.5 + std::uniform_real_distribution<>(0, 1)(rng);
  std::vector<Eigen::Index> rows;
  for (Eigen::Index j = 0; j < s.m.faces.rows(); ++j)
    if (s.m.x(s.m.faces(j, 0), 2) > 0.5 || s.m.x(s.m.faces(j, 1), 2) > 0.5 || s.m.x(s.m.faces(j, 2), 2) > 0.5)
      rows.push_back(j);
  s.cap.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t k = 0; k < rows.size(); ++k) s.cap.row(static_cast<Eigen::Index>(k)) = s.m.faces.row(rows[k]);
  return s;
}

TEST(LocalContraction, TheBareRegionPressurePushesTheWholeShell) {
  // Why the rigid part is removed: on an open patch the pressure has a net force.
  const Scene s = scene();
  Positions f;
  pressure_forces(s.m.x, s.cap, 3.0, PressureModel::EnergyConsistent, f);
  EXPECT_GT(net_force(f).norm(), 0.1 * f.rowwise().norm().sum());
}

TEST(LocalContraction, ForceHasNoNetForceAndNoNetTorque) {
  Scene s = scene();
  std::mt19937 rng(8);
  // Off-centre and tilted, so that the bare pressure also has a torque about the centre of mass.
  for (Eigen::Index i = 0; i < s.m.x.rows(); ++i) s.m.x.row(i) += 0.05 * test::random_vec3(rng).transpose();
  Positions bare, f;
  pressure_forces(s.m.x, s.cap, 3.0, PressureModel::EnergyConsistent, bare);
  local_contraction_forces(s.m.x, s.cap, 3.0, s.inv_mass, f);
  const double scale = bare.rowwise().norm().sum();
  ASSERT_GT(net_torque(s.m.x, s.inv_mass, bare).norm(), 1e-3 * scale);
  EXPECT_LE(net_force(f).norm(), 1e-12 * scale);
  EXPECT_LE(net_torque(s.m.x, s.inv_mass, f).norm(), 1e-12 * scale);
  // The region's vertices are still pushed inward: the removed part is a small uniform share.
  int inward = 0, region_vertices = 0;
  std::vector<char> in_region(static_cast<std::size_t>(s.m.x.rows()), 0);
  for (Eigen::Index j = 0; j < s.cap.rows(); ++j)
    for (int k = 0; k < 3; ++k) in_region[static_cast<std::size_t>(s.cap(j, k))] = 1;
  for (Eigen::Index i = 0; i < s.m.x.rows(); ++i)
    if (in_region[static_cast<std::size_t>(i)] && s.m.x(i, 2) > 0.6) {
      ++region_vertices;
      inward += f.row(i).dot(s.m.x.row(i)) < 0.0;
    }
  ASSERT_GT(region_vertices, 0);
  EXPECT_EQ(inward, region_vertices);
}

TEST(LocalContraction, FieldWithoutRigidPartIsUnchanged) {
  // The pressure on the whole closed shell has no net force; on a sphere centred at the centre
  // of mass it has no torque either, so nothing is removed.
  const Scene s = scene();
  Eigen::VectorXd uniform = Eigen::VectorXd::Ones(s.m.x.rows());
  Positions f, g;
  pressure_forces(s.m.x, s.m.faces, 2.0, PressureModel::EnergyConsistent, f);
  g = f;
  remove_rigid_body_force(s.m.x, uniform, g);
  EXPECT_LE((g - f).cwiseAbs().maxCoeff(), 1e-12 * f.cwiseAbs().maxCoeff());
}

TEST(LocalContraction, RemovesExactlyAUniformPushAndASpin) {
  // f = m_i (a + omega x r_i) is all rigid: nothing is left.
  const Scene s = scene();
  Vec3 c = Vec3::Zero();
  double M = 0.0;
  for (Eigen::Index i = 0; i < s.m.x.rows(); ++i) {
    c += Vec3(s.m.x.row(i)) / s.inv_mass(i);
    M += 1.0 / s.inv_mass(i);
  }
  c /= M;
  const Vec3 a(0.3, -1.0, 0.2), omega(0.5, 0.1, -0.7);
  Positions f(s.m.x.rows(), 3);
  for (Eigen::Index i = 0; i < s.m.x.rows(); ++i)
    f.row(i) = ((a + omega.cross(Vec3(s.m.x.row(i)) - c)) / s.inv_mass(i)).transpose();
  remove_rigid_body_force(s.m.x, s.inv_mass, f);
  EXPECT_LE(f.cwiseAbs().maxCoeff(), 1e-12);
}

TEST(LocalContraction, PinnedOrCollinearMassesAreHandled) {
  // Everything pinned: nothing to remove. Masses on one line: only the net force goes.
  Positions x(3, 3);
  x << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  Positions f(3, 3);
  f << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  Positions g = f;
  remove_rigid_body_force(x, Eigen::VectorXd::Zero(3), g);
  EXPECT_EQ(g, f);
  g = f;
  remove_rigid_body_force(x, Eigen::VectorXd::Ones(3), g);
  EXPECT_TRUE(g.allFinite());
  EXPECT_LE(net_force(g).norm(), 1e-12);
}

TEST(LocalContraction, StrengthMapsMonotonicallyToTheRegionPressure) {
  EXPECT_EQ(region_pressure(0.0), 0.0);
  EXPECT_EQ(region_pressure(1.0), FULL_REGION_PRESSURE);
  EXPECT_LT(region_pressure(0.3), region_pressure(0.6));
}

}  // namespace
}  // namespace shellcontract
