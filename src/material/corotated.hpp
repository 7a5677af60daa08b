// Corotated linear membrane (Sifakis & Barbic, "FEM simulation of 3D deformable solids",
// SIGGRAPH course 2012, section 5.3; math-spec 6.2).
#pragma once

#include "material/polar2.hpp"
#include "shellcontract/material.hpp"

namespace shellcontract {

/// psi = mu |F - R|_F^2 + lambda/2 (tr(R^T F) - 2)^2 with R from the rotation-variant polar
/// decomposition (material/polar2.hpp); P = 2 mu (F - R) + lambda (tr(R^T F) - 2) R.
/// tr(R^T F) = rho. The PK1 is exact: the dR/dF terms cancel (math-spec 6.2), because
/// d rho / dF = R.
///
/// frame_dependent() is true: rho^2 = tr C + 2 det F depends on the sign of det Fbar, i.e. on
/// the orientation s of the current frame (math-spec 4.2), not on C alone. An inverted triangle
/// (s = -1) therefore has a different energy than its mirror image, which is what makes the model
/// inversion-aware, and a collapsed triangle with an undefined frame must be skipped (math-spec
/// 11).
///
/// Singular spot: rho -> 0 (F = [[u, v], [v, -u]]). psi is continuous there
/// (|F - R|^2 = |F|^2 - 2 rho + 2 for every R in the family) but not differentiable; polar2's
/// guard returns R = I, so P stays finite (one element of the subdifferential's hull).
class Corotated final : public MembraneMaterial {
 public:
  /// @param p  uses mu and lambda (energy per unit rest area)
  explicit Corotated(const MaterialParams& p) : mu_(p.mu), lambda_(p.lambda) {}

  std::string name() const override { return "corotated"; }
  bool frame_dependent() const override { return true; }
  double mu() const { return mu_; }          ///< Lame mu (energy per unit rest area)
  double lambda() const { return lambda_; }  ///< plane-stress Lame lambda

  double psi(const Mat2& F, const ElementMaterialData&) const override {
    const Polar2 pd = polar2(F);
    const double t = pd.rho - 2.0;
    return mu_ * (F - pd.R).squaredNorm() + 0.5 * lambda_ * t * t;
  }

  Mat2 pk1(const Mat2& F, const ElementMaterialData&) const override {
    const Polar2 pd = polar2(F);
    return 2.0 * mu_ * (F - pd.R) + lambda_ * (pd.rho - 2.0) * pd.R;
  }

 private:
  double mu_;
  double lambda_;
};

}  // namespace shellcontract
