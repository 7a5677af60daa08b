#include "sim/mass_scaling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/decimal_text.hpp"

namespace shellcontract {

MassScaling scale_masses_for_pressure(const Positions& x, const Faces& faces, double pressure,
                                      double dt, Eigen::VectorXd& inv_mass) {
  MassScaling result;
  result.largest_unscaled_dt = std::numeric_limits<double>::infinity();
  const double P = std::abs(pressure);
  if (!(P > 0.0) || !(dt > 0.0)) return result;
  // Perimeter of each vertex's one-ring: the edge opposite the vertex in each of its faces.
  // d f_i / d x_k = P / 6 [skew(...)] sums, over the ring, to at most P / 3 times it.
  Eigen::VectorXd ring = Eigen::VectorXd::Zero(x.rows());
  for (Eigen::Index j = 0; j < faces.rows(); ++j)
    for (int k = 0; k < 3; ++k) {
      const int a = faces(j, (k + 1) % 3), b = faces(j, (k + 2) % 3);
      ring(faces(j, k)) += (x.row(a) - x.row(b)).norm();
    }
  // The scaling evens out the light vertices; it never makes one heavier than the mean vertex,
  // so a pressure or time step far too large for the whole mesh still ends in a reported blow-up.
  double mean_mass = 0.0;
  std::size_t massive = 0;
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    if (inv_mass(i) > 0.0) {
      mean_mass += 1.0 / inv_mass(i);
      ++massive;
    }
  if (massive == 0) return result;
  mean_mass /= static_cast<double>(massive);
  const double s = dt / MAX_PRESSURE_OMEGA_DT;
  const double factor = s * s * P / 3.0;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    if (!(inv_mass(i) > 0.0)) continue;
    const double mass = 1.0 / inv_mass(i);
    // The mean caps the floor: a vertex at or above it is never raised, at any step. Below it the
    // floor grows with dt^2 and passes the mass at dt * sqrt(mass / floor).
    if (mass < mean_mass && ring(i) > 0.0)
      result.largest_unscaled_dt =
          std::min(result.largest_unscaled_dt, dt * std::sqrt(mass / (factor * ring(i))));
    const double min_mass = std::min(factor * ring(i), mean_mass);
    if (inv_mass(i) * min_mass > 1.0) {
      result.largest_factor = std::max(result.largest_factor, inv_mass(i) * min_mass);
      inv_mass(i) = 1.0 / min_mass;
      ++result.raised;
    }
  }
  return result;
}

std::string mass_scaling_warning(const MassScaling& m, std::size_t vertices, double dt) {
  if (vertices == 0 ||
      !(static_cast<double>(m.raised) > MASS_SCALING_NOTE_SHARE * static_cast<double>(vertices)))
    return {};
  std::string text = std::to_string(m.raised) + " of " + std::to_string(vertices) + " vertices (" +
                     general_text(100.0 * static_cast<double>(m.raised) / vertices, 2) +
                     " %) are too light for the explicit pressure at `dt` " + general_text(dt, 6) +
                     ": their masses were raised, up to " + general_text(m.largest_factor, 3) +
                     " times (docs/design/defaults.md, \"Mass scaling\"), so the motion depends on "
                     "`dt`.";
  // Two significant digits, rounded down: at the value shown no vertex is raised.
  if (std::isfinite(m.largest_unscaled_dt) && m.largest_unscaled_dt > 0.0) {
    const double unit = std::pow(10.0, std::floor(std::log10(m.largest_unscaled_dt)) - 1.0);
    text += " At `dt` " + general_text(std::floor(m.largest_unscaled_dt / unit) * unit, 2) +
            " or less none is raised (with more `frames` for the same time);";
  }
  return text + " `pressure` 0 with `target_volume` contracts without the explicit load";
}

}  // namespace shellcontract
