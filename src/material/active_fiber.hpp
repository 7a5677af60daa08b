// Active-fibre energy: the physically meaningful alternative to the paper's k_A term
// (math-spec 7 "R-option, active fiber", 12 items 5-6).
#pragma once

#include <cmath>
#include <string>

#include "core/decimal_text.hpp"
#include "material/polar2.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/material.hpp"

namespace shellcontract {

/// psi = mu_A/2 (sqrt(I5) - gamma sigma)^2, P = mu_A (1 - gamma sigma / sqrt(I5)) F a a^T,
/// with target fibre stretch gamma = MaterialParams::fiber_target in (0, 1], I5 = |F a|^2,
/// sigma = sign(I4) (math-spec 5) and a = ElementMaterialData::fiber (unit, rest frame).
/// The rest state is |F a| = gamma (with sigma = +1), not F = I: for gamma < 1 the region wants
/// to shorten along a, which on a curved shell pulls the surface inward through geometry while
/// conserving momentum (unlike k_A, math-spec 12 item 5). gamma = 1 is AnisotropicArap.
///
/// frame_dependent() is true, for the same reason as AnisotropicArap (sigma depends on the sign
/// of det Fbar).
///
/// Guard: |F a| < FIBER_MIN_STRETCH gives P = 0 (direction undefined, see polar2.hpp).
class ActiveFiber final : public MembraneMaterial {
 public:
  /// @param p  uses mu_aniso (energy per unit rest area) and fiber_target gamma (dimensionless)
  /// \throws UsageError unless 0 < gamma <= 1 (math-spec 7)
  explicit ActiveFiber(const MaterialParams& p) : mu_(p.mu_aniso), gamma_(p.fiber_target) {
    if (!(gamma_ > 0.0 && gamma_ <= 1.0)) {  // also rejects NaN
      throw UsageError("active-fiber: fiber target stretch must be in (0, 1], got " +
                       fixed_text(gamma_, 6));  // std::to_string's "%f", in the "C" locale
    }
  }

  std::string name() const override { return "active-fiber"; }
  bool frame_dependent() const override { return true; }
  double mu() const { return mu_; }  ///< fibre stiffness mu_A (energy per unit rest area)

  /// @param d  d.fiber: unit fibre a in the rest frame
  double psi(const Mat2& F, const ElementMaterialData& d) const override {
    const double t = (F * d.fiber).norm() - gamma_ * fiber_sign(F, d.fiber);
    return 0.5 * mu_ * t * t;
  }

  Mat2 pk1(const Mat2& F, const ElementMaterialData& d) const override {
    const Vec2 Fa = F * d.fiber;
    const double len = Fa.norm();
    if (len < FIBER_MIN_STRETCH) return Mat2::Zero();  // direction undefined (math-spec 11)
    return mu_ * (1.0 - gamma_ * fiber_sign(F, d.fiber) / len) * Fa * d.fiber.transpose();
  }

  /// Target fibre stretch gamma.
  double fiber_target() const { return gamma_; }

 private:
  double mu_;
  double gamma_;
};

}  // namespace shellcontract
