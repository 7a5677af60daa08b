#include "pbd/constraint_kernels.hpp"

namespace shellcontract {

bool project_dihedral_hinge(const DihedralHingeConstraint& c, double k_bending,
                            const ProjectionContext& ctx, double* lambda) {
  std::array<Vec3, 4> grad;  // d theta / dx
  double theta = 0.0;
  const Vec3 x0 = kernel_parts::vertex(ctx.x, c.v[0]);
  const Vec3 x1 = kernel_parts::vertex(ctx.x, c.v[1]);
  const Vec3 x2 = kernel_parts::vertex(ctx.x, c.v[2]);
  const Vec3 x3 = kernel_parts::vertex(ctx.x, c.v[3]);
  if (!(c.rest.kappa > 0.0)) return false;
  if (!dihedral_angle_gradient(x0, x1, x2, x3, theta, grad)) return false;  // collapsed face
  const double d = wrapped_angle_difference(theta, c.rest.rest_angle);
  double wg = 0.0;
  for (int i = 0; i < 4; ++i) wg += ctx.w[c.v[i]] * grad[i].squaredNorm();
  if (!(wg > 1e-300) || d == 0.0) return false;
  if (lambda == nullptr) {
    // E = kappa d^2, g = 2 kappa d grad theta, E/G = d / (2 kappa ... ) -> step along grad theta:
    // scale * g_i = k_B (E/G) g_i = k_B d / (2 wg) grad_i.
    std::array<Vec3, 4> g = grad;
    kernel_parts::apply_step<4>(ctx.x, ctx.w, c.v, g, k_bending * d / (2.0 * wg), c.max_step);
    return true;
  }
  const double root = std::sqrt(2.0 * k_bending * c.rest.kappa);
  const double C = root * d;
  double dlam = (-C - ctx.alpha_tilde * *lambda) / (root * root * wg + ctx.alpha_tilde);
  // The same clamp as PBD's (math-spec 9.1d): the angle is nonlinear, and a linearized step on a
  // nearly folded hinge can throw its vertices across the mesh (bear under --solver xpbd --mu 0.2
  // blew up without it: docs/design/defaults.md "Resolution", tests/long/test_resolution_long.cpp).
  dlam *= kernel_parts::step_clamp_factor<4>(ctx.w, c.v, grad, root * dlam, c.max_step);
  *lambda += dlam;
  for (int i = 0; i < 4; ++i) kernel_parts::add_scaled(ctx.x, c.v[i], ctx.w[c.v[i]] * root * dlam, grad[i]);
  return true;
}

}  // namespace shellcontract
