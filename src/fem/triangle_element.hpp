// Triangle kinematics for membrane energies: rest frame and Dm^-1 (math-spec 4.1), the current
// edge-aligned frame p and the 2x2 deformation gradient Fbar = p Ds Dm^-1 (4.2, 4.3), and the
// lift of a 2x2 PK1 to the three vertex gradients (4.4). Eigen only.
//
// Vertex order: a face (j1, j2, j3) is counter-clockwise seen from outside; both frames use the
// edge j1 - j3 as first axis, so Fbar = I exactly at rest (math-spec 4.3).
//
// The functions that run per element and per iteration are inline: the PBD solver calls them
// in its hot loop (their cost is what the ns-per-projection benchmark measures).
#pragma once

#include <cmath>

#include "shellcontract/types.hpp"

namespace shellcontract {

/// Rest data of one triangle, computed once from the rest positions.
struct TriangleRest {
  Mat2 Dm_inv = Mat2::Identity();  ///< inverse of the rest edge matrix in the rest 2D frame
  double area = 0.0;               ///< rest area Abar (> 0 unless degenerate)
  double min_edge = 0.0;           ///< shortest rest edge, for the PBD step clamp (math-spec 9.1d)
  Vec3 T1 = Vec3::UnitX();         ///< rest frame axis 1 (unit, along x1 - x3)
  Vec3 T2 = Vec3::UnitY();         ///< rest frame axis 2 (unit, Nbar x T1)
  bool degenerate = true;          ///< 2 Abar < 1e-10 lbar^2: no membrane energy (math-spec 11)
};

/// Relative area below which a rest triangle is degenerate: 2 Abar < ZERO_AREA_RATIO * lbar^2,
/// lbar = mean edge length of the triangle (math-spec 11, first row).
inline constexpr double ZERO_AREA_RATIO = 1e-10;

/// Computes the rest frame, Dm^-1 and rest area of triangle (x1, x2, x3) (math-spec 4.1).
/// A degenerate triangle (see ZERO_AREA_RATIO) gets degenerate = true and Dm_inv = I.
TriangleRest triangle_rest(const Vec3& x1, const Vec3& x2, const Vec3& x3);

/// Current frame and in-plane deformation gradient of one triangle.
struct TriangleFrame {
  Mat2 F;          ///< Fbar = p Ds Dm^-1 (2x2), upper triangular when the frame is regular
  Vec3 t1, t2;     ///< rows of p (unit, orthogonal)
  double area;     ///< current area A
  bool regular;    ///< false when the current area is near zero and t2 was chosen arbitrarily
};

/// Relative current area below which the frame is not regular: A < FRAME_AREA_RATIO * Abar
/// (math-spec 11, "current triangle near zero area").
inline constexpr double FRAME_AREA_RATIO = 1e-10;

/// Builds p and Fbar for the current positions (math-spec 4.2-4.3).
/// @param s  orientation: +1 (default model), -1 when the inversion-aware mode counts the
///           triangle as inverted; det(Fbar) = s A / Abar.
/// @return false only when all three vertices coincide (no frame at all).
/// \note When A < FRAME_AREA_RATIO Abar the frame is not regular: t2 is any unit vector normal to
/// t1. Fbar is then still exact for energies of C = F^T F (the columns of F lie along t1), but
/// frame-dependent energies must skip the element.
inline bool triangle_frame(const Vec3& x1, const Vec3& x2, const Vec3& x3, const Mat2& Dm_inv,
                           double rest_area, double s, TriangleFrame& out) {
  const Vec3 e1 = x1 - x3;
  const Vec3 e2 = x2 - x3;
  const Vec3 N = e1.cross(e2);
  const double twice_area = N.norm();
  out.area = 0.5 * twice_area;
  const double len1 = e1.norm();
  if (out.area >= FRAME_AREA_RATIO * rest_area && len1 > 0.0) {
    out.regular = true;
    out.t1 = e1 / len1;
    out.t2 = (s / twice_area) * N.cross(out.t1);  // (s n) x t1
    Mat2 pDs;
    pDs << len1, e2.dot(out.t1), 0.0, s * twice_area / len1;
    out.F.noalias() = pDs * Dm_inv;
    return true;
  }
  // Collapsed triangle: pick t1 along the longer edge, t2 normal to it.
  out.regular = false;
  const double len2 = e2.norm();
  if (len1 <= 0.0 && len2 <= 0.0) return false;
  out.t1 = len1 >= len2 ? Vec3(e1 / len1) : Vec3(e2 / len2);
  Vec3 axis = Vec3::Zero();
  Eigen::Index k;
  out.t1.cwiseAbs().minCoeff(&k);
  axis(k) = 1.0;
  out.t2 = out.t1.cross(axis).normalized();  // |t1 x e_k| >= sqrt(2/3): no zero division
  Mat2 pDs;
  pDs << out.t1.dot(e1), out.t1.dot(e2), out.t2.dot(e1), out.t2.dot(e2);
  out.F.noalias() = pDs * Dm_inv;
  return true;
}

/// Lifts a 2x2 PK1 Pbar to the vertex gradients of E = Abar psi (math-spec 4.4, paper eq. (1)):
/// [g1 g2] = Abar p^T Pbar Dm^-T, g3 = -g1 - g2. Exact for rotation-invariant psi.
inline void lift_gradient(const TriangleFrame& fr, const Mat2& P, const Mat2& Dm_inv,
                          double rest_area, Vec3& g1, Vec3& g2, Vec3& g3) {
  const Mat2 H = rest_area * P * Dm_inv.transpose();  // 2x2 in-plane gradient of edges 1, 2
  g1 = fr.t1 * H(0, 0) + fr.t2 * H(1, 0);
  g2 = fr.t1 * H(0, 1) + fr.t2 * H(1, 1);
  g3 = -g1 - g2;
}

/// Energy E = Abar psi(Fbar) and vertex gradients of one triangle for a material M
/// (any type with psi/pk1 as in shellcontract/material.hpp).
/// @return false when the element contributes nothing (degenerate rest triangle, all vertices
/// coincident, or frame-dependent material on a collapsed triangle); E and g are then zero.
template <class M, class D>
bool element_energy_gradient(const M& material, const D& data, const Vec3& x1, const Vec3& x2,
                             const Vec3& x3, const TriangleRest& rest, double s, double& E,
                             Vec3& g1, Vec3& g2, Vec3& g3) {
  E = 0.0;
  g1.setZero();
  g2.setZero();
  g3.setZero();
  if (rest.degenerate) return false;
  TriangleFrame fr;
  if (!triangle_frame(x1, x2, x3, rest.Dm_inv, rest.area, s, fr)) return false;
  if (!fr.regular && material.frame_dependent()) return false;
  E = rest.area * material.psi(fr.F, data);
  lift_gradient(fr, material.pk1(fr.F, data), rest.Dm_inv, rest.area, g1, g2, g3);
  return true;
}

}  // namespace shellcontract
