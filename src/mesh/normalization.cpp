#include "mesh/normalization.hpp"

#include <cmath>

#include "shellcontract/error.hpp"

namespace shellcontract {

double bounding_diagonal(const Vec3& lo, const Vec3& hi) {
  // Below 1e-150 the sum of squares is under 1e-300, near the subnormals.
  const double plain = (hi - lo).norm();
  return std::isfinite(plain) && plain >= 1e-150 ? plain : (hi - lo).stableNorm();
}

Normalization compute_normalization(const Positions& x) {
  if (x.rows() == 0) throw InputError("cannot normalize an empty mesh");
  const Vec3 lo = x.colwise().minCoeff().transpose();
  const Vec3 hi = x.colwise().maxCoeff().transpose();
  Normalization n;
  n.center = 0.5 * lo + 0.5 * hi;
  n.scale = bounding_diagonal(lo, hi);
  if (!std::isfinite(n.scale) || !(n.scale > 0.0))
    throw InputError("the mesh has a zero or non-finite bounding-box diagonal");
  return n;
}

Positions normalize(const Positions& x, const Normalization& n) {
  return ((x.rowwise() - n.center.transpose()) / n.scale).eval();
}

Positions denormalize(const Positions& x, const Normalization& n) {
  Positions out;
  denormalize_into(x, n, out);
  return out;
}

void denormalize_into(const Positions& x, const Normalization& n, Positions& out) {
  out.resize(x.rows(), 3);
  out.noalias() = (x * n.scale).rowwise() + n.center.transpose();
}

}  // namespace shellcontract
