#include "collision/contact.hpp"

namespace shellcontract {

bool project_contact(const Contact& c, double separation, double* x, const double* w) {
  const Vec3 dir = c.side * c.normal;
  Vec3 gap = Vec3::Zero();
  double denom = 0.0;
  for (int k = 0; k < 4; ++k) {
    gap += c.weights(k) * Eigen::Map<const Vec3>(x + 3 * c.v[k]);
    denom += w[c.v[k]] * c.weights(k) * c.weights(k);
  }
  const double C = dir.dot(gap) - separation;
  if (!(C < 0.0) || !(denom > 0.0)) return false;
  const double lambda = -C / denom;
  for (int k = 0; k < 4; ++k)
    Eigen::Map<Vec3>(x + 3 * c.v[k]) += (lambda * w[c.v[k]] * c.weights(k)) * dir;
  return true;
}

}  // namespace shellcontract
