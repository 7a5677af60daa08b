#include "bending/dihedral_bending.hpp"

#include <cmath>

#include "core/constants.hpp"

namespace shellcontract {
namespace {

/// The hinge's edge and unnormalized face normals, shared by the angle and its gradient.
struct Hinge {
  Vec3 e, NA, NB;
  double e_sq, a_sq, b_sq;
};

/// False when a face of the hinge is collapsed: |N| < 1e-12 |e0|^2 (math-spec 11), compared in
/// squares (no square root; a NaN still counts as collapsed).
bool hinge(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3, Hinge& h) {
  h.e = x1 - x0;
  h.NA = h.e.cross(x2 - x0);
  h.NB = (x0 - x1).cross(x3 - x1);
  h.e_sq = h.e.squaredNorm();
  h.a_sq = h.NA.squaredNorm();
  h.b_sq = h.NB.squaredNorm();
  const double floor_sq = 1e-24 * h.e_sq * h.e_sq;
  return h.e_sq > 0.0 && h.a_sq >= floor_sq && h.b_sq >= floor_sq;
}

/// theta = atan2((nA x nB) . e_hat, nA . nB) with the normals left unnormalized: atan2 takes the
/// same angle from both arguments scaled by 1 / (|NA| |NB|) > 0. Two normalizations fewer than
/// the textbook form, in the solver's inner loop (BM_DihedralBendingPbd).
double angle(const Hinge& h, const Vec3& e_hat) {
  return std::atan2(h.NA.cross(h.NB).dot(e_hat), h.NA.dot(h.NB));
}
}  // namespace

bool dihedral_angle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                    double& theta) {
  Hinge h;
  theta = 0.0;
  if (!hinge(x0, x1, x2, x3, h)) return false;
  theta = angle(h, h.e / std::sqrt(h.e_sq));
  return true;
}

bool dihedral_angle_gradient(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                             double& theta, std::array<Vec3, 4>& grad) {
  grad.fill(Vec3::Zero());
  Hinge h;
  theta = 0.0;
  if (!hinge(x0, x1, x2, x3, h)) return false;
  const double L = std::sqrt(h.e_sq);
  const Vec3 e_hat = h.e / L;
  theta = angle(h, e_hat);
  const Vec3 aA = h.NA / h.a_sq;
  const Vec3 aB = h.NB / h.b_sq;
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
