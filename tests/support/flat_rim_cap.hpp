// A spherical cap with a flat rim for the mirrored dimple's tests (sim/region_mirror.hpp): its
// reflection through the rim's plane is known in closed form, so a test can check the mirror
// against it.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "shellcontract/types.hpp"

namespace shellcontract::test {

/// A spherical cap of the unit sphere around +z with a flat rim: the apex, then `rings` rings of
/// `n` vertices at polar angles up to `theta` (the last ring, z = cos theta, is the rim), fanned
/// and stripped into ccw-from-outside triangles. Every face belongs to the region.
struct FlatRimCap {
  Positions x;
  Faces faces;
  std::vector<int> region;
};

inline FlatRimCap flat_rim_cap(int rings = 4, int n = 12, double theta = 0.9) {
  FlatRimCap c;
  c.x.resize(1 + rings * n, 3);
  c.x.row(0) << 0.0, 0.0, 1.0;
  for (int r = 0; r < rings; ++r)
    for (int i = 0; i < n; ++i) {
      const double t = theta * (r + 1) / rings, p = 2.0 * M_PI * (i + 0.5 * r) / n;
      c.x.row(1 + r * n + i) << std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t);
    }
  std::vector<Eigen::RowVector3i> f;
  auto at = [&](int r, int i) { return 1 + r * n + ((i % n) + n) % n; };
  for (int i = 0; i < n; ++i) f.emplace_back(0, at(0, i), at(0, i + 1));
  for (int r = 0; r + 1 < rings; ++r)
    for (int i = 0; i < n; ++i) {
      f.emplace_back(at(r, i), at(r + 1, i), at(r + 1, i + 1));
      f.emplace_back(at(r, i), at(r + 1, i + 1), at(r, i + 1));
    }
  c.faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t j = 0; j < f.size(); ++j) c.faces.row(static_cast<Eigen::Index>(j)) = f[j];
  for (std::size_t j = 0; j < f.size(); ++j) c.region.push_back(static_cast<int>(j));
  return c;
}

}  // namespace shellcontract::test
