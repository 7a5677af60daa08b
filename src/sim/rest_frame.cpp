#include "sim/rest_frame.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>

namespace shellcontract {

void follow_rest_frame(Positions& x, const Positions& prev, const Eigen::VectorXd& inv_mass,
                       const std::vector<int>& outside) {
  Vec3 moment = Vec3::Zero(), centre = Vec3::Zero();
  double mass = 0.0;
  for (int v : outside) {
    const double w = inv_mass(v);
    if (!(w > 0.0)) continue;
    moment += Vec3(x.row(v) - prev.row(v)) / w;
    centre += Vec3(prev.row(v)) / w;
    mass += 1.0 / w;
  }
  if (!(mass > 0.0)) return;
  // The shift: a free shell whose regions sink recoils as a whole (its centre of mass stays), so
  // without it the rest moves by the recoil (docs/design/anisotropy.md).
  x.rowwise() -= (moment / mass).transpose();
  // The turn: the projections do not conserve angular momentum, and the mirrors' frame follows
  // the rest, so nothing else stops a slow spin of the whole shell (lab/regions/sink_why.md,
  // "What the drift is"; lab/regions/turn.md measures the rule). It is applied as an affine map
  // of the current positions, x_i -= omega x (x_i - c): an invertible affine map keeps a configuration free of intersections (whether two triangles meet
  // does not change under it), so this step cannot undo what the collision response ensured. A
  // lever taken at the step's start instead would move vertices in contact relative to each other.
  // omega is chosen so that the rest's net turn about c, sum_k m_k r_k x d_k with r_k = prev_k - c
  // and d_k the step, is zero afterwards: with s_k = x_k - c, r_k x (omega x s_k) = omega (r_k .
  // s_k) - s_k (r_k . omega), so J omega = L with J = sum_k m_k ((r_k . s_k) 1 - s_k r_k^T) and L the
  // net turn before. J is the rest's inertia about c plus a term of the size of the step; the rank
  // test is on the inertia.
  centre /= mass;
  Mat3 inertia = Mat3::Zero(), coupling = Mat3::Zero();
  Vec3 angular = Vec3::Zero();
  for (int v : outside) {
    const double w = inv_mass(v);
    if (!(w > 0.0)) continue;
    const Vec3 r = Vec3(prev.row(v)) - centre, s = Vec3(x.row(v)) - centre;
    angular += r.cross(s - r) / w;
    inertia += (r.squaredNorm() * Mat3::Identity() - r * r.transpose()) / w;
    coupling += (r.dot(s) * Mat3::Identity() - s * r.transpose()) / w;
  }
  const Vec3 moments = Eigen::JacobiSVD<Mat3>(inertia).singularValues();  // descending
  if (!(moments(2) > TURN_RANK_TOLERANCE * moments(0))) return;
  const Vec3 omega = coupling.fullPivLu().solve(angular);
  if (!omega.allFinite()) return;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const Vec3 lever = Vec3(x.row(i)) - centre;
    x.row(i) -= omega.cross(lever).transpose();
  }
}

}  // namespace shellcontract
