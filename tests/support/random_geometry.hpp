// Seeded random geometry for tests: points, rotations, perturbations. Fixed seeds only.
#pragma once

#include <random>

#include <Eigen/Geometry>

#include "shellcontract/types.hpp"

namespace shellcontract::test {

/// Uniform random vector in [-scale, scale]^3.
inline Vec3 random_vec3(std::mt19937& rng, double scale = 1.0) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Vec3(u(rng), u(rng), u(rng));
}

/// Uniformly random rotation (from a random unit quaternion).
inline Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}

}  // namespace shellcontract::test
