// Shortest edge paths round the concave creases (crease_path.hpp).
#include "geometry/crease_path.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

namespace shellcontract::detail {

CreasePaths::CreasePaths(const MeshArrays& m, const Positions& x, const std::vector<char>& crease)
    : m_(m),
      x_(x),
      crease_(crease),
      dist_(m.nv, std::numeric_limits<double>::infinity()),
      prev_(m.nv, -1) {}

double CreasePaths::distance(int s, const Vec3& c, double ball, int part,
                             const std::vector<int>& vertex_part, bool convex,
                             std::vector<int>* path) {
  // (distance, vertex) pairs, smallest first: equal distances pop by vertex index, so the path
  // found does not depend on the heap's internals.
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
  std::vector<int> touched{s};
  dist_[static_cast<std::size_t>(s)] = 0.0;
  heap.push({0.0, s});
  double found = std::numeric_limits<double>::infinity();
  int end = -1;
  while (!heap.empty()) {
    const auto [d, vi] = heap.top();
    heap.pop();
    const auto v = static_cast<std::size_t>(vi);
    if (d > dist_[v]) continue;
    if (vertex_part[v] == part) {
      found = d, end = vi;
      break;
    }
    for (int k = m_.nbr_start[v]; k < m_.nbr_start[v + 1]; ++k) {
      const auto w = static_cast<std::size_t>(m_.nbr_to[static_cast<std::size_t>(k)]);
      const double dw = d + m_.nbr_len[static_cast<std::size_t>(k)];
      if (!(dw < dist_[w]) || (convex && crease_[w]) ||
          (Vec3(x_.row(static_cast<Eigen::Index>(w))) - c).norm() > ball)
        continue;
      if (std::isinf(dist_[w])) touched.push_back(static_cast<int>(w));
      dist_[w] = dw;
      prev_[w] = vi;
      heap.push({dw, static_cast<int>(w)});
    }
  }
  if (path) {
    path->clear();
    for (int v = end; v >= 0; v = v == s ? -1 : prev_[static_cast<std::size_t>(v)])
      path->insert(path->begin(), v);
  }
  for (int v : touched) {
    dist_[static_cast<std::size_t>(v)] = std::numeric_limits<double>::infinity();
    prev_[static_cast<std::size_t>(v)] = -1;
  }
  return found;
}

bool CreasePaths::across(int s, const Vec3& c, double ball, int part,
                         const std::vector<int>& vertex_part) {
  const double any = distance(s, c, ball, part, vertex_part, false);
  if (std::isinf(any)) return false;
  return !(distance(s, c, ball, part, vertex_part, true) <= CREASE_DETOUR * any);
}

}  // namespace shellcontract::detail
