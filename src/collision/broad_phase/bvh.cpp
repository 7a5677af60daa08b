// The broad phase's Bvh method: a bounding-volume hierarchy (median split along a Morton
// order, rebuilt each call) over face boxes and over edge boxes, one query per vertex box and
// per edge box.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "collision/broad_phase/boxes.hpp"

namespace shellcontract {
namespace detail {

namespace {

/// Items per BVH leaf; 2, 8 and 16 were no faster on bear (bench_broad_phase).
constexpr int BVH_LEAF_SIZE = 4;

/// Spreads the low 10 bits of v to every third bit (for 30-bit Morton codes).
std::uint32_t spread_bits(std::uint32_t v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

/// Recursively splits order[begin, end) at its middle; node bounds come from the children.
int build_bvh_range(const std::vector<BroadPhaseBox>& boxes, const std::vector<int>& order,
                    int begin, int end, std::vector<detail::BvhNode>& nodes) {
  const int index = static_cast<int>(nodes.size());
  nodes.emplace_back();
  if (end - begin <= BVH_LEAF_SIZE) {
    detail::BvhNode& leaf = nodes[static_cast<std::size_t>(index)];
    leaf.lo = boxes[static_cast<std::size_t>(order[static_cast<std::size_t>(begin)])].lo;
    leaf.hi = boxes[static_cast<std::size_t>(order[static_cast<std::size_t>(begin)])].hi;
    for (int k = begin + 1; k < end; ++k) {
      const BroadPhaseBox& b = boxes[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])];
      for (std::size_t d = 0; d < 3; ++d) {
        leaf.lo[d] = std::min(leaf.lo[d], b.lo[d]);
        leaf.hi[d] = std::max(leaf.hi[d], b.hi[d]);
      }
    }
    leaf.first = begin;
    leaf.count = end - begin;
    return index;
  }
  const int mid = begin + (end - begin) / 2;
  const int left = build_bvh_range(boxes, order, begin, mid, nodes);
  const int right = build_bvh_range(boxes, order, mid, end, nodes);
  detail::BvhNode& node = nodes[static_cast<std::size_t>(index)];
  const detail::BvhNode& l = nodes[static_cast<std::size_t>(left)];
  const detail::BvhNode& r = nodes[static_cast<std::size_t>(right)];
  for (std::size_t d = 0; d < 3; ++d) {
    node.lo[d] = std::min(l.lo[d], r.lo[d]);
    node.hi[d] = std::max(l.hi[d], r.hi[d]);
  }
  node.first = right;
  node.count = 0;
  return index;
}

/// Builds a linear BVH over boxes[0..n): items sorted by the 30-bit Morton code of their box
/// centre, then split at the middle of each range. Rebuilt each call (O(n log n) for the sort,
/// O(n) otherwise); this adapts to large motions that would degrade a refitted tree.
/// @param keys  scratch for the (code, id) sort keys
void build_bvh(const std::vector<BroadPhaseBox>& boxes, std::vector<detail::BvhNode>& nodes,
               std::vector<int>& order, std::vector<std::uint64_t>& keys) {
  const std::size_t n = boxes.size();
  nodes.clear();
  order.resize(n);
  if (n == 0) return;
  std::array<double, 3> lo = boxes[0].lo, hi = boxes[0].hi;
  for (const BroadPhaseBox& b : boxes)
    for (std::size_t d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], b.lo[d]);
      hi[d] = std::max(hi[d], b.hi[d]);
    }
  std::array<double, 3> scale{};
  for (std::size_t d = 0; d < 3; ++d)
    scale[d] = hi[d] > lo[d] ? 1023.0 / (2.0 * (hi[d] - lo[d])) : 0.0;
  keys.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t code = 0;
    for (std::size_t d = 0; d < 3; ++d) {
      const double c = (boxes[i].lo[d] + boxes[i].hi[d] - 2.0 * lo[d]) * scale[d];
      code |= spread_bits(static_cast<std::uint32_t>(std::clamp(c, 0.0, 1023.0))) << d;
    }
    keys[i] = (static_cast<std::uint64_t>(code) << 32) | i;
  }
  std::sort(keys.begin(), keys.end());
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<int>(keys[i] & 0xffffffffu);
  nodes.reserve(2 * (n / BVH_LEAF_SIZE + 1));
  build_bvh_range(boxes, order, 0, static_cast<int>(n), nodes);
}

bool overlap(const detail::BvhNode& n, const BroadPhaseBox& b) {
  return n.lo[0] <= b.hi[0] && b.lo[0] <= n.hi[0] && n.lo[1] <= b.hi[1] && b.lo[1] <= n.hi[1] &&
         n.lo[2] <= b.hi[2] && b.lo[2] <= n.hi[2];
}

/// Calls visit(item) for every item of the tree whose box overlaps `query`.
template <class Visit>
void query_bvh(const std::vector<detail::BvhNode>& nodes, const std::vector<int>& order,
               const std::vector<BroadPhaseBox>& boxes, const BroadPhaseBox& query,
               std::vector<int>& stack, Visit visit) {
  if (nodes.empty() || !overlap(nodes[0], query)) return;
  // Children are tested before they are pushed; the depth is at most ~log2(n / leaf size) + 1.
  stack.resize(128);
  int top = 0;
  stack[0] = 0;
  ++top;
  while (top > 0) {
    const int index = stack[static_cast<std::size_t>(--top)];
    const detail::BvhNode& node = nodes[static_cast<std::size_t>(index)];
    if (node.count > 0) {
      for (int k = node.first; k < node.first + node.count; ++k) {
        const int item = order[static_cast<std::size_t>(k)];
        if (overlap(boxes[static_cast<std::size_t>(item)], query)) visit(item);
      }
      continue;
    }
    if (overlap(nodes[static_cast<std::size_t>(node.first)], query))
      stack[static_cast<std::size_t>(top++)] = node.first;
    if (overlap(nodes[static_cast<std::size_t>(index + 1)], query))
      stack[static_cast<std::size_t>(top++)] = index + 1;
  }
}

}  // namespace

std::int64_t bvh_pairs(const CollisionTopology& topo, CandidatePairs& out) {
  BroadPhaseScratch& s = *out.scratch;
  std::int64_t reported = 0;
  build_bvh(s.face_boxes, s.face_tree, s.face_order, s.vf_keys);
  build_bvh(s.edge_boxes, s.edge_tree, s.edge_order, s.ee_keys);
  auto& vf = out.vertex_face;
  vf.clear();
  for (int v = 0; v < topo.num_vertices; ++v) {
    const std::size_t run = vf.size();
    query_bvh(s.face_tree, s.face_order, s.face_boxes, s.vertex_boxes[static_cast<std::size_t>(v)],
              s.stack, [&](int f) {
                ++reported;
                if (!is_corner(v, topo.faces, f)) vf.push_back({v, f});
              });
    std::sort(vf.begin() + static_cast<std::ptrdiff_t>(run), vf.end());
  }
  auto& ee = out.edge_edge;
  ee.clear();
  const int ne = static_cast<int>(topo.edges.rows());
  for (int a = 0; a < ne; ++a) {
    const std::size_t run = ee.size();
    query_bvh(s.edge_tree, s.edge_order, s.edge_boxes, s.edge_boxes[static_cast<std::size_t>(a)],
              s.stack, [&](int b) {
                if (b <= a) return;
                ++reported;
                if (!share_vertex(topo.edges, a, b)) ee.push_back({a, b});
              });
    std::sort(ee.begin() + static_cast<std::ptrdiff_t>(run), ee.end());
  }
  return reported;
}

}  // namespace detail
}  // namespace shellcontract
