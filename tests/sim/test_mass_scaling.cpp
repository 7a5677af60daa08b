// sim/mass_scaling.hpp: the minimum vertex mass that the explicit pressure needs at a time step.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/mass_scaling.hpp"
#include "sim/simulator.hpp"
#include "support/cgal_mesh.hpp"

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
  EXPECT_EQ(scale_masses_for_pressure(x, f, P, dt, w), 1u);
  EXPECT_NEAR(1.0 / w(1), bound_mass, 1e-12 * bound_mass);
  EXPECT_NEAR(dt * std::sqrt(K * w(1)), MAX_PRESSURE_OMEGA_DT, 1e-12);  // omega dt at the bound
  EXPECT_EQ(w(0), 1.0 / (2.0 * bound_mass));
  EXPECT_EQ(w(2), 0.0);
  // The sign of P does not matter (an inflating pressure is as stiff); P = 0 changes nothing.
  Eigen::VectorXd w2 = Eigen::VectorXd::Constant(6, 1.0 / (0.5 * bound_mass));
  w2(0) = 1.0 / (10.0 * bound_mass);  // makes the mean mass 2.08 bound_mass
  EXPECT_EQ(scale_masses_for_pressure(x, f, -P, dt, w2), 5u);
  EXPECT_NEAR(1.0 / w2(3), bound_mass, 1e-12 * bound_mass);
  Eigen::VectorXd w3 = Eigen::VectorXd::Constant(6, 1e12);
  EXPECT_EQ(scale_masses_for_pressure(x, f, 0.0, dt, w3), 0u);
  EXPECT_EQ(w3, Eigen::VectorXd::Constant(6, 1e12));
}

TEST(MassScaling, NeverRaisesAMassAboveTheMeanMass) {
  // A pressure far too large for the whole mesh: every vertex is below the bound, and none is
  // raised past the mean, so such a run still blows up (and says so) instead of being slowed.
  Positions x;
  Faces f;
  octahedron(0.1, x, f);
  Eigen::VectorXd w = Eigen::VectorXd::Constant(6, 1e6);
  EXPECT_EQ(scale_masses_for_pressure(x, f, 1e6, 0.01, w), 0u);
  w(4) = 4e6;  // a quarter of the others' mass: raised to the mean, 0.875e-6
  EXPECT_EQ(scale_masses_for_pressure(x, f, 1e6, 0.01, w), 1u);
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

}  // namespace
}  // namespace shellcontract
