// CCD broad phase (math-spec 10.1-10.2): swept boxes, CGAL box_intersection_d, candidate pairs.
#include "shellcontract/collision/broad_phase.hpp"

#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "shellcontract/core/error.hpp"

namespace shellcontract {

namespace {

using detail::BroadPhaseBox;
using detail::BroadPhaseScratch;

/// CGAL's cutoff: below this many boxes a subproblem is solved by a scan instead of further
/// segment-tree recursion. On bear (bench_broad_phase) PrimitiveBoxes took 86 ms with CGAL's
/// default 10, 54 ms with 100, 42 ms with 300, 34 ms with 1000, 36 ms with 2000.
constexpr std::ptrdiff_t BOX_CUTOFF = 1000;

std::uint64_t pack(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

/// Closed-interval overlap on all three axes: the same test CGAL applies with Topology CLOSED.
bool overlap(const BroadPhaseBox& a, const BroadPhaseBox& b) {
  return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1] &&
         a.lo[2] <= b.hi[2] && b.lo[2] <= a.hi[2];
}

void grow(BroadPhaseBox& box, const BroadPhaseBox& other) {
  for (std::size_t d = 0; d < 3; ++d) {
    box.lo[d] = std::min(box.lo[d], other.lo[d]);
    box.hi[d] = std::max(box.hi[d], other.hi[d]);
  }
}

bool is_corner(int v, const Faces& faces, int f) {
  return faces(f, 0) == v || faces(f, 1) == v || faces(f, 2) == v;
}

bool share_vertex(const Edges& edges, int a, int b) {
  return edges(a, 0) == edges(b, 0) || edges(a, 0) == edges(b, 1) || edges(a, 1) == edges(b, 0) ||
         edges(a, 1) == edges(b, 1);
}

void check_inputs(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                  double inflation) {
  if (x0.rows() != topo.num_vertices || x1.rows() != topo.num_vertices)
    throw UsageError("broad phase: position arrays have " + std::to_string(x0.rows()) + " and " +
                     std::to_string(x1.rows()) + " rows, the topology has " +
                     std::to_string(topo.num_vertices) + " vertices");
  if (!(inflation >= 0.0) || !std::isfinite(inflation))
    throw UsageError("broad phase: inflation must be finite and >= 0, got " +
                     std::to_string(inflation));
}

/// Swept, inflated boxes of every vertex, face and edge (math-spec 10.2). Face and edge boxes are
/// unions of their inflated vertex boxes, which equals min/max over the corner positions minus /
/// plus the inflation exactly, because rounding of x - inflation is monotone in x.
/// Box ids: vertices 0..V-1, faces V..V+F-1 (distinct from vertex ids, because CGAL skips pairs
/// with equal ids even in bipartite mode), edges 0..E-1 (only ever compared with edges).
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

/// Sorts and deduplicates packed keys, then unpacks them into pairs (deterministic output).
void keys_to_pairs(std::vector<std::uint64_t>& keys, std::vector<std::array<int, 2>>& pairs) {
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  pairs.resize(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i)
    pairs[i] = {static_cast<int>(keys[i] >> 32), static_cast<int>(keys[i] & 0xffffffffu)};
}

/// Runs CGAL's box_intersection_d on copies of `a` and `b` (it reorders its input ranges, and the
/// complete mode needs two separate copies of the same boxes, as box_self_intersection_d makes;
/// we keep the copies in scratch to avoid its allocation).
template <class Callback>
void box_search(const std::vector<BroadPhaseBox>& a, const std::vector<BroadPhaseBox>& b,
                CGAL::Box_intersection_d::Setting setting, BroadPhaseScratch& s,
                Callback callback) {
  s.work_a.assign(a.begin(), a.end());
  s.work_b.assign(b.begin(), b.end());
  CGAL::box_intersection_d(s.work_a.begin(), s.work_a.end(), s.work_b.begin(), s.work_b.end(),
                           callback, BOX_CUTOFF, CGAL::Box_intersection_d::CLOSED, setting);
}

/// Method PrimitiveBoxes: VF by a bipartite search, EE by a complete (self) search.
/// @return number of overlapping box pairs CGAL reported
std::int64_t primitive_boxes(const CollisionTopology& topo, CandidatePairs& out) {
  BroadPhaseScratch& s = out.scratch;
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  std::int64_t reported = 0;

  s.vf_keys.clear();
  box_search(s.vertex_boxes, s.face_boxes, CGAL::Box_intersection_d::BIPARTITE, s,
             [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
               ++reported;
               // Bipartite mode passes (box of range 1, box of range 2); check anyway, it is free.
               const BroadPhaseBox& vb = a.box_id < nv ? a : b;
               const BroadPhaseBox& fb = a.box_id < nv ? b : a;
               const int v = static_cast<int>(vb.box_id);
               const int f = static_cast<int>(fb.box_id - nv);
               if (!is_corner(v, topo.faces, f)) s.vf_keys.push_back(pack(v, f));
             });
  keys_to_pairs(s.vf_keys, out.vertex_face);

  s.ee_keys.clear();
  box_search(s.edge_boxes, s.edge_boxes, CGAL::Box_intersection_d::COMPLETE, s,
             [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
               ++reported;
               const int ea = static_cast<int>(a.box_id);
               const int eb = static_cast<int>(b.box_id);
               if (!share_vertex(topo.edges, ea, eb))
                 s.ee_keys.push_back(pack(std::min(ea, eb), std::max(ea, eb)));
             });
  keys_to_pairs(s.ee_keys, out.edge_edge);
  return reported;
}

/// Method FacePairs (math-spec 10.2): overlapping face pairs, then their 6 VF and 9 EE pairs.
/// Unlike math-spec 10.2 we keep face pairs that share a vertex: a VF or EE pair whose every
/// containing face pair shares a vertex (e.g. a valence-3 vertex against the face across its
/// link) would otherwise be lost, and the result would differ from the primitive-box definition.
/// Each primitive pair is box-tested itself, so the result equals PrimitiveBoxes exactly: a
/// primitive's box lies inside each of its faces' boxes, so every overlapping primitive pair has
/// an overlapping face pair (two different faces, since adjacent pairs are excluded).
/// @return number of overlapping face box pairs
std::int64_t face_pairs(const CollisionTopology& topo, CandidatePairs& out) {
  BroadPhaseScratch& s = out.scratch;
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  const Faces& faces = topo.faces;
  std::int64_t reported = 0;
  s.vf_keys.clear();
  s.ee_keys.clear();
  // The vertices of g against face h.
  auto vertices_vs_face = [&](int g, int h) {
    const BroadPhaseBox& hb = s.face_boxes[static_cast<std::size_t>(h)];
    for (int k = 0; k < 3; ++k) {
      const int v = faces(g, k);
      if (!is_corner(v, faces, h) && overlap(s.vertex_boxes[static_cast<std::size_t>(v)], hb))
        s.vf_keys.push_back(pack(v, h));
    }
  };
  box_search(s.face_boxes, s.face_boxes, CGAL::Box_intersection_d::COMPLETE, s,
             [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
               ++reported;
               const int g = static_cast<int>(a.box_id - nv);
               const int h = static_cast<int>(b.box_id - nv);
               vertices_vs_face(g, h);
               vertices_vs_face(h, g);
               for (int i = 0; i < 3; ++i) {
                 const int ea = topo.face_edges(g, i);
                 const BroadPhaseBox& ab = s.edge_boxes[static_cast<std::size_t>(ea)];
                 for (int j = 0; j < 3; ++j) {
                   const int eb = topo.face_edges(h, j);
                   if (!share_vertex(topo.edges, ea, eb) &&
                       overlap(ab, s.edge_boxes[static_cast<std::size_t>(eb)]))
                     s.ee_keys.push_back(pack(std::min(ea, eb), std::max(ea, eb)));
                 }
               }
             });
  keys_to_pairs(s.vf_keys, out.vertex_face);
  keys_to_pairs(s.ee_keys, out.edge_edge);
  return reported;
}

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

/// Method Bvh: one query per vertex box (face tree) and per edge box (edge tree). Results come
/// grouped by the query id in increasing order, so sorting each short run sorts everything, and
/// each tree item is met at most once per query, so there are no duplicates.
/// @return number of overlapping box pairs found (VF, plus EE with a < b)
std::int64_t bvh_pairs(const CollisionTopology& topo, CandidatePairs& out) {
  BroadPhaseScratch& s = out.scratch;
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

/// Thrown by has_any_candidate's callbacks to stop CGAL's search at the first pair.
struct CandidateFound {};

}  // namespace

CollisionTopology make_collision_topology(const Faces& faces, int num_vertices) {
  if (num_vertices < 0)
    throw UsageError("make_collision_topology: negative vertex count " +
                     std::to_string(num_vertices));
  CollisionTopology topo;
  topo.faces = faces;
  topo.num_vertices = num_vertices;
  const Eigen::Index nf = faces.rows();
  for (Eigen::Index f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k)
      if (faces(f, k) < 0 || faces(f, k) >= num_vertices)
        throw InputError("make_collision_topology: face " + std::to_string(f) + " has vertex id " +
                         std::to_string(faces(f, k)) + " outside [0, " +
                         std::to_string(num_vertices) + ")");
    if (faces(f, 0) == faces(f, 1) || faces(f, 1) == faces(f, 2) || faces(f, 2) == faces(f, 0))
      throw InputError("make_collision_topology: face " + std::to_string(f) +
                       " has a repeated vertex");
  }

