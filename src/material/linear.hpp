// Linear (small-strain) membrane (Sifakis & Barbic 2012, section 3.2; math-spec 6.3).
#pragma once

#include "shellcontract/material.hpp"

namespace shellcontract {

/// eps = (F + F^T)/2 - I, psi = mu |eps|_F^2 + lambda/2 tr(eps)^2,
/// P = mu (F + F^T - 2 I) + lambda (tr F - 2) I.
///
/// Not rotation-invariant: psi(Q F) != psi(F). Used with the edge-aligned current frame
/// (Fbar upper triangular) it is a QR-type corotated model: invariant to rigid motion of the
/// triangle but dependent on which edge defines t1 (math-spec 6.3, 12 item 20). Its lifted
/// gradient p^T P is the gradient with p frozen, not the exact gradient (math-spec 4.4).
///
/// frame_dependent() is true: psi depends on the in-plane orientation of the frame, so a
/// collapsed triangle whose t2 is arbitrary must be skipped (math-spec 11).
class Linear final : public MembraneMaterial {
 public:
  /// @param p  uses mu and lambda (energy per unit rest area)
  explicit Linear(const MaterialParams& p) : mu_(p.mu), lambda_(p.lambda) {}

  std::string name() const override { return "linear"; }
  bool frame_dependent() const override { return true; }
  double mu() const { return mu_; }          ///< Lame mu (energy per unit rest area)
  double lambda() const { return lambda_; }  ///< plane-stress Lame lambda

  double psi(const Mat2& F, const ElementMaterialData&) const override {
    const Mat2 eps = small_strain(F);
    const double tr = eps.trace();
    return mu_ * eps.squaredNorm() + 0.5 * lambda_ * tr * tr;
  }

  Mat2 pk1(const Mat2& F, const ElementMaterialData&) const override {
    return mu_ * (F + F.transpose() - 2.0 * Mat2::Identity()) +
           lambda_ * (F.trace() - 2.0) * Mat2::Identity();
  }

 private:
  static Mat2 small_strain(const Mat2& F) { return 0.5 * (F + F.transpose()) - Mat2::Identity(); }
  double mu_;
  double lambda_;
};

}  // namespace shellcontract
