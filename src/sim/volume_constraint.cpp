#include "sim/volume_constraint.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shellcontract {
void volume_gradient(const Positions& x, const Faces& faces, Positions& g) {
  g.setZero(x.rows(), 3);
  for (Eigen::Index j = 0; j < faces.rows(); ++j) {
    const int a = faces(j, 0), b = faces(j, 1), c = faces(j, 2);
    const Vec3 xa = x.row(a), xb = x.row(b), xc = x.row(c);
    g.row(a) += xb.cross(xc).transpose() / 6.0;
    g.row(b) += xc.cross(xa).transpose() / 6.0;
    g.row(c) += xa.cross(xb).transpose() / 6.0;
  }
}

double signed_volume(const Positions& x, const Faces& faces) {
  double v = 0.0;
  for (Eigen::Index j = 0; j < faces.rows(); ++j) {
    const Vec3 xa = x.row(faces(j, 0)), xb = x.row(faces(j, 1)), xc = x.row(faces(j, 2));
    v += xa.dot(xb.cross(xc));
  }
  return v / 6.0;
}

double surface_area(const Positions& x, const Faces& faces) {
  double a = 0.0;
  for (Eigen::Index j = 0; j < faces.rows(); ++j) {
    const Vec3 xa = x.row(faces(j, 0)), xb = x.row(faces(j, 1)), xc = x.row(faces(j, 2));
    a += 0.5 * (xb - xa).cross(xc - xa).norm();
  }
  return a;
}

int project_volume(Positions& x, const Faces& faces, const Eigen::VectorXd& w, double target,
                   double tolerance, int max_steps, double max_move, double smooth_moves) {
  Positions g;
  int steps = 0;
  for (; steps < max_steps; ++steps) {
    const double c = signed_volume(x, faces) - target;
    if (std::abs(c) <= tolerance) break;
    volume_gradient(x, faces, g);
    const double denominator =
        (g.rowwise().squaredNorm().transpose().array() * w.transpose().array()).sum();
    // No gradient (every vertex fixed, or a collapsed mesh): nothing can move V.
    if (!(denominator > 0.0) || !std::isfinite(denominator)) break;
    const double lambda = c / denominator;
    const double largest = std::abs(lambda) * (g.rowwise().norm().array() * w.array()).maxCoeff();
    double cap = max_move;
    if (largest > cap && smooth_moves > 0.0) {
      const double area = surface_area(x, faces);
      if (area > 0.0 && std::isfinite(area)) cap = std::max(cap, smooth_moves * std::abs(c) / area);
    }
    if (largest > cap) {
      // Part of the way, the rest left to the next steps (max_move's comment in the header).
      x -= (lambda * cap / largest) * (g.array().colwise() * w.array()).matrix();
      ++steps;
      break;
    }
    x -= lambda * (g.array().colwise() * w.array()).matrix();
  }
  return steps;
}

double target_volume_at(int n, int ramp, double v0, double ratio) {
  const double t = ramp > 0 ? std::clamp(static_cast<double>(n) / ramp, 0.0, 1.0) : 1.0;
  const double s = t * t * (3.0 - 2.0 * t);
  return v0 * (1.0 - (1.0 - ratio) * s);
}

}  // namespace shellcontract
