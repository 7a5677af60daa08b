#include "shellcontract/sim/pressure.hpp"

#include <algorithm>

namespace shellcontract {

void pressure_forces(const Positions& x, const Faces& faces, double P, PressureModel model,
                     Positions& f) {
  f.setZero(x.rows(), 3);
  // Sum of the unnormalized face normals N_j = (x1 - x3) x (x2 - x3) = 2 A_j nhat_j around
  // each vertex; both models use it.
  for (Eigen::Index j = 0; j < faces.rows(); ++j) {
    const int a = faces(j, 0), b = faces(j, 1), c = faces(j, 2);
    const Vec3 xc = x.row(c);
    const Vec3 N = (Vec3(x.row(a)) - xc).cross(Vec3(x.row(b)) - xc);
    f.row(a) += N.transpose();
    f.row(b) += N.transpose();
    f.row(c) += N.transpose();
  }
  if (model == PressureModel::EnergyConsistent) {
    f *= -P / 6.0;
    return;
  }
  // Paper form: |f_i| = P * (sum of one-ring areas) / 3 along the normalized area-weighted normal.
  Eigen::VectorXd ring_area = Eigen::VectorXd::Zero(x.rows());
  for (Eigen::Index j = 0; j < faces.rows(); ++j) {
    const int a = faces(j, 0), b = faces(j, 1), c = faces(j, 2);
    const Vec3 xc = x.row(c);
    const double A = 0.5 * (Vec3(x.row(a)) - xc).cross(Vec3(x.row(b)) - xc).norm();
    ring_area(a) += A;
    ring_area(b) += A;
    ring_area(c) += A;
  }
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const double len = f.row(i).norm();
    if (len > 0.0) {
      f.row(i) *= -P * ring_area(i) / (3.0 * len);
    }  // else: the normals cancel (e.g. a flat fold); no direction, so no force
  }
}

double air_net_pressure(double P, double R, double v) {
  if (!(R > 0.0)) return P;
  const double outside = P / (1.0 - R);
  return outside * (1.0 - R / std::max(v, 0.25 * R));
}

}  // namespace shellcontract
