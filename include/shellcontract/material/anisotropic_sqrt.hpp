// Anisotropic "Sqrt" fibre energy (the name and formula of Kim, de Goes, Iben 2019's supplemental
// script; paper section 3.3; math-spec 7).
#pragma once

#include <cmath>

#include "shellcontract/material/material.hpp"
#include "shellcontract/material/polar2.hpp"

namespace shellcontract {

/// psi = mu_A/2 (sqrt(I5) - 1)^2, P = mu_A (1 - 1/sqrt(I5)) F a a^T, with I5 = |F a|^2 and
/// a = ElementMaterialData::fiber (unit, rest frame). The fibre-length spring: it resists a
/// change of |F a| and ignores its orientation.
///
/// frame_dependent() is false: psi depends only on I5 = a^T C a.
///
/// Guard: |F a| < FIBER_MIN_STRETCH gives P = 0 (direction undefined, see polar2.hpp); psi is
/// still evaluated exactly there (mu_A/2 at F a = 0).
class AnisotropicSqrt final : public MembraneMaterial {
 public:
  /// @param p  uses mu_aniso (energy per unit rest area)
  explicit AnisotropicSqrt(const MaterialParams& p) : mu_(p.mu_aniso) {}

  std::string name() const override { return "sqrt"; }
  bool frame_dependent() const override { return false; }

  /// @param d  d.fiber: unit fibre a in the rest frame
  double psi(const Mat2& F, const ElementMaterialData& d) const override {
    const double t = (F * d.fiber).norm() - 1.0;
    return 0.5 * mu_ * t * t;
  }

  Mat2 pk1(const Mat2& F, const ElementMaterialData& d) const override {
    const Vec2 Fa = F * d.fiber;
    const double len = Fa.norm();
    if (len < FIBER_MIN_STRETCH) return Mat2::Zero();  // direction undefined (math-spec 11)
    return mu_ * (1.0 - 1.0 / len) * Fa * d.fiber.transpose();
  }

 private:
  double mu_;
};

}  // namespace shellcontract
