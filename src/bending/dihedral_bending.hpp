// Rest-aware dihedral-angle bending (math-spec 8.3, the R option):
// E = k_B kappa_bar (theta - theta_bar)^2 with kappa_bar = 3 |e0|^2 / (2 (A0 + A1)), all rest
// values, so the rest shape has zero energy. Stencil order: hinge.hpp.
#pragma once

#include "bending/hinge.hpp"

namespace shellcontract {

/// Rest data of one dihedral hinge.
struct DihedralBendingRest {
  double rest_angle = 0.0;  ///< theta_bar in (-pi, pi], > 0 for a convex hinge
  double kappa = 0.0;       ///< kappa_bar = 3 |e0|^2 / (2 (A0 + A1)) (dimensionless)
};

/// Signed dihedral angle theta = atan2((nA x nB).e, nA.nB) in (-pi, pi]; > 0 where the hinge is
/// convex (math-spec 8.3). @return false (and theta = 0) when a face is collapsed,
/// |N| < 1e-12 |e0|^2, where the angle and its gradient are undefined (math-spec 11).
bool dihedral_angle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                    double& theta);

/// Gradient of theta with respect to x0..x3 (math-spec 8.3; Bridson et al. 2003).
/// @return false when a face is collapsed (gradient ~ 1/|N| undefined); grad is then zero.
bool dihedral_angle_gradient(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                             double& theta, std::array<Vec3, 4>& grad);

/// Rest angle and kappa_bar from the rest positions.
DihedralBendingRest dihedral_bending_rest(const Vec3& x0, const Vec3& x1, const Vec3& x2,
                                          const Vec3& x3);

/// theta - theta_bar wrapped into (-pi, pi] (branch cut at a fully folded hinge).
double wrapped_angle_difference(double theta, double rest_angle);

/// E = k_B kappa_bar (theta - theta_bar)^2. Zero when the angle is undefined.
double dihedral_bending_energy(const DihedralBendingRest& r, double k_bending, const Vec3& x0,
                               const Vec3& x1, const Vec3& x2, const Vec3& x3);

/// Gradient of dihedral_bending_energy; zero when the angle is undefined.
std::array<Vec3, 4> dihedral_bending_gradient(const DihedralBendingRest& r, double k_bending,
                                              const Vec3& x0, const Vec3& x1, const Vec3& x2,
                                              const Vec3& x3);

}  // namespace shellcontract
