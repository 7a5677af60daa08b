// Refusing an STL that would read back as another mesh (stl_positions.hpp).
#include "mesh/stl_positions.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numeric>
#include <sstream>

#include "core/classic_locale.hpp"
#include "mesh/formats.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {

void require_distinct_stl_positions(const std::string& what,
                                    const std::vector<std::array<double, 3>>& points,
                                    const std::vector<std::size_t>& vertex_of, bool floats) {
  std::vector<std::array<double, 3>> key(points);
  if (floats)
    for (auto& p : key)
      for (double& c : p) c = static_cast<float>(c);
  const auto vertex = [&](std::size_t i) { return vertex_of.empty() ? i : vertex_of[i]; };
  std::vector<std::size_t> order;
  order.reserve(key.size());
  for (std::size_t i = 0; i < key.size(); ++i)
    if (std::isfinite(key[i][0]) && std::isfinite(key[i][1]) && std::isfinite(key[i][2]))
      order.push_back(i);
  // Sorted by position, then by point: the first pair found names the lowest points of a position.
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return key[a] != key[b] ? key[a] < key[b] : a < b;
  });
  for (std::size_t k = 0; k + 1 < order.size();) {
    std::size_t end = k + 1;
    while (end < order.size() && key[order[end]] == key[order[k]]) ++end;
    for (std::size_t j = k + 1; j < end; ++j) {
      if (vertex(order[j]) == vertex(order[k])) continue;  // two copies of one welded vertex
      const std::array<double, 3>& at = key[order[k]];
      ClassicOStringStream where;
      where << std::setprecision(9) << '(' << at[0] << ", " << at[1] << ", " << at[2] << ')';
      throw UsageError(what + ": an STL keeps no vertex identity, and vertices " +
                       std::to_string(order[k]) + " and " + std::to_string(order[j]) +
                       " would both be stored at " + where.str() +
                       (floats ? " (as 32-bit floats)" : "") +
                       ": read back, they would be one vertex, and the mesh another; write " +
                       extension_list(&MeshFormat::exact_positions));
    }
    k = end;
  }
}

void require_distinct_stl_positions(const std::string& what, const Mesh& mesh, const Positions& x,
                                    bool floats) {
  const Positions p = input_positions(mesh, x);
  std::vector<std::array<double, 3>> points(static_cast<std::size_t>(p.rows()));
  for (Eigen::Index i = 0; i < p.rows(); ++i)
    points[static_cast<std::size_t>(i)] = {p(i, 0), p(i, 1), p(i, 2)};
  require_distinct_stl_positions(
      what, points, has_welded_seams(mesh) ? input_vertex_map(mesh) : std::vector<std::size_t>{},
      floats);
}

}  // namespace shellcontract
