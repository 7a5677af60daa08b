// Incremental least-squares sphere fit (private to the region finder): points are added one at a
// time as a geodesic disc grows, and the fit of all points so far is solved in O(1) from their
// moments, so growing a disc of n vertices costs O(n) however many times it is fitted.
#pragma once

#include <Eigen/Dense>

#include <cmath>
#include <optional>

#include "shellcontract/types.hpp"

namespace shellcontract::detail {

/// A fitted sphere and its quality, in the caller's length unit.
struct SphereFit {
  Vec3 centre = Vec3::Zero();
  double radius = 0.0;
  double residual = 0.0;  ///< RMS distance of the points to the sphere / radius (first order)
};

/// Weighted algebraic (Kasa) sphere fit: minimises sum w_i (|q_i|^2 - 2 c.q_i - d)^2 over (c, d)
/// with q_i = (p_i - origin) / scale, radius^2 = d + |c|^2. The algebraic distance of a point at
/// distance r + e from the centre is 2 r e + e^2, so sqrt(mean algebraic residual) / (2 r^2) is
/// the relative RMS distance to first order. Exact for points on a sphere. The origin and scale
/// (a point of the disc, the mesh's size) keep the moments of order 4 well conditioned.
class SphereMoments {
 public:
  SphereMoments(const Vec3& origin, double scale) : origin_(origin), scale_(scale) {}

  void add(const Vec3& p, double w) {
    const Vec3 q = (p - origin_) / scale_;
    const double q2 = q.squaredNorm();
    w_ += w;
    s1_ += w * q;
    s2_ += w * q * q.transpose();
    sq2_ += w * q2;
    sq2q_ += w * q2 * q;
    sq4_ += w * q2 * q2;
  }

  double weight() const { return w_; }

  /// The fit of the points added so far; nothing when their weight is 0, they are (nearly)
  /// coplanar or collinear (the 4 x 4 normal matrix is singular to 1e-12 of its largest
  /// eigenvalue) or the fitted radius^2 is not positive.
  std::optional<SphereFit> fit() const {
    if (!(w_ > 0.0)) return std::nullopt;
    Eigen::Matrix4d A;
    A.topLeftCorner<3, 3>() = 4.0 * s2_;
    A.topRightCorner<3, 1>() = 2.0 * s1_;
    A.bottomLeftCorner<1, 3>() = 2.0 * s1_.transpose();
    A(3, 3) = w_;
    Eigen::Vector4d rhs;
    rhs.head<3>() = 2.0 * sq2q_;
    rhs(3) = sq2_;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(A, Eigen::EigenvaluesOnly);
    const double lo = eig.eigenvalues()(0), hi = eig.eigenvalues()(3);
    if (!(hi > 0.0) || !(lo > 1e-12 * hi)) return std::nullopt;
    const Eigen::Vector4d sol = A.ldlt().solve(rhs);
    const Vec3 c = sol.head<3>();
    const double r2 = sol(3) + c.squaredNorm();
    if (!(r2 > 0.0) || !std::isfinite(r2)) return std::nullopt;
    // sum w b^2 - 2 x.rhs + x.A x with A x = rhs.
    const double algebraic = std::max(sq4_ - sol.dot(rhs), 0.0) / w_;
    SphereFit f;
    f.centre = origin_ + scale_ * c;
    f.radius = scale_ * std::sqrt(r2);
    f.residual = std::sqrt(algebraic) / (2.0 * r2);
    return f;
  }

 private:
  Vec3 origin_;
  double scale_;
  double w_ = 0.0, sq2_ = 0.0, sq4_ = 0.0;
  Vec3 s1_ = Vec3::Zero(), sq2q_ = Vec3::Zero();
  Mat3 s2_ = Mat3::Zero();
};

}  // namespace shellcontract::detail
