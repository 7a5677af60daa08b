// The explicit air's volume mode before a run (sim/air_step.hpp).
#include "sim/air_step.hpp"

#include <cmath>

#include "core/decimal_text.hpp"
#include "sim/volume_constraint.hpp"

namespace shellcontract {

namespace {

/// x to two significant digits, rounded up (`up`) or down: a value shown as the bound is on its
/// safe side.
std::string two_digits(double x, bool up) {
  const double unit = std::pow(10.0, std::floor(std::log10(x)) - 1.0);
  return general_text((up ? std::ceil(x / unit) : std::floor(x / unit)) * unit, 2);
}

}  // namespace

AirStep air_step(const Positions& x, const Faces& faces, const Eigen::VectorXd& inv_mass,
                 const SimOptions& s) {
  const Schedule& keys = s.pressure_schedule;
  const double P = keys.empty() ? s.pressure : keys.max_value();
  const double R = s.air_balance;
  AirStep a;
  // The simulator applies the air only under an outside pressure (Simulator::net_pressure).
  if (!(P > 0.0) || !(R > 0.0) || !(s.dt > 0.0)) return a;
  const double V0 = signed_volume(x, faces);
  Positions g;
  volume_gradient(x, faces, g);
  Eigen::VectorXd vertex_area = Eigen::VectorXd::Zero(x.rows());
  double area = 0.0;
  for (Eigen::Index j = 0; j < faces.rows(); ++j) {
    const Vec3 c = x.row(faces(j, 2));
    const double A =
        0.5 * (Vec3(x.row(faces(j, 0))) - c).cross(Vec3(x.row(faces(j, 1))) - c).norm();
    area += A;
    for (int k = 0; k < 3; ++k) vertex_area(faces(j, k)) += A / 3.0;
  }
  if (!(V0 > 0.0) || !(area > 0.0)) return a;
  // A change dV of the volume changes the net pressure P(v) = P / (1 - R) (1 - R / v) by
  // K dV, K = P / ((1 - R) R V0) at v = R, and so the force on vertex i by K dV q_i along its
  // normal; the volume's acceleration is then -K dV sum_i |g_i| w_i q_i. The membrane and the
  // contacts are left out: they project the step onto the moves they allow, which in the masses'
  // metric only shortens g, and a buckled shell that keeps its area has |g_i| at most about the
  // rest value. So this is the largest omega the mode can have: below the bound it is stable.
  double sum = 0.0;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const double gi = g.row(i).norm();
    const double qi = s.pressure_model == PressureModel::Paper ? vertex_area(i) : gi;
    sum += gi * inv_mass(i) * qi;
  }
  a.move = P * s.dt * s.dt * sum / area;
  a.length = R * (1.0 - R) * V0 / area;
  a.limit = 2.0 * (2.0 - s.damping);
  return a;
}

std::string air_step_warning(const AirStep& a, const SimOptions& s) {
  const bool target = s.target_volume > 0.0 || !s.target_volume_schedule.empty();
  if (target || !a.overshoots()) return {};
  // (omega dt)^2 is proportional to pressure dt^2 / density (the masses scale with the density).
  const double over = a.omega_dt_squared() / a.limit;
  const Schedule& keys = s.pressure_schedule;
  const double P = keys.empty() ? s.pressure : keys.max_value();
  // Unit masses do not scale with the density.
  const std::string density =
      s.mass == MassModel::AreaLumped
          ? "`density` " + two_digits(s.density * over, true) + " or more, a "
          : std::string();
  const std::string fix = "A " + density + "`dt` " + two_digits(s.dt / std::sqrt(over), false) +
                          " or less (with more `frames` for the same time), or a `pressure` " +
                          two_digits(P / over, false) + " or less";
  return "the explicit pressure moves the shell by about " + general_text(a.move, 3) +
         " per step (P dt^2 / rho_A, normalized units), more than the " +
         general_text(a.limit * a.length, 3) +
         " that the enclosed air is sure to take back in one step (2 (2 - d) R (1 - R) V0 / A: d "
         "the `damping`, R the `air_balance` " +
         general_text(s.air_balance, 3) +
         ", V0 / A the rest volume over the area; docs/math/air-pressure.md section 4): near its "
         "balance V/V0 can then overshoot further every step, and swing for the whole run or blow "
         "up (a membrane that holds its area may still settle it: the bound is on the safe "
         "side). " +
         fix + " keeps the step within it (about: the mass scaling changes with them)";
}

}  // namespace shellcontract
