// Air inside the shell (docs/math/air-pressure.md): Boyle's law against the outside pressure.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sim/pressure.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

TEST(AirPressure, NetPressureIsPAtRestZeroAtTheBalanceAndOutwardBelowIt) {
  const double P = 4.0, R = 0.5;
  EXPECT_DOUBLE_EQ(air_net_pressure(P, R, 1.0), P);
  EXPECT_NEAR(air_net_pressure(P, R, R), 0.0, 1e-15);
  EXPECT_LT(air_net_pressure(P, R, 0.4), 0.0);
  // Boyle: p_out = P / (1 - R) = 8, p_air(0.8) = 8 * 0.5 / 0.8 = 5, net 3.
  EXPECT_DOUBLE_EQ(air_net_pressure(P, R, 0.8), 3.0);
  // Monotone in v: the further it is compressed, the harder the air pushes back.
  double previous = air_net_pressure(P, R, 0.2);
  for (double v = 0.25; v <= 1.5; v += 0.05) {
    const double p = air_net_pressure(P, R, v);
    EXPECT_GE(p, previous) << "v " << v;
    previous = p;
  }
}

TEST(AirPressure, NoAirIsTheConstantPressure) {
  for (double v : {-1.0, 0.0, 0.3, 1.0, 2.0}) EXPECT_EQ(air_net_pressure(2.5, 0.0, v), 2.5);
}

TEST(AirPressure, CrushedOrInvertedShellGetsABoundedOutwardPush) {
  // The floor v >= R / 4 bounds the outward net pressure by 3 p_out = 3 P / (1 - R).
  const double P = 4.0, R = 0.5;
  for (double v : {0.1, 0.0, -0.5}) {
    const double p = air_net_pressure(P, R, v);
    EXPECT_TRUE(std::isfinite(p)) << v;
    EXPECT_DOUBLE_EQ(p, -3.0 * P / (1.0 - R)) << v;
  }
}

TEST(AirPressure, ForceIsMinusTheGradientOfTheAirEnergy) {
  // E(x) = p_out V - p_out R V0 ln V (docs/math/air-pressure.md 1); the simulator's force is
  // pressure_forces with the net pressure at the current volume. Central differences of E.
  std::mt19937 rng(5);
  test::TriMesh m = test::icosphere(1, 0.6);
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) m.x.row(i) += 0.04 * test::random_vec3(rng).transpose();
  const double P = 3.0, R = 0.4;
  const double V0 = 1.3 * test::signed_volume(m.x, m.faces);  // a shell already at v = 1/1.3
  const double p_out = P / (1.0 - R);
  auto energy = [&](const Positions& x) {
    const double V = test::signed_volume(x, m.faces);
    return p_out * V - p_out * R * V0 * std::log(V);
  };
  Positions f;
  pressure_forces(m.x, m.faces, air_net_pressure(P, R, test::signed_volume(m.x, m.faces) / V0),
                  PressureModel::EnergyConsistent, f);
  const double h = 1e-6;
  double err = 0.0, scale = 0.0;
  for (Eigen::Index i = 0; i < m.x.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      Positions xp = m.x, xm = m.x;
      xp(i, k) += h;
      xm(i, k) -= h;
      const double dE = (energy(xp) - energy(xm)) / (2.0 * h);
      err = std::max(err, std::abs(f(i, k) + dE));
      scale = std::max(scale, std::abs(f(i, k)));
    }
  ASSERT_GT(scale, 0.0);
  EXPECT_LE(err, 1e-7 * scale);
}

}  // namespace
}  // namespace shellcontract
