#include "sim/local_contraction.hpp"

#include "sim/pressure.hpp"

namespace shellcontract {

void remove_rigid_body_force(const Positions& x, const Eigen::VectorXd& inv_mass, Positions& f) {
  const Eigen::Index n = x.rows();
  Eigen::VectorXd m = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i)
    if (inv_mass(i) > 0.0) m(i) = 1.0 / inv_mass(i);
  const double M = m.sum();
  if (!(M > 0.0)) return;  // everything pinned: no rigid motion to remove
  const Vec3 c = (x.array().colwise() * m.array()).colwise().sum().transpose() / M;
  const Vec3 F = f.colwise().sum().transpose();
  Vec3 torque = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 r = Vec3(x.row(i)) - c;
    torque += r.cross(Vec3(f.row(i)));
    inertia += m(i) * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  // Subtracting m_i a with a = F / M leaves no net force, and changes the torque about the
  // centre of mass by -sum m_i r_i x a = 0, so the torque can be removed afterwards.
  const Vec3 a = F / M;
  Vec3 omega = Vec3::Zero();
  const Eigen::LDLT<Mat3> ldlt(inertia);
  // A shell whose masses lie on one line has a singular inertia tensor; the trace bounds its
  // eigenvalues, so a relative pivot test tells the well-posed case.
  const double scale = inertia.trace();
  if (scale > 0.0 && ldlt.info() == Eigen::Success &&
      ldlt.vectorD().cwiseAbs().minCoeff() > 1e-12 * scale)
    omega = ldlt.solve(torque);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 r = Vec3(x.row(i)) - c;
    f.row(i) -= (m(i) * (a + omega.cross(r))).transpose();
  }
}

void local_contraction_forces(const Positions& x, const Faces& region_faces, double P_A,
                              const Eigen::VectorXd& inv_mass, Positions& f) {
  pressure_forces(x, region_faces, P_A, PressureModel::EnergyConsistent, f);
  remove_rigid_body_force(x, inv_mass, f);
}

void local_contraction_forces(const Positions& x, const Faces& region_faces, double P_A,
                              const Eigen::VectorXd& weight, const Eigen::VectorXd& inv_mass,
                              Positions& f) {
  f.setZero(x.rows(), 3);
  for (Eigen::Index j = 0; j < region_faces.rows(); ++j) {
    const int a = region_faces(j, 0), b = region_faces(j, 1), c = region_faces(j, 2);
    const Vec3 xc = x.row(c);
    const Vec3 N = (Vec3(x.row(a)) - xc).cross(Vec3(x.row(b)) - xc);
    const Eigen::RowVector3d fj = (-P_A * weight(j) / 6.0) * N.transpose();
    f.row(a) += fj;
    f.row(b) += fj;
    f.row(c) += fj;
  }
  remove_rigid_body_force(x, inv_mass, f);
}

}  // namespace shellcontract
