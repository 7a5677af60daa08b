// A region for the local contraction's tests: the faces of an icosphere with a corner above a
// height, on a sphere whose vertices may be perturbed (seeded, so every run sees the same mesh).
#pragma once

#include <random>
#include <vector>

#include "support/mesh_fixtures.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract::test {

/// An icosphere and the faces of its region.
struct CapScene {
  TriMesh m;
  std::vector<int> region;
};

/// The icosphere of `levels` subdivisions (radius 1), each vertex moved by noise * random_vec3
/// (mt19937 seeded with `seed`), and the faces with a corner above z = z0.
inline CapScene icosphere_cap(int levels, double z0, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  CapScene s{icosphere(levels, 1.0), {}};
  for (Eigen::Index i = 0; i < s.m.x.rows(); ++i) s.m.x.row(i) += noise * random_vec3(rng).transpose();
  for (Eigen::Index j = 0; j < s.m.faces.rows(); ++j)
    for (int k = 0; k < 3; ++k)
      if (s.m.x(s.m.faces(j, k), 2) > z0) {
        s.region.push_back(static_cast<int>(j));
        break;
      }
  return s;
}

}  // namespace shellcontract::test
