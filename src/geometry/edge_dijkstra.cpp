// Multi-source Dijkstra on the edge graph (edge_dijkstra.hpp).
#include "geometry/edge_dijkstra.hpp"

#include <functional>
#include <queue>
#include <utility>
#include <vector>

namespace shellcontract::detail {

EdgeDijkstra::EdgeDijkstra(const MeshArrays& m) : m_(m), dist_(m.nv, NONE), done_(m.nv, 0) {}

const std::vector<int>& EdgeDijkstra::run(const std::vector<int>& sources, double limit) {
  for (int v : reached_) {
    const auto i = static_cast<std::size_t>(v);
    dist_[i] = NONE, done_[i] = 0;
  }
  reached_.clear();
  cut_off_ = false;
  // (distance, vertex) pairs, smallest first: equal distances pop by vertex index.
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  std::vector<int> touched;  // set but not yet popped, to reset if the limit cuts them off
  for (int src : sources) {
    const auto s = static_cast<std::size_t>(src);
    if (dist_[s] == 0.0) continue;  // listed twice: the first keeps it
    dist_[s] = 0.0;
    touched.push_back(src);
    heap.emplace(0.0, src);
  }
  while (!heap.empty()) {
    const auto [d, v] = heap.top();
    heap.pop();
    const auto vi = static_cast<std::size_t>(v);
    if (done_[vi] || d > dist_[vi]) continue;
    if (d > limit) {
      cut_off_ = true;
      break;
    }
    done_[vi] = 1;
    reached_.push_back(v);
    for (int k = m_.nbr_start[vi]; k < m_.nbr_start[vi + 1]; ++k) {
      const auto ki = static_cast<std::size_t>(k);
      const auto w = static_cast<std::size_t>(m_.nbr_to[ki]);
      const double nd = d + m_.nbr_len[ki];
      if (!done_[w] && nd < dist_[w]) {
        if (dist_[w] == NONE) touched.push_back(m_.nbr_to[ki]);
        dist_[w] = nd;
        heap.emplace(nd, m_.nbr_to[ki]);
      }
    }
  }
  // Vertices beyond the limit were given tentative distances: back to unreached.
  for (int v : touched) {
    const auto i = static_cast<std::size_t>(v);
    if (!done_[i]) dist_[i] = NONE;
  }
  // The reset at the next run goes through reached_ (done vertices): the others are clean.
  return reached_;
}

std::vector<double> edge_distances(const MeshArrays& m, const std::vector<int>& sources) {
  EdgeDijkstra dijkstra(m);
  dijkstra.run(sources);
  std::vector<double> d(m.nv, EdgeDijkstra::NONE);
  for (std::size_t v = 0; v < m.nv; ++v) d[v] = dijkstra.dist(static_cast<int>(v));
  return d;
}

}  // namespace shellcontract::detail
