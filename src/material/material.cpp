// Free functions of the material interface (include/shellcontract/material.hpp).
#include "shellcontract/material.hpp"

#include <cmath>
#include <sstream>

#include "core/classic_locale.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {

// Plane stress (math-spec 6): a thin sheet of thickness h has sigma_33 = 0, which eliminates
// eps_33 and turns the 3D lambda = E nu / ((1 + nu)(1 - 2 nu)) into the membrane's
// lambda* = 2 mu lambda / (lambda + 2 mu) = E nu / (1 - nu^2); mu is unchanged. Multiplying by h
// gives moduli per unit rest area (N/m in SI), the units of psi. nu = 1/2 (incompressible) is
// allowed and gives lambda = 2 mu, the incompressible membrane of math-spec 6.4.
// Only mu and lambda are set; the other fields keep their MaterialParams defaults.
namespace {
void check_young_poisson_thickness(const char* who, double young, double poisson,
                                   double thickness) {
  // Written as negated "valid" tests so that NaN is rejected too.
  if (!(young > 0.0) || !std::isfinite(young) || !(thickness > 0.0) || !std::isfinite(thickness) ||
      !(poisson > -1.0 && poisson < 1.0)) {
    ClassicOStringStream msg;
    msg << who << ": need E > 0, h > 0 and -1 < nu < 1 (finite), got E = " << young
        << ", nu = " << poisson << ", h = " << thickness;
    throw UsageError(msg.str());
  }
}
}  // namespace

MaterialParams membrane_lame_from_young(double young, double poisson, double thickness) {
  check_young_poisson_thickness("membrane_lame_from_young", young, poisson, thickness);
  MaterialParams p;
  p.mu = young * thickness / (2.0 * (1.0 + poisson));
  p.lambda = young * thickness * poisson / (1.0 - poisson * poisson);
  return p;
}

double dihedral_k_bending_from_young(double young, double poisson, double thickness) {
  check_young_poisson_thickness("dihedral_k_bending_from_young", young, poisson, thickness);
  const double plate_rigidity =
      young * thickness * thickness * thickness / (12.0 * (1.0 - poisson * poisson));
  return plate_rigidity / 3.0;
}

}  // namespace shellcontract
