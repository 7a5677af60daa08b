// The air's volume mode against the explicit step (sim/air_step.hpp, docs/math/air-pressure.md
// section 4), checked on a regular octahedron whose sums are done by hand. Before, a light
// `density` (bumpy_sphere at 0.002) swung for its whole run between about 0.3 and 0.6 with no
// word before it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "shellcontract/simulation_options.hpp"
#include "sim/air_step.hpp"

namespace shellcontract {
namespace {

/// The octahedron with vertices +-e_x, +-e_y, +-e_z, faces counter-clockwise from outside.
/// By hand: each face is equilateral with side sqrt 2, area sqrt 3 / 2, so the area is 4 sqrt 3,
/// each vertex's area (four faces / 3) is 2 / sqrt 3, and V0 = 4 / 3 (two pyramids of base 2 and
/// height 1). Moving a vertex outward by e adds the pyramid over the square of the other four
/// minus that at height 1: dV/dx_i = 2 / 3 along its axis.
struct Octahedron {
  Positions x;
  Faces faces;
  Octahedron() : x(6, 3), faces(8, 3) {
    x << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
    int j = 0;
    for (int a : {0, 1})
      for (int b : {2, 3})
        for (int c : {4, 5}) {
          // Counter-clockwise from outside where the octant's sign product is +1.
          const bool ccw = (a == 0) == (b == 2) ? c == 4 : c == 5;
          faces.row(j++) << a, ccw ? b : c, ccw ? c : b;
        }
  }
  /// Area-lumped inverse masses at areal density rho.
  Eigen::VectorXd inv_mass(double rho) const {
    return Eigen::VectorXd::Constant(6, std::sqrt(3.0) / (2.0 * rho));
  }
};

SimOptions air(double rho) {
  SimOptions s;
  s.pressure = 4.0;
  s.air_balance = 0.5;
  s.dt = 0.01;
  s.damping = 0.1;
  s.density = rho;
  return s;
}

TEST(AirStep, TheOctahedronsVolumeModeIsTheClosedForm) {
  const Octahedron o;
  const double rho = 0.002, P = 4.0, dt = 0.01, R = 0.5;
  const AirStep a = air_step(o.x, o.faces, o.inv_mass(rho), air(rho));
  // move = P dt^2 sum_i w_i |g_i|^2 / A = P dt^2 * 6 (4/9) (sqrt 3 / (2 rho)) / (4 sqrt 3)
  //      = P dt^2 / (3 rho); length = R (1 - R) V0 / A = R (1 - R) / (3 sqrt 3).
  EXPECT_NEAR(a.move, P * dt * dt / (3.0 * rho), 1e-12);
  EXPECT_NEAR(a.length, R * (1.0 - R) / (3.0 * std::sqrt(3.0)), 1e-12);
  EXPECT_DOUBLE_EQ(a.limit, 3.8);
  // (omega dt)^2 = sqrt 3 P dt^2 / (R (1 - R) rho) = 1.386 at rho 0.002: inside the bound.
  EXPECT_NEAR(a.omega_dt_squared(), std::sqrt(3.0) * P * dt * dt / (R * (1.0 - R) * rho), 1e-9);
  EXPECT_FALSE(a.overshoots());
  // The paper's form pushes each vertex by its area 2 / sqrt 3, not by |g_i| = 2 / 3:
  // move = P dt^2 * 6 (2/3) (2 / sqrt 3) (sqrt 3 / (2 rho)) / (4 sqrt 3) = P dt^2 / (sqrt 3 rho).
  SimOptions paper = air(rho);
  paper.pressure_model = PressureModel::Paper;
  EXPECT_NEAR(air_step(o.x, o.faces, o.inv_mass(rho), paper).move,
              P * dt * dt / (std::sqrt(3.0) * rho), 1e-12);
}

TEST(AirStep, TheLargestKeyAndOnlyAnAirThatActs) {
  const Octahedron o;
  SimOptions keyed = air(1.0);
  keyed.pressure_schedule = Schedule({{0, 1.0}, {50, 8.0}, {100, 0.0}});
  EXPECT_NEAR(air_step(o.x, o.faces, o.inv_mass(1.0), keyed).move, 8.0 * 1e-4 / 3.0, 1e-15);
  SimOptions none = air(1.0);
  none.air_balance = 0.0;  // a constant pressure: no spring on the volume
  EXPECT_EQ(air_step(o.x, o.faces, o.inv_mass(1.0), none).omega_dt_squared(), 0.0);
  SimOptions inflating = air(1.0);
  inflating.pressure = -4.0;  // the simulator applies the air only under P > 0
  EXPECT_FALSE(air_step(o.x, o.faces, o.inv_mass(1e-6), inflating).overshoots());
}

TEST(AirStep, PastTheBoundTheRunIsToldWhatWouldKeepItWithin) {
  const Octahedron o;
  // The bound (omega dt)^2 = 3.8 is met at rho = sqrt 3 P dt^2 / (R (1 - R) 3.8) = 0.000729.
  const double rho = 0.0005;
  const SimOptions s = air(rho);
  const AirStep a = air_step(o.x, o.faces, o.inv_mass(rho), s);
  ASSERT_TRUE(a.overshoots()) << a.omega_dt_squared();
  const std::string w = air_step_warning(a, s);
  EXPECT_NE(w.find("moves the shell by about 0.267 per step"), std::string::npos) << w;
  // Two digits on the safe side: density up, dt and pressure down (0.00729 * (0.5/0.729)^0.5,
  // 4 * 0.5 / 0.729).
  EXPECT_NE(w.find("A `density` 0.00073 or more, a `dt` 0.0082 or less"), std::string::npos) << w;
  EXPECT_NE(w.find("or a `pressure` 2.7 or less"), std::string::npos) << w;
  // Unit masses do not change with the density: it is not offered.
  SimOptions unit = s;
  unit.mass = MassModel::Unit;
  const std::string u = air_step_warning(a, unit);
  EXPECT_NE(u.find("A `dt` 0.0082 or less"), std::string::npos) << u;
  EXPECT_EQ(u.find("`density` 0"), std::string::npos) << u;
  EXPECT_TRUE(
      air_step_warning(air_step(o.x, o.faces, o.inv_mass(0.001), air(0.001)), air(0.001)).empty());
  // A target volume holds the volume, not the air.
  SimOptions target = s;
  target.target_volume = 0.5;
  EXPECT_TRUE(air_step_warning(a, target).empty());
}

}  // namespace
}  // namespace shellcontract
