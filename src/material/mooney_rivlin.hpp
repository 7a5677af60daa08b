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
/// The code evaluates the same psi and P without cancellation (outside the clamp). The form
/// above adds and subtracts terms of order C10 that cancel at rest, which leaves rounding noise
/// of ~1e-16 C10 in psi where the energy of a rigid motion is ~1e-32 C10: enough to pass the PBD
/// solver's energy floor and move an unloaded shell. With u = |J|, eta = sign(J) and
///   Delta = I_C - 2 u = (F11 - eta F22)^2 + (F12 + eta F21)^2 = |F - eta cof F|^2 / 2,
/// (and u^2 + 2/u - 3 = (u - 1)^2 (u + 2) / u, 2 u - 3 + 1/u^2 = (u - 1)^2 (2 u + 1) / u^2)
///   psi = C10 (Delta + (u - 1)^2 (2 u + 1) / u^2) + C01 (Delta / u^2 + (u - 1)^2 (u + 2) / u),
///   P   = 2 (C10 + C01 / u^2) (F - eta cof F)
///         + 2 eta / u^3 (C10 (u^3 - 1) + C01 ((u^3 - 1) u - Delta)) cof F
/// (math-spec 6.4, "Evaluation"): psi is a sum of non-negative terms, each vanishing at rest, so
/// a rigid motion gives ~1e-32 C10 (as StVK's Green strain does) and F = I exactly gives 0.
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
    if (std::abs(J) < MOONEY_RIVLIN_MIN_ABS_J) {  // the clamp: far from rest, no cancellation
      const double IC = F.squaredNorm();
      const double g = barrier(J);
      return c10_ * (IC + g - 3.0) + c01_ * (J * J + IC * g - 3.0);
    }
    const Split v = split(F, J);
    const double m2 = (v.u - 1.0) * (v.u - 1.0);
    return c10_ * (v.delta + m2 * (2.0 * v.u + 1.0) / (v.u * v.u)) +
           c01_ * (v.delta / (v.u * v.u) + m2 * (v.u + 2.0) / v.u);
  }

  Mat2 pk1(const Mat2& F, const ElementMaterialData&) const override {
    const double J = F.determinant();
    Mat2 cof;
    cof << F(1, 1), -F(1, 0), -F(0, 1), F(0, 0);
    if (std::abs(J) < MOONEY_RIVLIN_MIN_ABS_J) {
      const double IC = F.squaredNorm();
      const double g = barrier(J);
      const double dg = barrier_derivative(J);
      return 2.0 * (c10_ + c01_ * g) * F + (c10_ * dg + 2.0 * c01_ * J + c01_ * IC * dg) * cof;
    }
    const Split v = split(F, J);
    const double u2 = v.u * v.u;
    const double q = (v.u - 1.0) * (u2 + v.u + 1.0);  // u^3 - 1
    const double a = 2.0 * (c10_ + c01_ / u2);
    const double b = 2.0 * v.eta / (u2 * v.u) * (c10_ * q + c01_ * (q * v.u - v.delta));
    return a * (F - v.eta * cof) + b * cof;
  }

 private:
  /// What the cancellation-free form needs (|J| >= J0): u = |J|, eta = sign(J) and
  /// Delta = I_C - 2 u as a sum of squares.
  struct Split {
    double u, eta, delta;
  };
  static Split split(const Mat2& F, double J) {
    const double eta = J < 0.0 ? -1.0 : 1.0;
    const double d0 = F(0, 0) - eta * F(1, 1), d1 = F(0, 1) + eta * F(1, 0);
    return {std::abs(J), eta, d0 * d0 + d1 * d1};
  }
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
