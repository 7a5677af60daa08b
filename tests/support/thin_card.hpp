// A closed card: the surface of the box [0, sx] x [0, sy] x [0, sz], each side cut into a grid of
// n cells along each of its axes (two triangles per cell), faces outward. With sz much smaller
// than sx and sy it is a thin closed shell whose two large sheets lie sz apart at rest.
#pragma once

#include <array>
#include <map>
#include <vector>

#include "support/mesh_fixtures.hpp"

namespace shellcontract::test {

inline TriMesh box_surface(std::array<int, 3> n, std::array<double, 3> size) {
  std::map<std::array<int, 3>, int> index;
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 3>> triangles;
  auto vertex = [&](const std::array<int, 3>& p) {
    const auto [it, added] = index.emplace(p, static_cast<int>(points.size()));
    if (added)
      points.push_back({p[0] * size[0] / n[0], p[1] * size[1] / n[1], p[2] * size[2] / n[2]});
    return it->second;
  };
  // For the side normal to `axis`, u and w are the other two axes in cyclic order, so that
  // (u, w, axis) is right-handed: the cell (i, j) -> (i + 1, j + 1) is counterclockwise seen from
  // +axis, which is outward on the far side and reversed on the near one.
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < n[u]; ++i)
        for (int j = 0; j < n[w]; ++j) {
          auto at = [&](int a, int b) {
            std::array<int, 3> p{};
            p[axis] = side * n[axis];
            p[u] = a;
            p[w] = b;
            return vertex(p);
          };
          std::array<int, 4> q{at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
          if (side == 0) q = {q[3], q[2], q[1], q[0]};
          triangles.push_back({q[0], q[1], q[2]});
          triangles.push_back({q[0], q[2], q[3]});
        }
  }
  TriMesh m;
  m.x.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t k = 0; k < points.size(); ++k)
    for (int c = 0; c < 3; ++c) m.x(static_cast<Eigen::Index>(k), c) = points[k][c];
  m.faces.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t k = 0; k < triangles.size(); ++k)
    for (int c = 0; c < 3; ++c) m.faces(static_cast<Eigen::Index>(k), c) = triangles[k][c];
  return m;
}

/// The 1 x 1 x t card, 10 x 10 cells on each large side and one cell across the rim.
inline TriMesh thin_card(double t) { return box_surface({10, 10, 1}, {1.0, 1.0, t}); }

}  // namespace shellcontract::test
