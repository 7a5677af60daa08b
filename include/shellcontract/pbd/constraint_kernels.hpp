// Projection of one constraint: PBD "energy as constraint" (math-spec 9.1, paper eq. (5)) and
// XPBD with C = sqrt(2E) (math-spec 9.2). Pure functions of positions, inverse masses and rest
// data; Eigen only. Inline because they are the solver's inner loop.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>

#include "shellcontract/fem/triangle_element.hpp"
#include "shellcontract/pbd/constraints.hpp"

namespace shellcontract {

/// What a projection needs besides the constraint record.
struct ProjectionContext {
  double* x = nullptr;         ///< positions, 3 doubles per vertex (row-major #V by 3)
  const double* w = nullptr;   ///< inverse masses, one per vertex (0 = pinned)
  double alpha_tilde = 0.0;    ///< XPBD compliance / dt^2 (alpha = 1, math-spec 9.2)
  double energy_floor = 0.0;   ///< skip when E <= energy_floor * Abar (1e-16 mu, math-spec 9.1d)
  double orientation = 1.0;    ///< s of math-spec 4.2 (+1 default)
};

namespace detail {
inline Eigen::Map<Vec3> vertex(double* x, int i) { return Eigen::Map<Vec3>(x + 3 * i); }

/// Applies dx_i = -scale w_i g_i, scaled down so that no |dx_i| exceeds max_step
/// (math-spec 9.1d). N = number of stencil vertices.
template <int N>
inline void apply_step(double* x, const double* w, const std::array<int, N>& v,
                       const std::array<Vec3, N>& g, double scale, double max_step) {
  double longest_sq = 0.0;
  for (int i = 0; i < N; ++i) longest_sq = std::max(longest_sq, (scale * w[v[i]]) * (scale * w[v[i]]) * g[i].squaredNorm());
  if (longest_sq > max_step * max_step) scale *= max_step / std::sqrt(longest_sq);
  for (int i = 0; i < N; ++i) vertex(x, v[i]) -= (scale * w[v[i]]) * g[i];
}
}  // namespace detail

/// True when material M offers the frame-free C-form psi_second_pk(C, data, S) (math-spec 4.4).
template <class M, class = void>
struct has_second_pk : std::false_type {};
template <class M>
struct has_second_pk<M, std::void_t<decltype(std::declval<const M&>().psi_second_pk(
                            std::declval<const Mat2&>(), std::declval<const ElementMaterialData&>(),
                            std::declval<Mat2&>()))>> : std::true_type {};

/// Energy and vertex gradients of a membrane element through the C-form: F = Ds Dm^-1 (3x2),
/// C = F^T F, P3 = F S, [g1 g2] = Abar P3 Dm^-T (math-spec 4.4). No frame, no square root; exact
/// also for a collapsed current triangle. @return E
template <class M>
inline double membrane_energy_gradient_cform(const M& material, const MembraneConstraint& c,
                                             const Vec3& x1, const Vec3& x2, const Vec3& x3,
                                             std::array<Vec3, 3>& g) {
  Eigen::Matrix<double, 3, 2> Ds;
  Ds.col(0) = x1 - x3;
  Ds.col(1) = x2 - x3;
  const Eigen::Matrix<double, 3, 2> F = Ds * c.Dm_inv;
  const Mat2 C = F.transpose() * F;
  Mat2 S;
  const double psi = material.psi_second_pk(C, c.data, S);
  const Eigen::Matrix<double, 3, 2> H = c.rest_area * (F * S) * c.Dm_inv.transpose();
  g[0] = H.col(0);
  g[1] = H.col(1);
  g[2] = -g[0] - g[1];
  return c.rest_area * psi;
}

/// Projects one membrane (or anisotropic) constraint with material M.
/// PBD (lambda == nullptr): dx_i = -k E/G w_i g_i, G = sum w_i |g_i|^2 (math-spec 9.1), with the
/// skip and clamp guards of 9.1(d). XPBD (lambda != nullptr): C = sqrt(2E), division-free update
/// sigma = C (C + at lambda) / (G + at C^2), dx_i = -sigma w_i g_i, lambda += -C sigma (9.2).
/// @return true if the positions were changed.
template <class M>
inline bool project_membrane(const M& material, const MembraneConstraint& c, double stiffness,
                             const ProjectionContext& ctx, double* lambda) {
  const Vec3 x1 = detail::vertex(ctx.x, c.v[0]);
  const Vec3 x2 = detail::vertex(ctx.x, c.v[1]);
  const Vec3 x3 = detail::vertex(ctx.x, c.v[2]);
  std::array<Vec3, 3> g;
  double E;
  if constexpr (has_second_pk<M>::value) {
    // The orientation s does not matter for energies of C alone (math-spec 4.4).
    E = membrane_energy_gradient_cform(material, c, x1, x2, x3, g);
    if (!(E > ctx.energy_floor * c.rest_area)) return false;  // also rejects NaN
  } else {
    TriangleFrame fr;
    if (!triangle_frame(x1, x2, x3, c.Dm_inv, c.rest_area, ctx.orientation, fr)) return false;
    if (!fr.regular && material.frame_dependent()) return false;  // math-spec 11
    E = c.rest_area * material.psi(fr.F, c.data);
    if (!(E > ctx.energy_floor * c.rest_area)) return false;  // also rejects NaN
    lift_gradient(fr, material.pk1(fr.F, c.data), c.Dm_inv, c.rest_area, g[0], g[1], g[2]);
  }
  const double G = ctx.w[c.v[0]] * g[0].squaredNorm() + ctx.w[c.v[1]] * g[1].squaredNorm() +
                   ctx.w[c.v[2]] * g[2].squaredNorm();
  if (!(G > 1e-300)) return false;  // stationary point with E > 0 (math-spec 9.1d)
  if (lambda == nullptr) {
    detail::apply_step<3>(ctx.x, ctx.w, c.v, g, stiffness * E / G, c.max_step);
    return true;
  }
  const double C = std::sqrt(2.0 * E);
  const double at = ctx.alpha_tilde;
  const double sigma = C * (C + at * *lambda) / (G + at * C * C);
  *lambda -= C * sigma;
  for (int i = 0; i < 3; ++i) detail::vertex(ctx.x, c.v[i]) -= (sigma * ctx.w[c.v[i]]) * g[i];
  return true;
}

/// Projects one anisotropic (E_A) constraint with the paper's inward term (math-spec 9.3, PF):
/// dx_i = -(E_A / Gt) w_i (g_i + k_A n), Gt = sum w_i |g_i|^2 + k_A^2 sum w_i, where n is the
/// face's unit outward normal frozen for the solve. The cross term vanishes because every g_i
/// is in-plane (math-spec 4.4). Zero at rest (E_A = 0 gate). With k_A = 0 this is
/// project_membrane.
template <class A>
inline bool project_anisotropic_paper(const A& material, const MembraneConstraint& c, double k_a,
                                      const Vec3& n, const ProjectionContext& ctx) {
  if (k_a == 0.0) return project_membrane(material, c, 1.0, ctx, nullptr);
  const Vec3 x1 = detail::vertex(ctx.x, c.v[0]);
  const Vec3 x2 = detail::vertex(ctx.x, c.v[1]);
  const Vec3 x3 = detail::vertex(ctx.x, c.v[2]);
  std::array<Vec3, 3> g;
  double E;
  if constexpr (has_second_pk<A>::value) {
    E = membrane_energy_gradient_cform(material, c, x1, x2, x3, g);
  } else {
    TriangleFrame fr;
    if (!triangle_frame(x1, x2, x3, c.Dm_inv, c.rest_area, ctx.orientation, fr)) return false;
    if (!fr.regular && material.frame_dependent()) return false;
    E = c.rest_area * material.psi(fr.F, c.data);
    lift_gradient(fr, material.pk1(fr.F, c.data), c.Dm_inv, c.rest_area, g[0], g[1], g[2]);
  }
  if (!(E > ctx.energy_floor * c.rest_area)) return false;
  double G = 0.0;  // = sum w |g|^2 + k_A^2 sum w: the cross term is zero (g in-plane)
  for (int i = 0; i < 3; ++i) {
    g[i] += k_a * n;
    G += ctx.w[c.v[i]] * g[i].squaredNorm();
  }
  if (!(G > 1e-300)) return false;
  detail::apply_step<3>(ctx.x, ctx.w, c.v, g, E / G, c.max_step);
  return true;
}

/// Projects one isometric bending hinge. PBD closed form (math-spec 8.2):
/// dx_i = -k_B w_i K_i h / (2 sum_l w_l K_l^2), smooth at flat hinges. XPBD vector form with
/// beta = 3 k_B / (A0 + A1), C = sqrt(beta) h, lambda in R^3 (math-spec 8.2).
/// @param lambda  nullptr for PBD, else 3 doubles of accumulated multiplier
inline bool project_isometric_hinge(const IsometricHingeConstraint& c, double k_bending,
                                    const ProjectionContext& ctx, double* lambda) {
  const double* w = ctx.w;
  const Vec3 h = c.K(0) * detail::vertex(ctx.x, c.v[0]) + c.K(1) * detail::vertex(ctx.x, c.v[1]) +
                 c.K(2) * detail::vertex(ctx.x, c.v[2]) + c.K(3) * detail::vertex(ctx.x, c.v[3]);
  const double wK2 = w[c.v[0]] * c.K(0) * c.K(0) + w[c.v[1]] * c.K(1) * c.K(1) +
                     w[c.v[2]] * c.K(2) * c.K(2) + w[c.v[3]] * c.K(3) * c.K(3);
  if (!(wK2 > 1e-300)) return false;  // every stencil vertex pinned, or K = 0 (inactive hinge)
  if (lambda == nullptr) {
    const Vec3 base = h * (k_bending / (2.0 * wK2));
    // The clamp of 9.1(d): the largest |dx_i| is max_i w_i |K_i| |base|.
    double longest = 0.0;
    for (int i = 0; i < 4; ++i) longest = std::max(longest, w[c.v[i]] * std::abs(c.K(i)));
    longest *= base.norm();
    const double shrink = longest > c.max_step ? c.max_step / longest : 1.0;
    for (int i = 0; i < 4; ++i) detail::vertex(ctx.x, c.v[i]) -= (shrink * w[c.v[i]] * c.K(i)) * base;
    return true;
  }
  const double beta = k_bending * c.three_over_area;
  const double sqrt_beta = std::sqrt(beta);
  Eigen::Map<Vec3> lam(lambda);
  const Vec3 dlam = (-sqrt_beta * h - ctx.alpha_tilde * lam) / (beta * wK2 + ctx.alpha_tilde);
  lam += dlam;
  for (int i = 0; i < 4; ++i) detail::vertex(ctx.x, c.v[i]) += (w[c.v[i]] * sqrt_beta * c.K(i)) * dlam;
  return true;
}

/// Projects one dihedral hinge, E = k_B kappa (theta - theta_bar)^2 (math-spec 8.3).
/// PBD: dx_i = -k_B E/G w_i g_i with g = dE/dx for E without k_B (k_B is the correction
/// multiplier, reading R1 of math-spec 9.5). XPBD: C = sqrt(2 k_B kappa) (theta - theta_bar).
bool project_dihedral_hinge(const DihedralHingeConstraint& c, double k_bending,
                            const ProjectionContext& ctx, double* lambda);

}  // namespace shellcontract
