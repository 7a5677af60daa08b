#include "shellcontract/bending/dihedral_bending.hpp"

#include <cmath>

namespace shellcontract {
namespace {
constexpr double PI = 3.14159265358979323846;

/// A face of the hinge counts as collapsed when |N| < 1e-12 |e0|^2 (math-spec 11).
bool collapsed(const Vec3& N, double edge_sq) { return !(N.norm() >= 1e-12 * edge_sq) || edge_sq <= 0.0; }
}  // namespace

bool dihedral_angle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                    double& theta) {
  const Vec3 e = x1 - x0;
  const Vec3 NA = e.cross(x2 - x0);
  const Vec3 NB = (x0 - x1).cross(x3 - x1);
  const double e_sq = e.squaredNorm();
  theta = 0.0;
  if (collapsed(NA, e_sq) || collapsed(NB, e_sq)) return false;
  const Vec3 nA = NA.normalized();
  const Vec3 nB = NB.normalized();
  theta = std::atan2(nA.cross(nB).dot(e / std::sqrt(e_sq)), nA.dot(nB));
  return true;
}

bool dihedral_angle_gradient(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                             double& theta, std::array<Vec3, 4>& grad) {
  grad.fill(Vec3::Zero());
  if (!dihedral_angle(x0, x1, x2, x3, theta)) return false;
  const Vec3 e = x1 - x0;
  const double L = e.norm();
  const Vec3 e_hat = e / L;
  const Vec3 NA = e.cross(x2 - x0);
  const Vec3 NB = (x0 - x1).cross(x3 - x1);
  const Vec3 aA = NA / NA.squaredNorm();
  const Vec3 aB = NB / NB.squaredNorm();
  // math-spec 8.3 (Bridson et al. 2003), checked by finite differences in the tests.
  grad[2] = -L * aA;
  grad[3] = -L * aB;
  grad[0] = -((x2 - x1).dot(e_hat) * aA + (x3 - x1).dot(e_hat) * aB);
  grad[1] = (x2 - x0).dot(e_hat) * aA + (x3 - x0).dot(e_hat) * aB;
  return true;
}

DihedralBendingRest dihedral_bending_rest(const Vec3& x0, const Vec3& x1, const Vec3& x2,
                                          const Vec3& x3) {
  DihedralBendingRest r;
  double theta = 0.0;
  const double area_sum =
      0.5 * ((x1 - x0).cross(x2 - x0).norm() + (x0 - x1).cross(x3 - x1).norm());
  if (!dihedral_angle(x0, x1, x2, x3, theta) || !(area_sum > 0.0)) return r;  // kappa = 0: inactive
  r.rest_angle = theta;
  r.kappa = 3.0 * (x1 - x0).squaredNorm() / (2.0 * area_sum);
  return r;
}

double wrapped_angle_difference(double theta, double rest_angle) {
  double d = theta - rest_angle;  // in (-2 pi, 2 pi)
  if (d > PI) d -= 2.0 * PI;
  if (d <= -PI) d += 2.0 * PI;
  return d;
}

double dihedral_bending_energy(const DihedralBendingRest& r, double k_bending, const Vec3& x0,
                               const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  double theta = 0.0;
  if (!dihedral_angle(x0, x1, x2, x3, theta)) return 0.0;
  const double d = wrapped_angle_difference(theta, r.rest_angle);
  return k_bending * r.kappa * d * d;
}

std::array<Vec3, 4> dihedral_bending_gradient(const DihedralBendingRest& r, double k_bending,
                                              const Vec3& x0, const Vec3& x1, const Vec3& x2,
                                              const Vec3& x3) {
  std::array<Vec3, 4> g;
  double theta = 0.0;
  if (!dihedral_angle_gradient(x0, x1, x2, x3, theta, g)) return g;
  const double coeff = 2.0 * k_bending * r.kappa * wrapped_angle_difference(theta, r.rest_angle);
  for (auto& gi : g) gi *= coeff;
  return g;
}

}  // namespace shellcontract
