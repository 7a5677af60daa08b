// Anisotropic ARAP fibre energy (Kim, de Goes, Iben 2019, section 4 and its supplemental code;
// HOBAK ANISOTROPIC_ARAP; paper section 3.3; math-spec 7).
#pragma once

#include <cmath>

#include "material/polar2.hpp"
#include "shellcontract/material.hpp"

namespace shellcontract {

/// psi = mu_A/2 (sqrt(I5) - sigma)^2, P = mu_A (1 - sigma / sqrt(I5)) F a a^T, with
/// I5 = |F a|^2, sigma = sign(I4) from fiber_sign() (math-spec 5) and a =
/// ElementMaterialData::fiber (unit, rest frame). sigma is piecewise constant, so P is the exact
/// derivative away from the surface I4 = 0, where psi jumps by 2 mu_A sqrt(I5) (math-spec 7).
///
/// frame_dependent() is true: sigma = sign(I5 + det F) depends on the sign of det Fbar, i.e. on
/// the orientation s of the current frame (math-spec 4.2, 5). With s = +1, sigma = +1 and the
/// model equals AnisotropicSqrt; it differs only in the inversion-aware mode (math-spec 12 item 7).
///
/// Guard: |F a| < FIBER_MIN_STRETCH gives P = 0 (direction undefined, see polar2.hpp); psi is
/// still evaluated exactly there.
class AnisotropicArap final : public MembraneMaterial {
 public:
  /// @param p  uses mu_aniso (energy per unit rest area)
  explicit AnisotropicArap(const MaterialParams& p) : mu_(p.mu_aniso) {}

  std::string name() const override { return "arap"; }
  bool frame_dependent() const override { return true; }
  double mu() const { return mu_; }  ///< fibre stiffness mu_A (energy per unit rest area)

  /// @param d  d.fiber: unit fibre a in the rest frame
  double psi(const Mat2& F, const ElementMaterialData& d) const override {
    const double t = (F * d.fiber).norm() - fiber_sign(F, d.fiber);
    return 0.5 * mu_ * t * t;
  }

  Mat2 pk1(const Mat2& F, const ElementMaterialData& d) const override {
    const Vec2 Fa = F * d.fiber;
    const double len = Fa.norm();
    if (len < FIBER_MIN_STRETCH) return Mat2::Zero();  // direction undefined (math-spec 11)
    return mu_ * (1.0 - fiber_sign(F, d.fiber) / len) * Fa * d.fiber.transpose();
  }

 private:
  double mu_;
};

}  // namespace shellcontract