  // Sides as (packed sorted vertex pair, face * 3 + k); sorting gives lexicographic edge ids.
  std::vector<std::pair<std::uint64_t, Eigen::Index>> sides;
  sides.reserve(static_cast<std::size_t>(3 * nf));
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      sides.emplace_back(pack(std::min(a, b), std::max(a, b)), 3 * f + k);
    }
  std::sort(sides.begin(), sides.end());
  topo.face_edges.resize(nf, 3);
  std::vector<std::uint64_t> unique_keys;
  unique_keys.reserve(sides.size() / 2 + 1);
  for (const auto& [key, slot] : sides) {
    if (unique_keys.empty() || unique_keys.back() != key) unique_keys.push_back(key);
    topo.face_edges(slot / 3, static_cast<Eigen::Index>(slot % 3)) =
        static_cast<int>(unique_keys.size()) - 1;
  }
  const Eigen::Index ne = static_cast<Eigen::Index>(unique_keys.size());
  topo.edges.resize(ne, 2);
  std::vector<std::int64_t> degree(static_cast<std::size_t>(num_vertices), 0);
  for (Eigen::Index e = 0; e < ne; ++e) {
    const std::uint64_t key = unique_keys[static_cast<std::size_t>(e)];
    topo.edges(e, 0) = static_cast<int>(key >> 32);
    topo.edges(e, 1) = static_cast<int>(key & 0xffffffffu);
    ++degree[static_cast<std::size_t>(topo.edges(e, 0))];
    ++degree[static_cast<std::size_t>(topo.edges(e, 1))];
  }

