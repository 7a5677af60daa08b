// 2x2 rotation-variant polar decomposition, the fibre invariants I4/I5 and the robust
// sign(I4) (math-spec 5; Kim, de Goes, Iben 2019 "Anisotropic elasticity for inversion-safety
// and element rehabilitation", and HOBAK's rotation-variant SVD).
//
// All functions take the 2x2 in-plane deformation gradient Fbar of shellcontract/material.hpp
// (current edge-aligned frame in its rows, rest frame in its columns; dimensionless) and, for the
// fibre invariants, the unit fibre direction a in the REST frame (math-spec 7).
//
// "Rotation-variant" means reflections go into the stretch S, never into R: R is always a proper
// rotation (det R = +1), and S = R^T F is symmetric with a negative eigenvalue when det F < 0.
// The classical polar formula R ~ F + sign(det F) cof F would give det R = -1 for an inverted F
// and must not be used for I4 (math-spec 5).
#pragma once

#include <cmath>

#include "shellcontract/types.hpp"

namespace shellcontract {

/// Relative size of rho = |(c, d)| below which the polar rotation is undefined and R = I is used:
/// rho <= POLAR_DEGENERACY_RATIO * |F|_F (math-spec 5, 11). Only F = [[u, v], [v, -u]] has
/// rho = 0 exactly.
inline constexpr double POLAR_DEGENERACY_RATIO = 1e-12;

/// Relative tolerance of the sign(I4) tie rule: |I5 + det F| <= SIGN_TIE_RATIO (I5 + |det F|)
/// counts as a tie and gives +1 (math-spec 5, 12 item 18).
inline constexpr double SIGN_TIE_RATIO = 1e-12;

/// |F a| below which the fibre direction F a / |F a| is undefined (math-spec 11, "I5 -> 0").
/// The anisotropic ARAP, Sqrt and active-fibre PK1 mu (1 - k/|Fa|) F a a^T stays bounded there
/// (its norm tends to mu |k|) but has no limit direction, so those models return P = 0 below
/// this threshold (and the PBD kernel then skips the projection). Dimensionless.
inline constexpr double FIBER_MIN_STRETCH = 1e-8;

/// Result of polar2(): F = R S with R in SO(2) and S symmetric.
struct Polar2 {
  Mat2 R = Mat2::Identity();  ///< proper rotation (det R = +1); I when degenerate
  double rho = 0.0;           ///< sqrt(c^2 + d^2) = tr(R^T F) = tr S (0 <= rho)
  bool degenerate = true;     ///< rho <= POLAR_DEGENERACY_RATIO |F|_F, R = I was used
};

/// Rotation-variant polar decomposition of a 2x2 matrix (math-spec 5).
/// c = F11 + F22, d = F21 - F12, rho = sqrt(c^2 + d^2), R = [[c, -d], [d, c]] / rho.
/// @param F  2x2 deformation gradient Fbar (any determinant sign)
/// @return R, rho and whether the R = I guard was taken
/// \note R maximises tr(R^T F) over SO(2), so tr(R^T F) = rho. When det F < 0 the reflection
/// lands in S = R^T F (one negative eigenvalue), never in R.
inline Polar2 polar2(const Mat2& F) {
  Polar2 out;
  const double c = F(0, 0) + F(1, 1);
  const double d = F(1, 0) - F(0, 1);
  out.rho = std::sqrt(c * c + d * d);
  // Guard the division by rho (math-spec 5): relative to |F| so that it is scale-free; F = 0
  // gives 0 <= 0 and takes the guard too.
  if (out.rho <= POLAR_DEGENERACY_RATIO * F.norm()) {
    out.R.setIdentity();
    out.degenerate = true;
    return out;
  }
  out.degenerate = false;
  out.R << c / out.rho, -d / out.rho, d / out.rho, c / out.rho;
  return out;
}

/// Fibre invariant I5 = |F a|^2 (math-spec 5, 7).
/// @param F  2x2 Fbar; @param a  unit fibre in the rest frame
/// \note |Fbar a| = |F a| for the 3x2 F because the columns of F lie in the current plane (4.3).
inline double fiber_i5(const Mat2& F, const Vec2& a) { return (F * a).squaredNorm(); }

/// Fibre invariant I4 = a^T S a with S = R^T F from polar2() (math-spec 5), by the closed form
/// I4 = (I5 + det F) / rho (Cayley-Hamilton: S = (C + det F I) / rho).
/// @param F  2x2 Fbar (any determinant sign); @param a  unit fibre in the rest frame
/// @return I4 (dimensionless). When polar2's guard is taken (rho ~ 0) it returns a^T F a, the
/// value of a^T S a for the R = I that polar2 then uses.
/// @pre |a| = 1 (the closed form uses a^T a = 1)
inline double fiber_i4(const Mat2& F, const Vec2& a) {
  const Polar2 pd = polar2(F);
  if (pd.degenerate) return a.dot(F * a);  // R = I, S = F (math-spec 5 guard)
  return (fiber_i5(F, a) + F.determinant()) / pd.rho;
}

/// Robust sign(I4) in {-1, +1} without polar decomposition or division (math-spec 5):
/// sign(I4) = sign(I5 + det F) because rho > 0. Ties |I5 + det F| <= SIGN_TIE_RATIO (I5 + |det F|)
/// give +1 (math-spec 12 item 18; HOBAK would give -1, which differs on a null set only).
/// @param F  2x2 Fbar; @param a  unit fibre in the rest frame
/// \note With the default orientation s = +1, det Fbar = A / Abar > 0, so this is +1 for every
/// non-degenerate triangle; -1 needs the inversion-aware mode (math-spec 4.2).
inline double fiber_sign(const Mat2& F, const Vec2& a) {
  const double i5 = fiber_i5(F, a);
  const double J = F.determinant();
  const double x = i5 + J;
  if (std::abs(x) <= SIGN_TIE_RATIO * (i5 + std::abs(J))) return 1.0;
  return x > 0.0 ? 1.0 : -1.0;
}

}  // namespace shellcontract
