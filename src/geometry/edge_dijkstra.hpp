// Private to the tip finder (tip_finder.cpp, docs/math/tip-finder.md): shortest distances along
// the edges of a mesh from one or more sources.
#pragma once

#include <limits>
#include <vector>

#include "geometry/cap_internal.hpp"

namespace shellcontract::detail {

/// Multi-source Dijkstra on the edge graph of a MeshArrays (edge lengths nbr_len). The
/// distances are the exact minima over edge paths, so they do not depend on the order in which
/// vertices are visited; the visiting order itself breaks ties of distance by the smaller vertex
/// index, so the list of reached vertices is reproducible. Scratch arrays are kept between runs
/// and reset through the list of what a run reached, so a run limited to a small radius costs
/// what it reaches, not the mesh's size.
class EdgeDijkstra {
 public:
  static constexpr double NONE = std::numeric_limits<double>::infinity();

  explicit EdgeDijkstra(const MeshArrays& m);

  /// Distances from the nearest of `sources` (each at 0), up to `limit` (vertices farther stay
  /// unreached). Returns the reached vertices in visiting order (by distance, ties by index).
  const std::vector<int>& run(const std::vector<int>& sources, double limit = NONE);

  /// Whether the last run's limit left vertices unreached that an unlimited run would reach.
  bool cut_off() const { return cut_off_; }
  /// The last run's distance of v (NONE when not reached).
  double dist(int v) const { return dist_[static_cast<std::size_t>(v)]; }

 private:
  const MeshArrays& m_;
  std::vector<double> dist_;
  std::vector<char> done_;
  std::vector<int> reached_;
  bool cut_off_ = false;
};

/// The distances of every vertex from the nearest of `sources` (NONE where unreachable).
std::vector<double> edge_distances(const MeshArrays& m, const std::vector<int>& sources);

}  // namespace shellcontract::detail