  // Table 2 "no culling": every pair a brute-force narrow phase would test.
  topo.all_vertex_face_pairs = static_cast<std::int64_t>(num_vertices) * nf - 3 * nf;
  std::int64_t sharing = 0;  // unordered edge pairs with a common vertex (exactly one, edges unique)
  for (const std::int64_t d : degree) sharing += d * (d - 1) / 2;
  topo.all_edge_edge_pairs = static_cast<std::int64_t>(ne) * (ne - 1) / 2 - sharing;
  return topo;
}

void find_candidates(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                     double inflation, CandidatePairs& out, BroadPhaseStats* stats,
                     BroadPhaseMethod method) {
  const auto start = std::chrono::steady_clock::now();
  check_inputs(x0, x1, topo, inflation);
  build_boxes(x0, x1, topo, inflation, out.scratch, true, true);
  std::int64_t reported = 0;
  switch (method) {
    case BroadPhaseMethod::PrimitiveBoxes:
      reported = primitive_boxes(topo, out);
      break;
    case BroadPhaseMethod::FacePairs:
      reported = face_pairs(topo, out);
      break;
    case BroadPhaseMethod::Bvh:
      reported = bvh_pairs(topo, out);
      break;
  }
  if (stats) {
    stats->no_culling_vertex_face = topo.all_vertex_face_pairs;
    stats->no_culling_edge_edge = topo.all_edge_edge_pairs;
    stats->box_overlaps = reported;
    stats->vertex_face = static_cast<std::int64_t>(out.vertex_face.size());
    stats->edge_edge = static_cast<std::int64_t>(out.edge_edge.size());
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
}

bool has_any_candidate(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                       double inflation, detail::BroadPhaseScratch& scratch) {
  check_inputs(x0, x1, topo, inflation);
  build_boxes(x0, x1, topo, inflation, scratch, true, true);
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  // CGAL offers no early exit; an exception out of the callback is the documented-safe way to
  // stop (the boxes are copies in scratch, so their reordering does not matter).
  try {
    box_search(scratch.vertex_boxes, scratch.face_boxes, CGAL::Box_intersection_d::BIPARTITE,
               scratch, [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
                 const BroadPhaseBox& vb = a.box_id < nv ? a : b;
                 const BroadPhaseBox& fb = a.box_id < nv ? b : a;
                 if (!is_corner(static_cast<int>(vb.box_id), topo.faces,
                                static_cast<int>(fb.box_id - nv)))
                   throw CandidateFound{};
               });
    box_search(scratch.edge_boxes, scratch.edge_boxes, CGAL::Box_intersection_d::COMPLETE,
               scratch, [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
                 if (!share_vertex(topo.edges, static_cast<int>(a.box_id),
                                   static_cast<int>(b.box_id)))
                   throw CandidateFound{};
               });
  } catch (const CandidateFound&) {
    return true;
  }
  return false;
}

}  // namespace shellcontract
