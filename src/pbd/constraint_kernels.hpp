// Projection of one constraint: PBD "energy as constraint" (math-spec 9.1, paper eq. (5)) and
// XPBD with C = sqrt(2E) (math-spec 9.2). Pure functions of positions, inverse masses and rest
// data; Eigen only. Inline because they are the solver's inner loop.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>

#include "fem/triangle_element.hpp"
#include "pbd/constraints.hpp"

namespace shellcontract {

/// What a projection needs besides the constraint record.
struct ProjectionContext {
  double* x = nullptr;         ///< positions, 3 doubles per vertex (row-major #V by 3)
  const double* w = nullptr;   ///< inverse masses, one per vertex (0 = pinned)
  double alpha_tilde = 0.0;    ///< XPBD compliance / dt^2 (alpha = 1, math-spec 9.2)
  double energy_floor = 0.0;   ///< skip when E <= energy_floor * Abar (skip_energy_floor)
  double orientation = 1.0;    ///< s of math-spec 4.2 (+1 default)
};

/// The skip floor of math-spec 9.1(d), 1e-16 times the stiffness of the energies in use alone:
/// a parameter the run warns has no effect (--c10 under StVK, --mu-a without --aniso) must not
/// move the floor, and so the result.
inline double skip_energy_floor(MaterialKind material, AnisoKind aniso, const MaterialParams& p) {
  double scale =
      material == MaterialKind::MooneyRivlin ? 2.0 * (p.c10 + p.c01) : std::max(p.mu, p.lambda);
  if (aniso != AnisoKind::None) scale = std::max(scale, p.mu_aniso);
  return 1e-16 * scale;
}

/// Building blocks of the inline projection kernels below (vertex access, scaled updates, the
/// energy gradient of any material): in this header because the kernels are inline for speed.
namespace kernel_parts {
inline Eigen::Map<Vec3> vertex(double* x, int i) { return Eigen::Map<Vec3>(x + 3 * i); }

/// x_i -= s g, written out: the same roundings as vertex(x, i) -= s * g, but GCC did not inline
/// Eigen's operator-= on a Map (a visible share of a bear run's samples in a call of its own;
/// lab/history.md).
inline void subtract_scaled(double* x, int i, double s, const Vec3& g) {
  double* p = x + 3 * static_cast<std::ptrdiff_t>(i);
  p[0] -= s * g[0];
  p[1] -= s * g[1];
  p[2] -= s * g[2];
}
/// x_i += s g, as subtract_scaled (the XPBD updates).
inline void add_scaled(double* x, int i, double s, const Vec3& g) {
  double* p = x + 3 * static_cast<std::ptrdiff_t>(i);
  p[0] += s * g[0];
  p[1] += s * g[1];
  p[2] += s * g[2];
}

/// The factor in (0, 1] that keeps every |dx_i| = |scale w_i g_i| within max_step (math-spec
/// 9.1d): 1 unless the longest step is over it. N = number of stencil vertices.
template <int N>
inline double step_clamp_factor(const double* w, const std::array<int, N>& v,
                                const std::array<Vec3, N>& g, double scale, double max_step) {
  double longest_sq = 0.0;
  for (int i = 0; i < N; ++i) longest_sq = std::max(longest_sq, (scale * w[v[i]]) * (scale * w[v[i]]) * g[i].squaredNorm());
  return longest_sq > max_step * max_step ? max_step / std::sqrt(longest_sq) : 1.0;
}

/// Applies dx_i = -scale w_i g_i, scaled down so that no |dx_i| exceeds max_step
/// (math-spec 9.1d). N = number of stencil vertices.
template <int N>
inline void apply_step(double* x, const double* w, const std::array<int, N>& v,
                       const std::array<Vec3, N>& g, double scale, double max_step) {
  scale *= step_clamp_factor<N>(w, v, g, scale, max_step);
  for (int i = 0; i < N; ++i) subtract_scaled(x, v[i], scale * w[v[i]], g[i]);
}
}  // namespace kernel_parts

/// True when material M offers the frame-free C-form psi_second_pk(C, data, S) (math-spec 4.4).
template <class M, class = void>
struct has_second_pk : std::false_type {};
template <class M>
struct has_second_pk<M, std::void_t<decltype(std::declval<const M&>().psi_second_pk(
                            std::declval<const Mat2&>(), std::declval<const ElementMaterialData&>(),
                            std::declval<Mat2&>()))>> : std::true_type {};

/// Energy and vertex gradients of a membrane element through the C-form: F = Ds Dm^-1 (3x2),
/// C = F^T F, P3 = F S, [g1 g2] = Abar P3 Dm^-T (math-spec 4.4). No frame, no square root; exact
/// also for a collapsed current triangle. Written out for the upper-triangular Dm^-1 of
/// PackedMembrane (the solver's inner loop). @return E
template <class M>
inline double membrane_energy_gradient_cform(const M& material, const PackedMembrane& c,
                                             const ElementMaterialData& data, const Vec3& x1,
                                             const Vec3& x2, const Vec3& x3,
                                             std::array<Vec3, 3>& g) {
  const Vec3 e1 = x1 - x3;
  const Vec3 e2 = x2 - x3;
  const Vec3 f0 = e1 * c.dm00;                  // F = [e1 e2] Dm^-1, Dm^-1(1, 0) = 0
  const Vec3 f1 = e1 * c.dm01 + e2 * c.dm11;
  Mat2 C;
  C(0, 0) = f0.dot(f0);
  C(1, 1) = f1.dot(f1);
  C(0, 1) = C(1, 0) = f0.dot(f1);
  Mat2 S;
  const double psi = material.psi_second_pk(C, data, S);
  const Vec3 p0 = f0 * S(0, 0) + f1 * S(1, 0);  // P3 = F S
  const Vec3 p1 = f0 * S(0, 1) + f1 * S(1, 1);
  g[0] = c.rest_area * (p0 * c.dm00 + p1 * c.dm01);  // Abar P3 Dm^-T
  g[1] = c.rest_area * (p1 * c.dm11);
  g[2] = -g[0] - g[1];
  return c.rest_area * psi;
}

/// The C-form for a MembraneConstraint (see the PackedMembrane overload).
/// \pre c.Dm_inv(1, 0) == 0, as triangle_rest makes it.
template <class M>
inline double membrane_energy_gradient_cform(const M& material, const MembraneConstraint& c,
                                             const Vec3& x1, const Vec3& x2, const Vec3& x3,
                                             std::array<Vec3, 3>& g) {
  return membrane_energy_gradient_cform(material, pack_membrane(c), c.data, x1, x2, x3, g);
}

namespace kernel_parts {
/// Energy E and vertex gradients g of a membrane element for any material: the C-form when
/// the material has one, else the current frame and the lift (math-spec 4.2-4.4).
/// @return false when the element must be skipped (no frame, or a frame-dependent material on
///         an irregular frame, math-spec 11)
template <class M>
inline bool membrane_energy_gradient(const M& material, const PackedMembrane& c,
                                     const ElementMaterialData& data, double orientation,
                                     const Vec3& x1, const Vec3& x2, const Vec3& x3,
                                     std::array<Vec3, 3>& g, double& E) {
  if constexpr (has_second_pk<M>::value) {
    // The orientation s does not matter for energies of C alone (math-spec 4.4).
    (void)orientation;
    E = membrane_energy_gradient_cform(material, c, data, x1, x2, x3, g);
    return true;
  } else {
    Mat2 Dm_inv;
    Dm_inv << c.dm00, c.dm01, 0.0, c.dm11;
    TriangleFrame fr;
    if (!triangle_frame(x1, x2, x3, Dm_inv, c.rest_area, orientation, fr)) return false;
    if (!fr.regular && material.frame_dependent()) return false;  // math-spec 11
    E = c.rest_area * material.psi(fr.F, data);
    lift_gradient(fr, material.pk1(fr.F, data), Dm_inv, c.rest_area, g[0], g[1], g[2]);
    return true;
  }
}
}  // namespace kernel_parts

/// Projects one membrane (or anisotropic) constraint with material M.
/// PBD (lambda == nullptr): dx_i = -k E/G w_i g_i, G = sum w_i |g_i|^2 (math-spec 9.1), with the
/// skip and clamp guards of 9.1(d). XPBD (lambda != nullptr): C = sqrt(2E), division-free update
/// sigma = C (C + at lambda) / (G + at C^2), dx_i = -sigma w_i g_i, lambda += -C sigma (9.2).
/// Every input is read into locals before the first store: ctx.x could alias the record or w
/// as far as the compiler knows, and would otherwise force reloads after each vertex update.
/// @param data  fibre direction (anisotropic energies; isotropic ones ignore it)
/// @return true if the positions were changed.
template <class M>
inline bool project_membrane(const M& material, const PackedMembrane& c,
                             const ElementMaterialData& data, double stiffness,
                             const ProjectionContext& ctx, double* lambda) {
  double* const x = ctx.x;
  const int i0 = c.v[0], i1 = c.v[1], i2 = c.v[2];
  const double max_step = c.max_step;
  std::array<Vec3, 3> g;
  double E;
  if (!kernel_parts::membrane_energy_gradient(material, c, data, ctx.orientation, kernel_parts::vertex(x, i0),
                                        kernel_parts::vertex(x, i1), kernel_parts::vertex(x, i2), g, E))
    return false;
  if (!(E > ctx.energy_floor * c.rest_area)) return false;  // also rejects NaN
  const double w0 = ctx.w[i0], w1 = ctx.w[i1], w2 = ctx.w[i2];
  const double n0 = g[0].squaredNorm(), n1 = g[1].squaredNorm(), n2 = g[2].squaredNorm();
  const double G = w0 * n0 + w1 * n1 + w2 * n2;
  if (!(G > 1e-300)) return false;  // stationary point with E > 0 (math-spec 9.1d)
  if (lambda == nullptr) {
    // kernel_parts::apply_step with the |g_i|^2 above reused.
    double scale = stiffness * E / G;
    double longest_sq = std::max(0.0, (scale * w0) * (scale * w0) * n0);
    longest_sq = std::max(longest_sq, (scale * w1) * (scale * w1) * n1);
    longest_sq = std::max(longest_sq, (scale * w2) * (scale * w2) * n2);
    if (longest_sq > max_step * max_step) scale *= max_step / std::sqrt(longest_sq);
    kernel_parts::subtract_scaled(x, i0, scale * w0, g[0]);
    kernel_parts::subtract_scaled(x, i1, scale * w1, g[1]);
    kernel_parts::subtract_scaled(x, i2, scale * w2, g[2]);
    return true;
  }
  const double C = std::sqrt(2.0 * E);
  const double at = ctx.alpha_tilde;
  const double sigma = C * (C + at * *lambda) / (G + at * C * C);
  *lambda -= C * sigma;
  kernel_parts::subtract_scaled(x, i0, sigma * w0, g[0]);
  kernel_parts::subtract_scaled(x, i1, sigma * w1, g[1]);
  kernel_parts::subtract_scaled(x, i2, sigma * w2, g[2]);
  return true;
}

/// Projects one MembraneConstraint (see the PackedMembrane overload, which it calls).
/// \pre c.Dm_inv(1, 0) == 0, as triangle_rest makes it.
template <class M>
inline bool project_membrane(const M& material, const MembraneConstraint& c, double stiffness,
                             const ProjectionContext& ctx, double* lambda) {
  return project_membrane(material, pack_membrane(c), c.data, stiffness, ctx, lambda);
}

/// Projects one anisotropic (E_A) constraint with the paper's inward term (math-spec 9.3, PF):
/// dx_i = -(E_A / Gt) w_i (g_i + k_A n), Gt = sum w_i |g_i|^2 + k_A^2 sum w_i, where n is the
/// face's unit outward normal frozen for the solve. The cross term vanishes because every g_i
/// is in-plane (math-spec 4.4). Zero at rest (E_A = 0 gate). With k_A = 0 this is
/// project_membrane.
template <class A>
inline bool project_anisotropic_paper(const A& material, const PackedMembrane& c,
                                      const ElementMaterialData& data, double k_a, const Vec3& n,
                                      const ProjectionContext& ctx) {
  if (k_a == 0.0) return project_membrane(material, c, data, 1.0, ctx, nullptr);
  std::array<Vec3, 3> g;
  double E;
  if (!kernel_parts::membrane_energy_gradient(material, c, data, ctx.orientation,
                                        kernel_parts::vertex(ctx.x, c.v[0]), kernel_parts::vertex(ctx.x, c.v[1]),
                                        kernel_parts::vertex(ctx.x, c.v[2]), g, E))
    return false;
  if (!(E > ctx.energy_floor * c.rest_area)) return false;
  double G = 0.0;  // = sum w |g|^2 + k_A^2 sum w: the cross term is zero (g in-plane)
  for (int i = 0; i < 3; ++i) {
    g[i] += k_a * n;
    G += ctx.w[c.v[i]] * g[i].squaredNorm();
  }
  if (!(G > 1e-300)) return false;
  kernel_parts::apply_step<3>(ctx.x, ctx.w, c.v, g, E / G, c.max_step);
  return true;
}

/// The paper's E_A projection for a MembraneConstraint (fibre from c.data).
/// \pre c.Dm_inv(1, 0) == 0, as triangle_rest makes it.
template <class A>
inline bool project_anisotropic_paper(const A& material, const MembraneConstraint& c, double k_a,
                                      const Vec3& n, const ProjectionContext& ctx) {
  return project_anisotropic_paper(material, pack_membrane(c), c.data, k_a, n, ctx);
}

/// Projects one isometric bending hinge. PBD closed form (math-spec 8.2):
/// dx_i = -k_B w_i K_i h / (2 sum_l w_l K_l^2), smooth at flat hinges. XPBD vector form with
/// beta = 3 k_B / (A0 + A1), C = sqrt(beta) h, lambda in R^3 (math-spec 8.2).
/// Inputs are read into locals first (see project_membrane: x may alias them for the compiler).
/// @param lambda  nullptr for PBD, else 3 doubles of accumulated multiplier
inline bool project_isometric_hinge(const IsometricHingeConstraint& c, double k_bending,
                                    const ProjectionContext& ctx, double* lambda) {
  double* const x = ctx.x;
  const int i0 = c.v[0], i1 = c.v[1], i2 = c.v[2], i3 = c.v[3];
  const double K0 = c.K(0), K1 = c.K(1), K2 = c.K(2), K3 = c.K(3);
  const double max_step = c.max_step, three_over_area = c.three_over_area;
  const double w0 = ctx.w[i0], w1 = ctx.w[i1], w2 = ctx.w[i2], w3 = ctx.w[i3];
  const Vec3 h = K0 * kernel_parts::vertex(x, i0) + K1 * kernel_parts::vertex(x, i1) +
                 K2 * kernel_parts::vertex(x, i2) + K3 * kernel_parts::vertex(x, i3);
  const double wK2 = w0 * K0 * K0 + w1 * K1 * K1 + w2 * K2 * K2 + w3 * K3 * K3;
  if (!(wK2 > 1e-300)) return false;  // every stencil vertex pinned, or K = 0 (inactive hinge)
  if (lambda == nullptr) {
    const Vec3 base = h * (k_bending / (2.0 * wK2));
    // The clamp of 9.1(d): the largest |dx_i| is max_i w_i |K_i| |base|.
    double longest = std::max(0.0, w0 * std::abs(K0));
    longest = std::max(longest, w1 * std::abs(K1));
    longest = std::max(longest, w2 * std::abs(K2));
    longest = std::max(longest, w3 * std::abs(K3));
    longest *= base.norm();
    const double shrink = longest > max_step ? max_step / longest : 1.0;
    kernel_parts::subtract_scaled(x, i0, shrink * w0 * K0, base);
    kernel_parts::subtract_scaled(x, i1, shrink * w1 * K1, base);
    kernel_parts::subtract_scaled(x, i2, shrink * w2 * K2, base);
    kernel_parts::subtract_scaled(x, i3, shrink * w3 * K3, base);
    return true;
  }
  const double beta = k_bending * three_over_area;
  const double sqrt_beta = std::sqrt(beta);
  Eigen::Map<Vec3> lam(lambda);
  const Vec3 dlam = (-sqrt_beta * h - ctx.alpha_tilde * lam) / (beta * wK2 + ctx.alpha_tilde);
  lam += dlam;
  kernel_parts::add_scaled(x, i0, w0 * sqrt_beta * K0, dlam);
  kernel_parts::add_scaled(x, i1, w1 * sqrt_beta * K1, dlam);
  kernel_parts::add_scaled(x, i2, w2 * sqrt_beta * K2, dlam);
  kernel_parts::add_scaled(x, i3, w3 * sqrt_beta * K3, dlam);
  return true;
}

/// Projects one dihedral hinge, E = k_B kappa (theta - theta_bar)^2 (math-spec 8.3).
/// PBD: dx_i = -k_B E/G w_i g_i with g = dE/dx for E without k_B (k_B is the correction
/// multiplier, reading R1 of math-spec 9.5). XPBD: C = sqrt(2 k_B kappa) (theta - theta_bar).
bool project_dihedral_hinge(const DihedralHingeConstraint& c, double k_bending,
                            const ProjectionContext& ctx, double* lambda);

}  // namespace shellcontract
