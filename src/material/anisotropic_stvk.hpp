// Anisotropic StVK fibre energy (Kim, de Goes, Iben 2019 and HOBAK ANISOTROPIC_STVK; paper
// section 3.3; math-spec 7).
#pragma once

#include "material/polar2.hpp"
#include "shellcontract/material.hpp"

namespace shellcontract {

/// psi = mu_A/2 (I5 - 1)^2, P = 2 mu_A (I5 - 1) F a a^T, with I5 = |F a|^2 and
/// a = ElementMaterialData::fiber (unit, rest frame).
///
/// frame_dependent() is false: psi depends only on I5 = a^T C a.
///
/// No guard is needed: there is no division, and as F a -> 0 the PK1 tends to 0 smoothly
/// (|P| = 2 mu_A |I5 - 1| |F a|). F a = 0 is a stationary point with psi = mu_A/2 > 0, which the
/// PBD kernel has to handle (math-spec 11, 9.1d), not the material.
class AnisotropicStvk final : public MembraneMaterial {
 public:
  /// @param p  uses mu_aniso (energy per unit rest area)
  explicit AnisotropicStvk(const MaterialParams& p) : mu_(p.mu_aniso) {}

  std::string name() const override { return "stvk"; }
  bool frame_dependent() const override { return false; }
  double mu() const { return mu_; }  ///< fibre stiffness mu_A (energy per unit rest area)

  /// @param d  d.fiber: unit fibre a in the rest frame
  double psi(const Mat2& F, const ElementMaterialData& d) const override {
    const double t = fiber_i5(F, d.fiber) - 1.0;
    return 0.5 * mu_ * t * t;
  }

  Mat2 pk1(const Mat2& F, const ElementMaterialData& d) const override {
    const Vec2 Fa = F * d.fiber;
    return 2.0 * mu_ * (Fa.squaredNorm() - 1.0) * Fa * d.fiber.transpose();
  }

  /// C-form (math-spec 4.4 shortcut, same hook as Stvk::psi_second_pk): psi and the second
  /// Piola-Kirchhoff stress S = 2 dpsi/dC = 2 mu_A (I5 - 1) a a^T from C = F^T F (2x2, rest
  /// frame), I5 = a^T C a, so that P3 = F S needs no current frame.
  /// @param C  right Cauchy-Green tensor (2x2, symmetric); @param d  d.fiber: unit a
  /// @param S  output, symmetric 2x2; @return psi
  double psi_second_pk(const Mat2& C, const ElementMaterialData& d, Mat2& S) const {
    const Vec2& a = d.fiber;
    const double t = a.dot(C * a) - 1.0;
    S = (2.0 * mu_ * t) * a * a.transpose();
    return 0.5 * mu_ * t * t;
  }

 private:
  double mu_;
};

}  // namespace shellcontract
