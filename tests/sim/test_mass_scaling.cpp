// sim/mass_scaling.hpp: the minimum vertex mass that the explicit pressure needs at a time step.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/mass_scaling.hpp"
#include "sim/run_plan.hpp"
#include "sim/simulator.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

/// Regular octahedron with vertices at +-a on the axes: every one-ring is a square of side
/// a sqrt(2), perimeter 4 sqrt(2) a.
void octahedron(double a, Positions& x, Faces& f) {
  x.resize(6, 3);
  x << a, 0, 0, -a, 0, 0, 0, a, 0, 0, -a, 0, 0, 0, a, 0, 0, -a;
  f.resize(8, 3);
  f << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
}

TEST(MassScaling, RaisesOnlyTheMassesBelowTheBoundAndToExactlyTheBound) {
  Positions x;
  Faces f;
  octahedron(0.1, x, f);
  const double P = 4.0, dt = 0.01;
  const double ring = 4.0 * std::sqrt(2.0) * 0.1;
  const double K = P / 3.0 * ring;
  const double bound_mass = K * std::pow(dt / MAX_PRESSURE_OMEGA_DT, 2);
  Eigen::VectorXd w = Eigen::VectorXd::Constant(6, 1.0 / (2.0 * bound_mass));  // heavy enough
  w(1) = 1.0 / (0.5 * bound_mass);                                             // too light
  w(2) = 0.0;                                                                  // pinned
  const MassScaling m = scale_masses_for_pressure(x, f, P, dt, w);
  EXPECT_EQ(m.raised, 1u);
  EXPECT_NEAR(m.largest_factor, 2.0, 1e-12);  // from half the bound's mass to the bound
  EXPECT_NEAR(1.0 / w(1), bound_mass, 1e-12 * bound_mass);
  EXPECT_NEAR(dt * std::sqrt(K * w(1)), MAX_PRESSURE_OMEGA_DT, 1e-12);  // omega dt at the bound
  EXPECT_EQ(w(0), 1.0 / (2.0 * bound_mass));
  EXPECT_EQ(w(2), 0.0);
  // The sign of P does not matter (an inflating pressure is as stiff); P = 0 changes nothing.
  Eigen::VectorXd w2 = Eigen::VectorXd::Constant(6, 1.0 / (0.5 * bound_mass));
  w2(0) = 1.0 / (10.0 * bound_mass);  // makes the mean mass 2.08 bound_mass
  EXPECT_EQ(scale_masses_for_pressure(x, f, -P, dt, w2).raised, 5u);
  EXPECT_NEAR(1.0 / w2(3), bound_mass, 1e-12 * bound_mass);
  Eigen::VectorXd w3 = Eigen::VectorXd::Constant(6, 1e12);
  const MassScaling none = scale_masses_for_pressure(x, f, 0.0, dt, w3);
  EXPECT_EQ(none.raised, 0u);
  EXPECT_EQ(none.largest_factor, 1.0);
  EXPECT_TRUE(std::isinf(none.largest_unscaled_dt));
  EXPECT_EQ(w3, Eigen::VectorXd::Constant(6, 1e12));
}

TEST(MassScaling, NeverRaisesAMassAboveTheMeanMass) {
  // A pressure far too large for the whole mesh: every vertex is below the bound, and none is
  // raised past the mean, so such a run still blows up (and says so) instead of being slowed.
  Positions x;
  Faces f;
  octahedron(0.1, x, f);
  Eigen::VectorXd w = Eigen::VectorXd::Constant(6, 1e6);
  EXPECT_EQ(scale_masses_for_pressure(x, f, 1e6, 0.01, w).raised, 0u);
  w(4) = 4e6;  // a quarter of the others' mass: raised to the mean, 0.875e-6
  EXPECT_EQ(scale_masses_for_pressure(x, f, 1e6, 0.01, w).raised, 1u);
  EXPECT_NEAR(1.0 / w(4), (5.0 * 1e-6 + 0.25e-6) / 6.0, 1e-18);
}

