// Incompressible Mooney-Rivlin membrane in plane stress (math-spec 6.4; the paper names the
// model but gives no formula, 12 item 9).
#pragma once

#include <cmath>

#include "shellcontract/material.hpp"

namespace shellcontract {

/// |det F| below which the J^-2 barrier is continued linearly in |J| (math-spec 11: "for MR
/// clamp J >= 1e-6"). Dimensionless (J = A / Abar).
inline constexpr double MOONEY_RIVLIN_MIN_ABS_J = 1e-6;

/// Out-of-plane stretch 1/|J| makes the membrane incompressible; with J = det F, I_C = tr C:
///   psi = C10 (I_C + J^-2 - 3) + C01 (J^2 + I_C J^-2 - 3),
///   P   = 2 (C10 + C01 J^-2) F + (-2 C10 J^-3 + 2 C01 J - 2 C01 I_C J^-3) cof F,
/// cof F = [[F22, -F21], [-F12, F11]] = J F^-T (math-spec 6.4).
/// Small strain: shear modulus mu = 2 (C10 + C01) and, because the membrane is incompressible in
/// plane stress, plane-stress lambda = 2 mu (not infinity: the thickness absorbs the area change).
///
/// frame_dependent() is false: psi is even in J and depends only on tr C and J^2 = det C, so it
/// cannot see inversion (math-spec 6.4, 11) and is exact on a collapsed triangle's C-path.
///
/// Clamp (math-spec 11), written so that P stays the exact gradient of psi: for
/// |J| < J0 = MOONEY_RIVLIN_MIN_ABS_J the barrier g(J) = J^-2 is replaced by its first-order
/// Taylor continuation in |J| at J0, g = 3/J0^2 - 2|J|/J0^3 (so dg/dJ = -2 sign(J)/J0^3, the
/// barrier slope at |J| = J0). psi is then finite at J = 0 (at most ~3 C10 / J0^2), C1 across
/// |J| = J0, and P keeps pushing |J| up instead of blowing up or vanishing. At J = 0 exactly
/// sign(J) = +1 is used (psi has a kink there; the subgradient choice is arbitrary).
///
/// No C-form psi_second_pk() (the frame-free hook Stvk offers the PBD kernel): under the clamp
/// dpsi/d(det C) ~ 1/(J0^3 |J|) diverges as det C -> 0 while P = F S stays finite, so S is
/// unusable exactly where the C-path would be needed (collapsed triangles). The F-form is exact
/// on the collapsed-triangle frame too, since psi depends on C only.
class MooneyRivlin final : public MembraneMaterial {
 public:
  /// @param p  uses c10 and c01 (energy per unit rest area)
  explicit MooneyRivlin(const MaterialParams& p) : c10_(p.c10), c01_(p.c01) {}

  std::string name() const override { return "mooney-rivlin"; }
  bool frame_dependent() const override { return false; }
  double c10() const { return c10_; }  ///< C10 (energy per unit rest area)
  double c01() const { return c01_; }  ///< C01 (energy per unit rest area)

  double psi(const Mat2& F, const ElementMaterialData&) const override {
    const double J = F.determinant();
    const double IC = F.squaredNorm();
    const double g = barrier(J);
    return c10_ * (IC + g - 3.0) + c01_ * (J * J + IC * g - 3.0);
  }

  Mat2 pk1(const Mat2& F, const ElementMaterialData&) const override {
    const double J = F.determinant();
    const double IC = F.squaredNorm();
    const double g = barrier(J);
    const double dg = barrier_derivative(J);
    Mat2 cof;
    cof << F(1, 1), -F(1, 0), -F(0, 1), F(0, 0);
    return 2.0 * (c10_ + c01_ * g) * F + (c10_ * dg + 2.0 * c01_ * J + c01_ * IC * dg) * cof;
  }

 private:
  /// g(J) = J^-2, continued linearly in |J| below J0 (see class comment).
  static double barrier(double J) {
    constexpr double J0 = MOONEY_RIVLIN_MIN_ABS_J;
    const double a = std::abs(J);
    if (a >= J0) return 1.0 / (J * J);
    return 3.0 / (J0 * J0) - 2.0 * a / (J0 * J0 * J0);
  }
  /// dg/dJ; sign(0) = +1 at the kink.
  static double barrier_derivative(double J) {
    constexpr double J0 = MOONEY_RIVLIN_MIN_ABS_J;
    if (std::abs(J) >= J0) return -2.0 / (J * J * J);
    return (J < 0.0 ? 2.0 : -2.0) / (J0 * J0 * J0);
  }
  double c10_;
  double c01_;
};

}  // namespace shellcontract
