// The broad phase's input checks, swept boxes (math-spec 10.2) and pair keys, shared by its
// methods.
#include "collision/broad_phase/boxes.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/decimal_text.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {
namespace detail {

void check_inputs(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                  double inflation) {
  if (x0.rows() != topo.num_vertices || x1.rows() != topo.num_vertices)
    throw UsageError("broad phase: position arrays have " + std::to_string(x0.rows()) + " and " +
                     std::to_string(x1.rows()) + " rows, the topology has " +
                     std::to_string(topo.num_vertices) + " vertices");
  if (!(inflation >= 0.0) || !std::isfinite(inflation))
    throw UsageError("broad phase: inflation must be finite and >= 0, got " +
                     fixed_text(inflation, 6));  // std::to_string's "%f", in the "C" locale
}

void build_boxes(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                 double inflation, BroadPhaseScratch& s, bool need_faces, bool need_edges) {
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  s.vertex_boxes.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    BroadPhaseBox& b = s.vertex_boxes[v];
    const Eigen::Index i = static_cast<Eigen::Index>(v);
    for (std::size_t d = 0; d < 3; ++d) {
      const double a = x0(i, static_cast<Eigen::Index>(d));
      const double c = x1(i, static_cast<Eigen::Index>(d));
      b.lo[d] = std::min(a, c) - inflation;
      b.hi[d] = std::max(a, c) + inflation;
    }
    b.box_id = v;
  }
  if (need_faces) {
    const std::size_t nf = static_cast<std::size_t>(topo.faces.rows());
    s.face_boxes.resize(nf);
    for (std::size_t f = 0; f < nf; ++f) {
      const Eigen::Index j = static_cast<Eigen::Index>(f);
      BroadPhaseBox& b = s.face_boxes[f];
      b = s.vertex_boxes[static_cast<std::size_t>(topo.faces(j, 0))];
      grow(b, s.vertex_boxes[static_cast<std::size_t>(topo.faces(j, 1))]);
      grow(b, s.vertex_boxes[static_cast<std::size_t>(topo.faces(j, 2))]);
      b.box_id = nv + f;
    }
  }
  if (need_edges) {
    const std::size_t ne = static_cast<std::size_t>(topo.edges.rows());
    s.edge_boxes.resize(ne);
    for (std::size_t e = 0; e < ne; ++e) {
      const Eigen::Index k = static_cast<Eigen::Index>(e);
      BroadPhaseBox& b = s.edge_boxes[e];
      b = s.vertex_boxes[static_cast<std::size_t>(topo.edges(k, 0))];
      grow(b, s.vertex_boxes[static_cast<std::size_t>(topo.edges(k, 1))]);
      b.box_id = e;
    }
  }
}

void keys_to_pairs(std::vector<std::uint64_t>& keys, NoZeroVector<std::array<int, 2>>& pairs) {
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  pairs.resize(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i)
    pairs[i] = {static_cast<int>(keys[i] >> 32), static_cast<int>(keys[i] & 0xffffffffu)};
}

}  // namespace detail
}  // namespace shellcontract
