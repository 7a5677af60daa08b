// Saint Venant-Kirchhoff membrane (paper section 3.1, eq. (1); math-spec 6.1).
#pragma once

#include "shellcontract/material.hpp"

namespace shellcontract {

/// psi = mu |E|_F^2 + lambda/2 tr(E)^2 with Green strain E = (F^T F - I)/2;
/// P = F (2 mu E + lambda tr(E) I). Depends on F only through C = F^T F.
class Stvk final : public MembraneMaterial {
 public:
  explicit Stvk(const MaterialParams& p) : mu_(p.mu), lambda_(p.lambda) {}

  std::string name() const override { return "stvk"; }
  double mu() const { return mu_; }          ///< Lame mu (energy per unit rest area)
  double lambda() const { return lambda_; }  ///< plane-stress Lame lambda
  bool frame_dependent() const override { return false; }

  double psi(const Mat2& F, const ElementMaterialData&) const override {
    const Mat2 E = green_strain(F);
    const double tr = E.trace();
    return mu_ * E.squaredNorm() + 0.5 * lambda_ * tr * tr;
  }

  Mat2 pk1(const Mat2& F, const ElementMaterialData&) const override {
    const Mat2 E = green_strain(F);
    return F * (2.0 * mu_ * E + lambda_ * E.trace() * Mat2::Identity());
  }

  /// C-form (math-spec 4.4 "shortcut"): psi and the second Piola-Kirchhoff stress
  /// S = 2 dpsi/dC = 2 mu E + lambda tr(E) I from C = F^T F, so that P3 = F S needs no frame.
  /// The PBD kernel uses this path when a material provides it.
  double psi_second_pk(const Mat2& C, const ElementMaterialData&, Mat2& S) const {
    const double e00 = 0.5 * (C(0, 0) - 1.0), e11 = 0.5 * (C(1, 1) - 1.0);
    const double e01 = 0.5 * C(0, 1);
    const double tr = e00 + e11;
    S(0, 0) = 2.0 * mu_ * e00 + lambda_ * tr;
    S(1, 1) = 2.0 * mu_ * e11 + lambda_ * tr;
    S(0, 1) = S(1, 0) = 2.0 * mu_ * e01;
    return mu_ * (e00 * e00 + e11 * e11 + 2.0 * e01 * e01) + 0.5 * lambda_ * tr * tr;
  }

 private:
  static Mat2 green_strain(const Mat2& F) {
    return 0.5 * (F.transpose() * F - Mat2::Identity());
  }
  double mu_;
  double lambda_;
};

}  // namespace shellcontract
