// Anisotropic "Sqrt" fibre energy (the name and formula of Kim, de Goes, Iben 2019's supplemental
// script; paper section 3.3; math-spec 7).
#pragma once

#include <algorithm>
#include <cmath>

#include "material/polar2.hpp"
#include "shellcontract/material.hpp"

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
  double mu() const { return mu_; }  ///< fibre stiffness mu_A (energy per unit rest area)

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

  /// C-form (math-spec 4.4 shortcut, same hook as Stvk::psi_second_pk): psi and the second
  /// Piola-Kirchhoff stress S = 2 dpsi/dC = mu_A (1 - 1/sqrt(I5)) a a^T from C = F^T F (2x2, rest
  /// frame), I5 = a^T C a, so that P3 = F S needs no current frame. Same guard as pk1(): S = 0
  /// when sqrt(I5) < FIBER_MIN_STRETCH (I5 is clamped at 0 against round-off first).
  /// @param C  right Cauchy-Green tensor (2x2, symmetric); @param d  d.fiber: unit a
  /// @param S  output, symmetric 2x2; @return psi
  double psi_second_pk(const Mat2& C, const ElementMaterialData& d, Mat2& S) const {
    const Vec2& a = d.fiber;
    const double len = std::sqrt(std::max(0.0, a.dot(C * a)));
    if (len < FIBER_MIN_STRETCH) {
      S.setZero();  // direction undefined (math-spec 11)
    } else {
      S = (mu_ * (1.0 - 1.0 / len)) * a * a.transpose();
    }
    const double t = len - 1.0;
    return 0.5 * mu_ * t * t;
  }

 private:
  double mu_;
};

}  // namespace shellcontract
