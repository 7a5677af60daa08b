#include "sim/rest_frame.hpp"

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
  // "What the drift is"; lab/regions/turn.md measures the rule).
  centre /= mass;
  Mat3 inertia = Mat3::Zero();
  Vec3 angular = Vec3::Zero();
  for (int v : outside) {
    const double w = inv_mass(v);
    if (!(w > 0.0)) continue;
    const Vec3 r = Vec3(prev.row(v)) - centre;
    angular += r.cross(Vec3(x.row(v) - prev.row(v))) / w;
    inertia += (r.squaredNorm() * Mat3::Identity() - r * r.transpose()) / w;
  }
  const Eigen::JacobiSVD<Mat3> svd(inertia, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Vec3 moments = svd.singularValues();  // descending
  if (!(moments(2) > TURN_RANK_TOLERANCE * moments(0))) return;
  const Vec3 omega = svd.solve(angular);
  if (!omega.allFinite()) return;
  // The linear turn omega x r, not a finite rotation: it is what leaves the rest's net turn exactly
  // zero, and it stretches the shell only by the square of one step's turn.
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    x.row(i) -= omega.cross(Vec3(prev.row(i)) - centre).transpose();
}

}  // namespace shellcontract