TEST(MassScaling, LeavesTheMassesOfAnEvenSphereAloneAndRaisesThoseOfAFinerOne) {
  // At a unit bounding-box diagonal the 162 vertices of a level-2 icosphere have
  // omega dt ~ 0.1 at the defaults; those of a level-5 one (10,242 vertices) ~ 0.3, and the ones
  // lighter than the mean are raised.
  SimOptions opt;
  opt.frames = 1;
  EXPECT_EQ(Simulator(test::to_surface_mesh(test::icosphere(2, 1.0)), opt).mass_scaled_vertices(),
            0u);
  EXPECT_GT(Simulator(test::to_surface_mesh(test::icosphere(5, 1.0)), opt).mass_scaled_vertices(),
            0u);
  opt.pressure = 0.0;
  EXPECT_EQ(Simulator(test::to_surface_mesh(test::icosphere(5, 1.0)), opt).mass_scaled_vertices(),
            0u);
}

TEST(MassScaling, NoMassIsRaisedAtOrBelowTheLargestUnscaledStep) {
  // The step the report gives is where the first vertex would be raised: the masses of a run at
  // a smaller --dt are the lumped ones, and just above it they are not.
  test::TriMesh m = test::icosphere_with_small_faces(2, 3);
  m.x /= (m.x.colwise().maxCoeff() - m.x.colwise().minCoeff()).norm();  // a run's normalization
  Eigen::VectorXd lumped = Eigen::VectorXd::Zero(m.x.rows());  // inverse area-lumped masses
  for (Eigen::Index j = 0; j < m.faces.rows(); ++j) {
    const Eigen::RowVector3d e1 = m.x.row(m.faces(j, 1)) - m.x.row(m.faces(j, 0));
    const Eigen::RowVector3d e2 = m.x.row(m.faces(j, 2)) - m.x.row(m.faces(j, 0));
    for (int k = 0; k < 3; ++k) lumped(m.faces(j, k)) += e1.cross(e2).norm() / 6.0;
  }
  lumped = lumped.cwiseInverse();
  Eigen::VectorXd w = lumped;
  const MassScaling at = scale_masses_for_pressure(m.x, m.faces, 4.0, 0.01, w);
  ASSERT_GT(at.raised, 0u);
  ASSERT_LT(at.largest_unscaled_dt, 0.01);
  w = lumped;
  EXPECT_EQ(scale_masses_for_pressure(m.x, m.faces, 4.0, 0.999 * at.largest_unscaled_dt, w).raised,
            0u);
  EXPECT_EQ(w, lumped);
  w = lumped;
  const MassScaling above =
      scale_masses_for_pressure(m.x, m.faces, 4.0, 1.001 * at.largest_unscaled_dt, w);
  EXPECT_GT(above.raised, 0u);
  // The same threshold whichever step it is computed at.
  EXPECT_NEAR(above.largest_unscaled_dt, at.largest_unscaled_dt, 1e-12 * at.largest_unscaled_dt);
}

TEST(MassScaling, APlanMayFixTheStepTheMassesAreFor) {
  // bench error's runs at a fraction of the step keep the base step's masses (SimPlan's
  // mass_scaling_dt): the same as a Simulator at that step, not the lighter ones of their own.
  const Mesh mesh = test::to_surface_mesh(test::icosphere_with_small_faces(2, 3));
  SimOptions opt;
  opt.frames = 1;
  opt.collisions = false;
  const MassScaling base = Simulator(mesh, opt).mass_scaling();
  ASSERT_GT(base.raised, 0u);
  opt.dt /= 4.0;
  EXPECT_EQ(Simulator(mesh, opt).mass_scaled_vertices(), 0u);
  SimPlan plan = plan_simulation(mesh, opt);
  plan.mass_scaling_dt = 4.0 * opt.dt;
  const MassScaling kept = Simulator(std::move(plan)).mass_scaling();
  EXPECT_EQ(kept.raised, base.raised);
  EXPECT_EQ(kept.largest_factor, base.largest_factor);
}

}  // namespace
}  // namespace shellcontract
