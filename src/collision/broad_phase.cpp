// CCD broad phase (math-spec 10.1-10.2): swept boxes, CGAL box_intersection_d, candidate pairs.
#include "shellcontract/collision/broad_phase.hpp"
#include "collision/broad_phase/scratch.hpp"

#include <CGAL/box_intersection_d.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include "shellcontract/core/error.hpp"

// The Grid method's AVX-512 cell loop needs GCC's target pragma and x86-64 (as cull_batch.cpp);
// other compilers get the portable loop only.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define SHELLCONTRACT_GRID_AVX512 1
#include <immintrin.h>
#else
#define SHELLCONTRACT_GRID_AVX512 0
#endif

namespace shellcontract {

namespace {

using detail::BroadPhaseBox;

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
  BroadPhaseScratch& s = *out.scratch;
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
/// an overlapping face pair (two different faces, since adjacent pairs are excluded). Vertices
/// no face references are in no face pair: they are searched against the faces separately.
/// @return number of overlapping face box pairs (and unreferenced-vertex / face box pairs)
std::int64_t face_pairs(const CollisionTopology& topo, CandidatePairs& out) {
  BroadPhaseScratch& s = *out.scratch;
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
  // Vertices no face references are in no face pair: their own bipartite search.
  if (!topo.orphan_vertices.empty()) {
    std::vector<BroadPhaseBox> orphans;
    orphans.reserve(topo.orphan_vertices.size());
    for (int v : topo.orphan_vertices)
      orphans.push_back(s.vertex_boxes[static_cast<std::size_t>(v)]);
    box_search(orphans, s.face_boxes, CGAL::Box_intersection_d::BIPARTITE, s,
               [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
                 ++reported;
                 const BroadPhaseBox& vb = a.box_id < nv ? a : b;
                 const BroadPhaseBox& fb = a.box_id < nv ? b : a;
                 s.vf_keys.push_back(
                     pack(static_cast<int>(vb.box_id), static_cast<int>(fb.box_id - nv)));
               });
  }
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

// ------------------------------------------------------------------ Grid method

/// Cell size over the median swept-box extent (the largest side of a face or edge box).
/// On bear (bench_broad_phase, CPU ms per call): 0.6: 11.7, 1.0: 10.0, 1.5: 8.3, 2: 8.3, 3: 8.6
/// (smaller cells put each box in more cells; larger ones test more pairs per cell).
constexpr double GRID_CELL_FACTOR = 1.5;
/// Boxes sampled for the median extent; a sample keeps it O(1) and robust to a few huge boxes
/// (e.g. one vertex that flies off), which would drag a mean up.
constexpr std::size_t GRID_EXTENT_SAMPLES = 1024;
/// At most this many cells per box on average: caps the cell count (memory, the counting-sort
/// passes) when the boxes are tiny compared with the scene.
constexpr std::size_t GRID_CELLS_PER_BOX = 2;
/// At most this many (box, cell) entries per box on average; beyond it the cell size is doubled.
constexpr std::size_t GRID_ENTRIES_PER_BOX = 16;
/// If the per-cell pair loops would visit more than this many entry pairs per box (every box in
/// a few cells: boxes spread over a huge range, or nearly all of the scene overlapping), the
/// grid degenerates towards brute force, so PrimitiveBoxes runs instead (same result).
constexpr std::int64_t GRID_WORK_PER_BOX = 256;
/// The per-cell pair loops run as this many chunks of cells (about equal entry counts each), in
/// parallel with TBB; more chunks than threads balance the load.
constexpr std::size_t GRID_CHUNKS = 32;
/// Parts of the grid's counting sort: at most this many (one per thread of the arena).
constexpr std::size_t GRID_MAX_PARTS = 8;
/// Grid reuse (temporal coherence, grid_pairs): a call keeps the last call's grid while the
/// desired cell size is within this factor of the kept one and the scene is inside the kept grid.
constexpr double GRID_REUSE_FACTOR = 1.25;
/// A new grid extends this many cells beyond the scene on every side (see GRID_REUSE_FACTOR).
constexpr double GRID_MARGIN_CELLS = 0.5;
/// The kept grid's counting sort is patched (patch_grid) if at most 1 / GRID_PATCH_DIVISOR of the
/// boxes changed their cell range, else rebuilt. Bear at P = 4: 7.2k of 83k boxes per step on
/// average; patching costs about a third of a rebuild there (benchmarks/bench_broad_phase.cpp).
constexpr std::size_t GRID_PATCH_DIVISOR = 4;
/// Vertices per task of the grid's per-vertex loops.
constexpr std::size_t GRID_VERTEX_GRAIN = 2048;
/// Rows of the AVX-512 cell loop processed together (cell_rows_avx512). bench_broad_phase on
/// bear's frames 299 and 300 at P = 4 (one core, best of 5, five alternating series): 1 row
/// 13.2-15.0 ms per call, 2 rows 11.6-13.5, 4 rows 12.7-14.4 (their broadcast row values no
/// longer fit the 32 vector registers). At most 4 (BroadPhaseScratch's row buffers).
constexpr int GRID_ROW_GROUP = 2;
static_assert(GRID_ROW_GROUP >= 1 && GRID_ROW_GROUP <= 4, "see detail::GridChunk::row_keys");
/// Ids are stored as gid << 3 | flags in 32 bits.
constexpr std::size_t GRID_MAX_BOXES = std::size_t{1} << 29;
/// Cells per axis fit the 16-bit fields of detail::GridRange.
constexpr double GRID_MAX_DIM = 65535.0;

/// Entry flags: bit d is set iff the cell is the box's first cell on axis d. Two overlapping
/// boxes meet in every cell of the intersection of their cell ranges; we emit the pair only in
/// the cell max(first cell of a, first cell of b) (per axis), i.e. where on every axis at least
/// one of the two is in its first cell: (flags_a | flags_b) == 7. Each pair is emitted once, no
/// hash set needed.
constexpr std::uint32_t GRID_ALL_FIRST = 7;

/// Uniform grid over the bounding box of all swept boxes (with a margin, and kept from call to
/// call while it fits: grid_pairs). coord() is monotone in x (a rounded subtraction, a
/// multiplication by a positive number, a clamp, a truncation of a non-negative value), so if two
/// boxes' closed intervals overlap on an axis, so do their cell ranges: no pair is lost to
/// rounding, and the exact double box test decides. Monotone also means the cell range of a union
/// of boxes is the union (min/max) of their cell ranges.
struct Grid {
  std::array<double, 3> origin{};
  double inv_h = 1.0;
  std::array<std::size_t, 3> dims{1, 1, 1};

  std::uint16_t coord(double x, std::size_t d) const {
    const double t = std::min((x - origin[d]) * inv_h, static_cast<double>(dims[d] - 1));
    return static_cast<std::uint16_t>(std::max(t, 0.0));
  }
  std::size_t cells() const { return dims[0] * dims[1] * dims[2]; }
};

/// Grid with cell size h over [lo, hi], at most max_cells cells (h grows if needed).
Grid make_grid(const std::array<double, 3>& lo, const std::array<double, 3>& hi, double h,
               std::size_t max_cells) {
  Grid g;
  g.origin = lo;
  for (;;) {
    std::size_t n = 1;
    for (std::size_t d = 0; d < 3; ++d) {
      // Clamped in double first: (hi - lo) / h may exceed any integer for a tiny h.
      const double cells = std::min(std::floor((hi[d] - lo[d]) / h) + 1.0, GRID_MAX_DIM);
      g.dims[d] = static_cast<std::size_t>(cells);
      n *= g.dims[d];
    }
    if (n <= max_cells) break;
    h *= std::max(1.01, std::cbrt(static_cast<double>(n) / static_cast<double>(max_cells)));
  }
  g.inv_h = 1.0 / h;
  return g;
}

/// Largest float <= x (the conversion rounds to nearest; step down if it went up). Infinite
/// results are still bounds: e.g. x = 1e300 gives FLT_MAX <= x.
float round_down(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity())
                                    : f;
}
float round_up(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity())
                                    : f;
}

/// Per-primitive data of the grid, derived from the per-vertex data on the fly: stored face and
/// edge boxes would be 2-5 MB per call and memory traffic dominated earlier versions, while the
/// vertex arrays and the topology stay in cache.
struct GridPrimitives {
  const CollisionTopology& topo;
  const BroadPhaseScratch& s;
  std::size_t nv, nf;

  /// Vertex ids (detail::primitive_vertices).
  std::array<int, 3> ids(std::size_t gid) const { return detail::primitive_vertices(topo, gid); }
  static int corners(const std::array<int, 3>& v) { return detail::primitive_corners(v); }

  detail::GridRange range(const std::array<int, 3>& v) const {
    detail::GridRange r = s.grid_vertex_ranges[static_cast<std::size_t>(v[0])];
    for (int k = 1; k < corners(v); ++k) {
      const detail::GridRange& q = s.grid_vertex_ranges[static_cast<std::size_t>(v[k])];
      for (std::size_t d = 0; d < 3; ++d) {
        r.lo[d] = std::min(r.lo[d], q.lo[d]);
        r.hi[d] = std::max(r.hi[d], q.hi[d]);
      }
    }
    return r;
  }
  detail::GridFloatBox float_box(const std::array<int, 3>& v) const {
    detail::GridFloatBox b = s.grid_vertex_floats[static_cast<std::size_t>(v[0])];
    for (int k = 1; k < corners(v); ++k) {
      const detail::GridFloatBox& q = s.grid_vertex_floats[static_cast<std::size_t>(v[k])];
      for (std::size_t d = 0; d < 3; ++d) {
        b.lo[d] = std::min(b.lo[d], q.lo[d]);
        b.hi[d] = std::max(b.hi[d], q.hi[d]);
      }
    }
    return b;
  }
  /// The exact box: the same arithmetic as build_boxes, bit-identical to the other methods'.
  detail::GridVertexBox box(const std::array<int, 3>& v) const {
    return detail::primitive_box(s.grid_vertex_boxes, v);
  }
};

bool overlap(const detail::GridVertexBox& a, const detail::GridVertexBox& b) {
  return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1] &&
         a.lo[2] <= b.hi[2] && b.lo[2] <= a.hi[2];
}

/// Calls visit(cell index, flags, valid) for the cells of a range. Ranges of at most 2 cells per
/// axis (nearly all, with cells about as large as the boxes) take a fixed 2x2x2 pattern with
/// `valid` false for the cells outside the range, so there are no data-dependent branches;
/// visit must do nothing for invalid cells (whose index is then the range's first cell).
template <class Visit>
void for_each_cell(const Grid& g, const detail::GridRange& r, Visit visit) {
  const std::size_t sx = 1, sy = g.dims[0], sz = g.dims[0] * g.dims[1];
  const std::size_t first = r.lo[0] * sx + r.lo[1] * sy + r.lo[2] * sz;
  const unsigned dx = r.hi[0] - r.lo[0], dy = r.hi[1] - r.lo[1], dz = r.hi[2] - r.lo[2];
  if ((dx | dy | dz) <= 1) {
    for (unsigned corner = 0; corner < 8; ++corner) {
      const unsigned ox = corner & 1u, oy = (corner >> 1) & 1u, oz = corner >> 2;
      const bool valid = ox <= dx && oy <= dy && oz <= dz;
      const std::size_t c = first + (valid ? ox * sx + oy * sy + oz * sz : 0);
      visit(c, (ox ^ 1u) | (oy ^ 1u) << 1 | (oz ^ 1u) << 2, valid);
    }
    return;
  }
  for (std::size_t z = r.lo[2]; z <= r.hi[2]; ++z)
    for (std::size_t y = r.lo[1]; y <= r.hi[1]; ++y) {
      const std::size_t row = z * sz + y * sy;
      const std::uint32_t fyz = (y == r.lo[1] ? 2u : 0u) | (z == r.lo[2] ? 4u : 0u);
      for (std::size_t x = r.lo[0]; x <= r.hi[0]; ++x)
        visit(row + x, fyz | (x == r.lo[0] ? 1u : 0u), true);
    }
}

int bit_width(std::uint64_t v) {
  int n = 0;
  while (v != 0) {
    ++n;
    v >>= 1;
  }
  return n;
}

/// Unpacks keys (a << shift | b) << 1 | close into pairs[at..] and close[at..].
void unpack_keys(const std::vector<std::uint64_t>& keys, int shift, std::size_t at,
                 std::vector<std::array<int, 2>>& pairs, std::vector<std::uint8_t>& close) {
  const std::uint64_t mask = (std::uint64_t{1} << shift) - 1;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const std::uint64_t k = keys[i] >> 1;
    pairs[at + i] = {static_cast<int>(k >> shift), static_cast<int>(k & mask)};
    close[at + i] = static_cast<std::uint8_t>(keys[i] & 1u);
  }
}

/// True if, on some axis, the gap between the two boxes is larger than `threshold` (a negative
/// threshold asks for an overlap of at least -threshold).
bool gap_above(const detail::GridVertexBox& a, const detail::GridVertexBox& b, double threshold) {
  return b.lo[0] - a.hi[0] > threshold || a.lo[0] - b.hi[0] > threshold ||
         b.lo[1] - a.hi[1] > threshold || a.lo[1] - b.hi[1] > threshold ||
         b.lo[2] - a.hi[2] > threshold || a.lo[2] - b.hi[2] > threshold;
}

/// Item i of the current cell against items [j0, j1): mask[j] = 1 iff the pair passes the dedupe
/// flags, the float box test and the adjacency test. Plain loops over structure-of-arrays data,
/// written so that the compiler vectorizes them (no branches, 32-bit lanes throughout); they are
/// the hot loop (~10^6 pairs on bear). Adds the number of flag-and-box hits (adjacent pairs
/// included) to `hits`, for the statistics; returns whether any mask is set (most rows have
/// none, and then the caller skips its scan).
bool cell_masks(const detail::GridCell& cell, std::size_t i, std::size_t j0, std::size_t j1,
                std::uint32_t* mask, std::int64_t& hits) {
  const float lx = cell.lo[0][i], ly = cell.lo[1][i], lz = cell.lo[2][i];
  const float hx = cell.hi[0][i], hy = cell.hi[1][i], hz = cell.hi[2][i];
  const std::uint32_t fi = cell.flags[i];
  const int a = cell.v[0][i], b = cell.v[1][i], c = cell.v[2][i];
  const float* __restrict qlx = cell.lo[0].data();
  const float* __restrict qly = cell.lo[1].data();
  const float* __restrict qlz = cell.lo[2].data();
  const float* __restrict qhx = cell.hi[0].data();
  const float* __restrict qhy = cell.hi[1].data();
  const float* __restrict qhz = cell.hi[2].data();
  const std::uint32_t* __restrict qf = cell.flags.data();
  const int* __restrict qa = cell.v[0].data();
  const int* __restrict qb = cell.v[1].data();
  const int* __restrict qc = cell.v[2].data();
  std::uint32_t box_hits = 0, any = 0;
  for (std::size_t j = j0; j < j1; ++j) {
    const std::uint32_t box = static_cast<std::uint32_t>(
        ((fi | qf[j]) == GRID_ALL_FIRST) & (lx <= qhx[j]) & (qlx[j] <= hx) & (ly <= qhy[j]) &
        (qly[j] <= hy) & (lz <= qhz[j]) & (qlz[j] <= hz));
    // Adjacent iff a vertex id is shared; the -1/-2 placeholders never match (see ids()).
    const std::uint32_t apart = static_cast<std::uint32_t>(
        (a != qa[j]) & (a != qb[j]) & (a != qc[j]) & (b != qa[j]) & (b != qb[j]) &
        (c != qa[j]) & (c != qb[j]));
    box_hits += box;
    mask[j] = box & apart;
    any |= box & apart;
  }
  hits += box_hits;
  return any != 0;
}

#if SHELLCONTRACT_GRID_AVX512
// The AVX-512 cell loop. The portable loop tests float boxes (4 SSE2 lanes), writes a mask per
// item, scans it, and confirms each hit with the exact double boxes, gathered again from the
// vertex arrays (cache misses on bear). Here the cell holds the exact double boxes and one pass
// of 8 double lanes applies every test of the portable path to the same doubles with the same
// comparisons (the dedupe flags, overlap(), the adjacency test, gap_above()), then writes the
// finished keys of the lanes that pass with a compress-store, in lane order: the same pairs, in
// the same order, with the same close flags (tested against the portable loop). The float boxes
// were only a cull in front of the exact test, so skipping them changes nothing but the
// box_overlaps statistic, which then counts exact overlaps.
#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,popcnt")

/// Items i, ..., i + R - 1 of the cell (R rows, see GRID_ROW_GROUP) against items
/// [j0 + r s, j1), where s = 1 if `stagger` (edge-edge rows: row r starts after its own item)
/// and 0 otherwise (vertex-face rows share their range). Row r appends to keys[r][n[r]..] the key
/// (base[r] | (gid_j - sub)) << 1 | close of every j (increasing) that passes the dedupe flags,
/// the exact box test and the adjacency test; close is 0 iff gap_above(box i + r, box j,
/// far_gap). Adds the flag-and-box hits (adjacent pairs included) to `hits`. The rows share the
/// loads of the j items and the loop (EE rows average about three 8-lane steps, so a row's set-up
/// and its loop exit weigh as much as its tests); each row's answers are its own, written to its
/// own buffer, so the caller can append them in row order and keep the order of single rows.
template <int R>
inline __attribute__((always_inline)) void cell_rows_avx512(
    const detail::GridCell& cell, std::size_t i, std::size_t j0, std::size_t j1, bool stagger,
    const std::uint64_t (&base)[R], std::uint32_t sub, double far_gap,
    std::vector<std::uint64_t>* const (&keys)[R], std::size_t* const (&n)[R],
    std::int64_t& hits) {
  __m512d lx[R], ly[R], lz[R], hx[R], hy[R], hz[R];
  __m256i fi[R], a[R], b[R], c[R];
  __m512i key_base[R];
  std::size_t start[R];
  for (int r = 0; r < R; ++r) {
    const std::size_t q = i + static_cast<std::size_t>(r);
    lx[r] = _mm512_set1_pd(cell.dlo[0][q]);
    ly[r] = _mm512_set1_pd(cell.dlo[1][q]);
    lz[r] = _mm512_set1_pd(cell.dlo[2][q]);
    hx[r] = _mm512_set1_pd(cell.dhi[0][q]);
    hy[r] = _mm512_set1_pd(cell.dhi[1][q]);
    hz[r] = _mm512_set1_pd(cell.dhi[2][q]);
    fi[r] = _mm256_set1_epi32(static_cast<int>(cell.flags[q]));
    a[r] = _mm256_set1_epi32(cell.v[0][q]);
    b[r] = _mm256_set1_epi32(cell.v[1][q]);
    c[r] = _mm256_set1_epi32(cell.v[2][q]);
    key_base[r] = _mm512_set1_epi64(static_cast<long long>(base[r]));
    start[r] = j0 + (stagger ? static_cast<std::size_t>(r) : 0);
  }
  const __m512d gap = _mm512_set1_pd(far_gap);
  const __m256i all_first = _mm256_set1_epi32(static_cast<int>(GRID_ALL_FIRST));
  const __m512i key_sub = _mm512_set1_epi64(sub), one = _mm512_set1_epi64(1);
  std::int64_t box_hits = 0;
  for (std::size_t j = j0; j < j1; j += 8) {
    // Lanes past j1 are masked: their loads read nothing and they never pass. The comparisons
    // are independent of each other (one mask AND at the end, one branch), so they do not form
    // a chain of masked compares.
    const __mmask8 live =
        j1 - j >= 8 ? __mmask8{0xff} : static_cast<__mmask8>((1u << (j1 - j)) - 1u);
    const __m256i qf = _mm256_maskz_loadu_epi32(live, cell.flags.data() + j);
    const __m512d qlx = _mm512_maskz_loadu_pd(live, cell.dlo[0].data() + j);
    const __m512d qhx = _mm512_maskz_loadu_pd(live, cell.dhi[0].data() + j);
    const __m512d qly = _mm512_maskz_loadu_pd(live, cell.dlo[1].data() + j);
    const __m512d qhy = _mm512_maskz_loadu_pd(live, cell.dhi[1].data() + j);
    const __m512d qlz = _mm512_maskz_loadu_pd(live, cell.dlo[2].data() + j);
    const __m512d qhz = _mm512_maskz_loadu_pd(live, cell.dhi[2].data() + j);
    const __m256i qa = _mm256_maskz_loadu_epi32(live, cell.v[0].data() + j);
    const __m256i qb = _mm256_maskz_loadu_epi32(live, cell.v[1].data() + j);
    const __m256i qc = _mm256_maskz_loadu_epi32(live, cell.v[2].data() + j);
    for (int r = 0; r < R; ++r) {
      // Row r's lanes: live, and at or after its start (only a staggered row's first step
      // drops a lane).
      const unsigned lanes =
          start[r] > j ? live & ~((1u << (start[r] - j)) - 1u) : static_cast<unsigned>(live);
      // The dedupe flags and overlap(i + r, j): closed intervals on all three axes.
      const unsigned box =
          lanes & _mm256_cmpeq_epi32_mask(_mm256_or_si256(fi[r], qf), all_first) &
          _mm512_cmp_pd_mask(lx[r], qhx, _CMP_LE_OQ) & _mm512_cmp_pd_mask(qlx, hx[r], _CMP_LE_OQ) &
          _mm512_cmp_pd_mask(ly[r], qhy, _CMP_LE_OQ) & _mm512_cmp_pd_mask(qly, hy[r], _CMP_LE_OQ) &
          _mm512_cmp_pd_mask(lz[r], qhz, _CMP_LE_OQ) & _mm512_cmp_pd_mask(qlz, hz[r], _CMP_LE_OQ);
      // Adjacent iff a vertex id is shared; the -1/-2 placeholders never match (see ids()).
      const unsigned apart =
          _mm256_cmpneq_epi32_mask(a[r], qa) & _mm256_cmpneq_epi32_mask(a[r], qb) &
          _mm256_cmpneq_epi32_mask(a[r], qc) & _mm256_cmpneq_epi32_mask(b[r], qa) &
          _mm256_cmpneq_epi32_mask(b[r], qb) & _mm256_cmpneq_epi32_mask(c[r], qa) &
          _mm256_cmpneq_epi32_mask(c[r], qb);
      box_hits += __builtin_popcount(box);
      const __mmask8 pass = static_cast<__mmask8>(box & apart);
      if (pass == 0) continue;
      // gap_above(box i + r, box j, far_gap), the same subtractions.
      const __mmask8 far = static_cast<__mmask8>(
          _mm512_cmp_pd_mask(_mm512_sub_pd(qlx, hx[r]), gap, _CMP_GT_OQ) |
          _mm512_cmp_pd_mask(_mm512_sub_pd(lx[r], qhx), gap, _CMP_GT_OQ) |
          _mm512_cmp_pd_mask(_mm512_sub_pd(qly, hy[r]), gap, _CMP_GT_OQ) |
          _mm512_cmp_pd_mask(_mm512_sub_pd(ly[r], qhy), gap, _CMP_GT_OQ) |
          _mm512_cmp_pd_mask(_mm512_sub_pd(qlz, hz[r]), gap, _CMP_GT_OQ) |
          _mm512_cmp_pd_mask(_mm512_sub_pd(lz[r], qhz), gap, _CMP_GT_OQ));
      const __m512i gid = _mm512_maskz_cvtepu32_epi64(
          pass,
          _mm256_maskz_loadu_epi32(pass, reinterpret_cast<const int*>(cell.gid.data() + j)));
      __m512i key = _mm512_maskz_slli_epi64(
          pass, _mm512_or_si512(key_base[r], _mm512_sub_epi64(gid, key_sub)), 1);
      key = _mm512_mask_or_epi64(key, static_cast<__mmask8>(~far), key, one);
      std::vector<std::uint64_t>& out = *keys[r];
      std::size_t& count = *n[r];
      if (out.size() < count + 8) out.resize(std::max<std::size_t>(2 * out.size(), count + 256));
      _mm512_mask_compressstoreu_epi64(out.data() + count, pass, key);
      count += static_cast<std::size_t>(__builtin_popcount(pass));
    }
  }
  hits += box_hits;
}

/// The superset variant of cell_rows_avx512 for the speculative broad phase
/// (find_candidates_in_vertex_boxes): items i, ..., i + R - 1 against [j0 + r s, j1) on the
/// cell's float boxes, 16 lanes at a time, with the same dedupe flags, the same adjacency test
/// and the same staggering and key layout. Every pair whose exact boxes overlap passes (the
/// float boxes are the exact ones rounded monotonically: see grid_pairs), and a pair whose float
/// boxes overlap only by rounding passes too; every key is flagged close (no far test). Twice
/// the lanes of the double loop and no confirmation: the speculative task's cell loop is the
/// step's longest part at strong pressure. Bear's P = 4 frames 299-300 (BM_GridOnVertexBoxes,
/// one core, with the gather by kind of grid_chunk_avx512 for both): cell loop 6.5-6.7 against
/// 7.8-9.8 ms, the same 252k pairs (docs/design/self-collision.md).
template <int R>
inline __attribute__((always_inline)) void cell_rows_avx512_float(
    const detail::GridCell& cell, std::size_t i, std::size_t j0, std::size_t j1, bool stagger,
    const std::uint64_t (&base)[R], std::uint32_t sub,
    std::vector<std::uint64_t>* const (&keys)[R], std::size_t* const (&n)[R],
    std::int64_t& hits) {
  __m512 lx[R], ly[R], lz[R], hx[R], hy[R], hz[R];
  __m512i fi[R], a[R], b[R], c[R];
  __m512i key_base[R];
  std::size_t start[R];
  for (int r = 0; r < R; ++r) {
    const std::size_t q = i + static_cast<std::size_t>(r);
    lx[r] = _mm512_set1_ps(cell.lo[0][q]);
    ly[r] = _mm512_set1_ps(cell.lo[1][q]);
    lz[r] = _mm512_set1_ps(cell.lo[2][q]);
    hx[r] = _mm512_set1_ps(cell.hi[0][q]);
    hy[r] = _mm512_set1_ps(cell.hi[1][q]);
    hz[r] = _mm512_set1_ps(cell.hi[2][q]);
    fi[r] = _mm512_set1_epi32(static_cast<int>(cell.flags[q]));
    a[r] = _mm512_set1_epi32(cell.v[0][q]);
    b[r] = _mm512_set1_epi32(cell.v[1][q]);
    c[r] = _mm512_set1_epi32(cell.v[2][q]);
    // (base | (gid - sub)) << 1 | 1 = (base << 1 | 1) + ((gid - sub) << 1): base's low bits
    // below the gid field are zero.
    key_base[r] = _mm512_set1_epi64(static_cast<long long>(base[r] << 1 | 1u));
    start[r] = j0 + (stagger ? static_cast<std::size_t>(r) : 0);
  }
  const __m512i all_first = _mm512_set1_epi32(static_cast<int>(GRID_ALL_FIRST));
  const __m512i key_sub = _mm512_set1_epi64(sub);
  std::int64_t box_hits = 0;
  for (std::size_t j = j0; j < j1; j += 16) {
    const __mmask16 live =
        j1 - j >= 16 ? __mmask16{0xffff} : static_cast<__mmask16>((1u << (j1 - j)) - 1u);
    const __m512i qf = _mm512_maskz_loadu_epi32(live, cell.flags.data() + j);
    const __m512 qlx = _mm512_maskz_loadu_ps(live, cell.lo[0].data() + j);
    const __m512 qhx = _mm512_maskz_loadu_ps(live, cell.hi[0].data() + j);
    const __m512 qly = _mm512_maskz_loadu_ps(live, cell.lo[1].data() + j);
    const __m512 qhy = _mm512_maskz_loadu_ps(live, cell.hi[1].data() + j);
    const __m512 qlz = _mm512_maskz_loadu_ps(live, cell.lo[2].data() + j);
    const __m512 qhz = _mm512_maskz_loadu_ps(live, cell.hi[2].data() + j);
    const __m512i qa = _mm512_maskz_loadu_epi32(live, cell.v[0].data() + j);
    const __m512i qb = _mm512_maskz_loadu_epi32(live, cell.v[1].data() + j);
    const __m512i qc = _mm512_maskz_loadu_epi32(live, cell.v[2].data() + j);
    for (int r = 0; r < R; ++r) {
      const unsigned lanes =
          start[r] > j ? live & ~((1u << (start[r] - j)) - 1u) : static_cast<unsigned>(live);
      const unsigned box =
          lanes & _mm512_cmpeq_epi32_mask(_mm512_or_si512(fi[r], qf), all_first) &
          _mm512_cmp_ps_mask(lx[r], qhx, _CMP_LE_OQ) & _mm512_cmp_ps_mask(qlx, hx[r], _CMP_LE_OQ) &
          _mm512_cmp_ps_mask(ly[r], qhy, _CMP_LE_OQ) & _mm512_cmp_ps_mask(qly, hy[r], _CMP_LE_OQ) &
          _mm512_cmp_ps_mask(lz[r], qhz, _CMP_LE_OQ) & _mm512_cmp_ps_mask(qlz, hz[r], _CMP_LE_OQ);
      const unsigned apart =
          _mm512_cmpneq_epi32_mask(a[r], qa) & _mm512_cmpneq_epi32_mask(a[r], qb) &
          _mm512_cmpneq_epi32_mask(a[r], qc) & _mm512_cmpneq_epi32_mask(b[r], qa) &
          _mm512_cmpneq_epi32_mask(b[r], qb) & _mm512_cmpneq_epi32_mask(c[r], qa) &
          _mm512_cmpneq_epi32_mask(c[r], qb);
      box_hits += __builtin_popcount(box);
      const unsigned pass = box & apart;
      if (pass == 0) continue;
      std::vector<std::uint64_t>& out = *keys[r];
      std::size_t& count = *n[r];
      if (out.size() < count + 16) out.resize(std::max<std::size_t>(2 * out.size(), count + 256));
      for (std::size_t half = 0; half < 2; ++half) {
        const __mmask8 m = static_cast<__mmask8>(pass >> (8 * half));
        if (m == 0) continue;
        const __m512i gid = _mm512_maskz_cvtepu32_epi64(
            m, _mm256_maskz_loadu_epi32(
                   m, reinterpret_cast<const int*>(cell.gid.data() + j + 8 * half)));
        const __m512i key = _mm512_add_epi64(
            key_base[r], _mm512_maskz_slli_epi64(m, _mm512_sub_epi64(gid, key_sub), 1));
        _mm512_storeu_si512(out.data() + count, _mm512_maskz_compress_epi64(m, key));
        count += static_cast<std::size_t>(__builtin_popcount(m));
      }
    }
  }
  hits += box_hits;
}

/// The cells [c0, c1) of the grid with the AVX-512 rows: the same cells, rows and pairs as the
/// portable loop in grid_pairs, on exact boxes (cell_rows_avx512), or with Float a superset of
/// them on float boxes (cell_rows_avx512_float; far_gap unused). The key buffers serve as their
/// own capacity and are trimmed at the end.
template <bool Float>
void grid_chunk_avx512(const GridPrimitives& prim, const std::uint32_t* start,
                       const std::uint32_t* entry, std::size_t c0, std::size_t c1, int vf_shift,
                       int ee_shift, double far_gap, detail::GridChunk& out_chunk) {
  const std::size_t nv = prim.nv, nf = prim.nf;
  detail::GridCell& cell = out_chunk.cell;
  std::size_t nvf = 0, nee = 0;
  for (std::size_t c = c0; c < c1; ++c) {
    const std::uint32_t b = start[c], e = start[c + 1];
    if (e - b < 2) continue;
    const std::size_t k = e - b;
    // The portable loop or the other flavour may have sized the shared buffers but not these.
    if (cell.flags.size() < k || (Float ? cell.lo[0].size() : cell.dlo[0].size()) < k) {
      for (std::size_t d = 0; d < 3; ++d) {
        if constexpr (Float) {
          cell.lo[d].resize(k);
          cell.hi[d].resize(k);
        } else {
          cell.dlo[d].resize(k);
          cell.dhi[d].resize(k);
        }
        cell.v[d].resize(k);
      }
      cell.flags.resize(k);
      cell.gid.resize(k);
    }
    // Each cell lists its vertices, then faces, then edges, each by increasing id (the counting
    // sort's order, kept by patch_grid), so the kinds are three runs: one gather loop per kind,
    // without the per-entry branches on the kind and its corner count.
    const std::uint32_t* const tags = entry + b;
    const std::size_t fb = static_cast<std::size_t>(
        std::partition_point(tags, tags + k, [&](std::uint32_t tag) { return (tag >> 3) < nv; }) -
        tags);
    const std::size_t eb = static_cast<std::size_t>(
        std::partition_point(tags + fb, tags + k,
                             [&](std::uint32_t tag) { return (tag >> 3) < nv + nf; }) -
        tags);
    using Box = std::conditional_t<Float, detail::GridFloatBox, detail::GridVertexBox>;
    const Box* const vbox = [&] {
      if constexpr (Float) return prim.s.grid_vertex_floats.data();
      else return prim.s.grid_vertex_boxes.data();
    }();
    auto put = [&](std::size_t t, std::uint32_t tag, const Box& box, int v0, int v1, int v2) {
      for (std::size_t d = 0; d < 3; ++d) {
        if constexpr (Float) {
          cell.lo[d][t] = box.lo[d];
          cell.hi[d][t] = box.hi[d];
        } else {
          cell.dlo[d][t] = box.lo[d];
          cell.dhi[d][t] = box.hi[d];
        }
      }
      cell.v[0][t] = v0;
      cell.v[1][t] = v1;
      cell.v[2][t] = v2;
      cell.flags[t] = tag & GRID_ALL_FIRST;
      cell.gid[t] = tag >> 3;
    };
    // min and max are exact: a joined box is bit-identical to primitive_box's.
    auto join = [](Box x, const Box& y) {
      for (std::size_t d = 0; d < 3; ++d) {
        x.lo[d] = std::min(x.lo[d], y.lo[d]);
        x.hi[d] = std::max(x.hi[d], y.hi[d]);
      }
      return x;
    };
    auto vb = [&](int v) -> const Box& { return vbox[static_cast<std::size_t>(v)]; };
    for (std::size_t t = 0; t < fb; ++t) {
      const std::uint32_t v = tags[t] >> 3;
      put(t, tags[t], vbox[v], static_cast<int>(v), -1, -1);
    }
    const int* const face_v = prim.topo.faces.data();
    for (std::size_t t = fb; t < eb; ++t) {
      const std::size_t f = (tags[t] >> 3) - nv;
      const int v0 = face_v[3 * f], v1 = face_v[3 * f + 1], v2 = face_v[3 * f + 2];
      put(t, tags[t], join(join(vb(v0), vb(v1)), vb(v2)), v0, v1, v2);
    }
    const int* const edge_v = prim.topo.edges.data();
    for (std::size_t t = eb; t < k; ++t) {
      const std::size_t ed = (tags[t] >> 3) - nv - nf;
      const int v0 = edge_v[2 * ed], v1 = edge_v[2 * ed + 1];
      put(t, tags[t], join(vb(v0), vb(v1)), v0, v1, -2);
    }
    // Rows GRID_ROW_GROUP at a time; row r > 0 of a group writes to row_keys[r - 1], appended
    // after the rows before it, so the keys come in the order of single rows (the portable
    // loop's). `base_of(q)` is item q's key prefix.
    auto rows = [&](auto group, std::size_t i, std::size_t j0, std::size_t j1, bool stagger,
                    auto base_of, std::uint32_t sub, std::vector<std::uint64_t>& keys,
                    std::size_t& count) {
      constexpr int R = decltype(group)::value;
      std::uint64_t base[R];
      std::vector<std::uint64_t>* buffers[R];
      std::size_t row_count[R] = {};
      std::size_t* counts[R];
      for (int r = 0; r < R; ++r) {
        base[r] = base_of(i + static_cast<std::size_t>(r));
        buffers[r] = r == 0 ? &keys : &out_chunk.row_keys[static_cast<std::size_t>(r - 1)];
        counts[r] = r == 0 ? &count : &row_count[r];
      }
      if constexpr (Float)
        cell_rows_avx512_float<R>(cell, i, j0, j1, stagger, base, sub, buffers, counts,
                                  out_chunk.reported);
      else
        cell_rows_avx512<R>(cell, i, j0, j1, stagger, base, sub, far_gap, buffers, counts,
                            out_chunk.reported);
      for (int r = 1; r < R; ++r) {
        const std::size_t m = row_count[r];
        if (m == 0) continue;
        if (keys.size() < count + m) keys.resize(std::max(2 * keys.size(), count + m));
        const std::vector<std::uint64_t>& row = *buffers[r];
        std::copy(row.begin(), row.begin() + static_cast<std::ptrdiff_t>(m),
                  keys.begin() + static_cast<std::ptrdiff_t>(count));
        count += m;
      }
    };
    using Group = std::integral_constant<int, GRID_ROW_GROUP>;
    using Single = std::integral_constant<int, 1>;
    constexpr std::size_t G = GRID_ROW_GROUP;
    // Vertex-face rows: every vertex i < fb against the faces [fb, eb).
    const std::uint32_t vf_sub = static_cast<std::uint32_t>(nv);
    auto vf_base = [&](std::size_t q) {
      return static_cast<std::uint64_t>(cell.v[0][q]) << vf_shift;
    };
    std::size_t i = 0;
    if (eb > fb) {
      for (; i + G <= fb; i += G)
        rows(Group{}, i, fb, eb, false, vf_base, vf_sub, out_chunk.vf_keys, nvf);
      for (; i < fb; ++i)
        rows(Single{}, i, fb, eb, false, vf_base, vf_sub, out_chunk.vf_keys, nvf);
    }
    // Edge-edge rows: edge i against the edges after it, [i + 1, k) (a group needs a j for its
    // last row).
    const std::uint32_t ee_sub = static_cast<std::uint32_t>(nv + nf);
    auto ee_base = [&](std::size_t q) {
      return static_cast<std::uint64_t>(cell.gid[q] - nv - nf) << ee_shift;
    };
    for (i = eb; i + G < k; i += G)
      rows(Group{}, i, i + 1, k, true, ee_base, ee_sub, out_chunk.ee_keys, nee);
    for (; i + 1 < k; ++i)
      rows(Single{}, i, i + 1, k, true, ee_base, ee_sub, out_chunk.ee_keys, nee);
  }
  out_chunk.vf_keys.resize(nvf);
  out_chunk.ee_keys.resize(nee);
}

#pragma GCC pop_options
#endif  // SHELLCONTRACT_GRID_AVX512

void build_grid_vertex_boxes(const Positions& x0, const Positions& x1, double inflation,
                             std::vector<detail::GridVertexBox>& boxes) {
  boxes.resize(static_cast<std::size_t>(x0.rows()));
  for (Eigen::Index v = 0; v < x0.rows(); ++v) {
    detail::GridVertexBox& b = boxes[static_cast<std::size_t>(v)];
    for (Eigen::Index d = 0; d < 3; ++d) {
      const double a = x0(v, d), c = x1(v, d);
      b.lo[static_cast<std::size_t>(d)] = std::min(a, c) - inflation;
      b.hi[static_cast<std::size_t>(d)] = std::max(a, c) + inflation;
    }
  }
}

/// Builds s.grid_vertex_prims (per vertex, the grid ids of the faces and edges it is a corner
/// of) and keeps a copy of the topology it was built for, unless that copy equals `topo`
/// already. Returns whether it was rebuilt.
bool update_vertex_prims(const CollisionTopology& topo, BroadPhaseScratch& s) {
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  const std::size_t nf = static_cast<std::size_t>(topo.faces.rows());
  const std::size_t ne = static_cast<std::size_t>(topo.edges.rows());
  const std::size_t face_ints = 3 * nf, edge_ints = 2 * ne;
  if (s.grid_topology_vertices == nv && s.grid_topology.size() == face_ints + edge_ints &&
      std::equal(topo.faces.data(), topo.faces.data() + face_ints, s.grid_topology.begin()) &&
      std::equal(topo.edges.data(), topo.edges.data() + edge_ints,
                 s.grid_topology.begin() + static_cast<std::ptrdiff_t>(face_ints)))
    return false;
  s.grid_topology_vertices = nv;
  s.grid_topology.assign(topo.faces.data(), topo.faces.data() + face_ints);
  s.grid_topology.insert(s.grid_topology.end(), topo.edges.data(), topo.edges.data() + edge_ints);
  // Counting sort of (vertex, primitive) by vertex: faces first, then edges, each by id, so
  // each vertex lists its primitives in increasing grid id.
  std::vector<std::uint32_t>& start = s.grid_vertex_prims_start;
  start.assign(nv + 1, 0);
  for (std::size_t k = 0; k < face_ints + edge_ints; ++k)
    ++start[static_cast<std::size_t>(s.grid_topology[k]) + 1];
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  s.grid_vertex_prims.resize(start[nv]);
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t k = 0; k < face_ints + edge_ints; ++k) {
    const std::size_t gid = k < face_ints ? nv + k / 3 : nv + nf + (k - face_ints) / 2;
    s.grid_vertex_prims[fill[static_cast<std::size_t>(s.grid_topology[k])]++] =
        static_cast<std::uint32_t>(gid);
  }
  return true;
}

/// Updates the kept grid's counting sort (s.cell_start, s.cell_entries over s.grid_ranges) for
/// this call's vertex ranges (s.grid_vertex_ranges; the last call's, on the same grid g, in
/// s.grid_vertex_ranges_prev): the boxes whose range changed leave their old cells and enter
/// their new ones, and s.grid_ranges gets their new ranges. Only a box with a vertex whose range
/// changed can change (a box's range is the union of its vertices'; the topology is compared
/// with the last call's, and if it differs every box is recomputed). The result is what the
/// counting sort builds from the new ranges (each cell lists its boxes in increasing id order,
/// with the same flags), because an entry depends only on its box's id and range. Returns false,
/// leaving the counting sort as it was, if more than nboxes / GRID_PATCH_DIVISOR ranges changed
/// (s.grid_ranges is then stale: the caller rebuilds it).
bool patch_grid(const Grid& g, const GridPrimitives& prim, std::size_t nboxes,
                BroadPhaseScratch& s) {
  const std::size_t nv = prim.nv;
  const std::vector<detail::GridRange>& vr = s.grid_vertex_ranges;
  const std::vector<detail::GridRange>& vr_prev = s.grid_vertex_ranges_prev;
  auto same = [](const detail::GridRange& a, const detail::GridRange& b) {
    return a.lo[0] == b.lo[0] && a.lo[1] == b.lo[1] && a.lo[2] == b.lo[2] &&
           a.hi[0] == b.hi[0] && a.hi[1] == b.hi[1] && a.hi[2] == b.hi[2];
  };
  // The boxes that may have changed: every one after a change of topology, else those with a
  // vertex whose range changed (a bit per box; a bitset stays in the first-level cache).
  const std::size_t words = (nboxes + 63) / 64;
  std::vector<std::uint64_t>& maybe = s.grid_maybe_bits;
  const bool all = update_vertex_prims(prim.topo, s) || vr_prev.size() != nv;
  maybe.assign(words, all ? ~std::uint64_t{0} : 0);
  if (!all) {
    auto mark = [&](std::size_t id) { maybe[id >> 6] |= std::uint64_t{1} << (id & 63); };
    for (std::size_t v = 0; v < nv; ++v) {
      if (same(vr[v], vr_prev[v])) continue;
      mark(v);
      for (std::uint32_t k = s.grid_vertex_prims_start[v]; k < s.grid_vertex_prims_start[v + 1];
           ++k)
        mark(s.grid_vertex_prims[k]);
    }
  }
  // The changed boxes, in increasing id order, their new ranges, and a bit per changed box for
  // the merge's lookups.
  s.grid_changed_ids.clear();
  s.grid_changed_ranges.clear();
  s.grid_changed_bits.assign(words, 0);
  const std::size_t limit = nboxes / GRID_PATCH_DIVISOR;
  for (std::size_t w = 0; w < words; ++w)
    for (std::uint64_t bits = maybe[w]; bits != 0; bits &= bits - 1) {
      const std::size_t i = 64 * w + static_cast<std::size_t>(__builtin_ctzll(bits));
      if (i >= nboxes) break;
      const detail::GridRange n = prim.range(prim.ids(i));
      if (same(n, s.grid_ranges[i])) continue;
      if (s.grid_changed_ids.size() == limit) return false;
      s.grid_changed_ids.push_back(static_cast<std::uint32_t>(i));
      s.grid_changed_ranges.push_back(n);
      s.grid_changed_bits[i >> 6] |= std::uint64_t{1} << (i & 63);
    }
  // The changed boxes' new entries, counting-sorted by cell (in id order within a cell).
  const std::size_t ncell = g.cells();
  std::vector<std::uint32_t>& add_start = s.grid_add_start;
  add_start.assign(ncell + 1, 0);
  const std::size_t nchanged = s.grid_changed_ids.size();
  for (const detail::GridRange& r : s.grid_changed_ranges)
    for_each_cell(g, r,
                  [&](std::size_t c, std::uint32_t, bool valid) { add_start[c + 1] += valid; });
  for (std::size_t c = 0; c < ncell; ++c) add_start[c + 1] += add_start[c];
  s.grid_adds.resize(add_start[ncell]);
  s.cell_fill.assign(add_start.begin(), add_start.end() - 1);
  for (std::size_t k = 0; k < nchanged; ++k) {
    const std::uint32_t tag = s.grid_changed_ids[k] << 3;
    for_each_cell(g, s.grid_changed_ranges[k],
                  [&](std::size_t c, std::uint32_t flags, bool valid) {
                    if (valid) s.grid_adds[s.cell_fill[c]++] = tag | flags;
                  });
  }
  // The cells the patch changes: those of the changed boxes' old ranges (entries leave) and
  // new ranges (entries come). The others keep their entries, copied as runs of cells.
  s.grid_dirty.assign(ncell + 1, 0);
  std::uint8_t* const dirty = s.grid_dirty.data();
  for (std::size_t k = 0; k < nchanged; ++k) {
    const auto mark = [&](std::size_t c, std::uint32_t, bool valid) {
      dirty[valid ? c : ncell] = 1;
    };
    for_each_cell(g, s.grid_ranges[s.grid_changed_ids[k]], mark);
    for_each_cell(g, s.grid_changed_ranges[k], mark);
  }
  // Merge cell by cell: the old entries without the changed boxes', and the new ones.
  const std::vector<std::uint32_t>& start = s.cell_start;
  const std::uint32_t* const entry = s.cell_entries.data();
  const std::uint32_t* const adds = s.grid_adds.data();
  const std::uint64_t* const gone = s.grid_changed_bits.data();
  std::vector<std::uint32_t>& next_start = s.cell_start_next;
  std::vector<std::uint32_t>& next_entries = s.cell_entries_next;
  next_start.resize(ncell + 1);
  next_entries.resize(static_cast<std::size_t>(start[ncell]) + s.grid_adds.size());
  std::uint32_t* const next = next_entries.data();
  auto kept = [&](std::uint32_t tag) {
    const std::uint32_t id = tag >> 3;
    return ((gone[id >> 6] >> (id & 63)) & 1u) == 0;
  };
  std::size_t out = 0;
  for (std::size_t c = 0; c < ncell; ++c) {
    if (!dirty[c]) {  // a run of unchanged cells: shifted offsets, one copy of their entries
      const std::size_t run = c;
      const std::uint32_t shift = static_cast<std::uint32_t>(out) - start[run];  // mod 2^32
      for (; c < ncell && !dirty[c]; ++c) next_start[c] = start[c] + shift;
      std::copy(entry + start[run], entry + start[c], next + out);
      out += start[c] - start[run];
      if (c == ncell) break;
    }
    next_start[c] = static_cast<std::uint32_t>(out);
    std::uint32_t k = start[c];
    const std::uint32_t e = start[c + 1];
    for (std::uint32_t a = add_start[c]; a < add_start[c + 1]; ++a) {
      for (; k < e && entry[k] < adds[a]; ++k) {
        next[out] = entry[k];
        out += kept(entry[k]) ? 1 : 0;
      }
      next[out++] = adds[a];
    }
    for (; k < e; ++k) {
      next[out] = entry[k];
      out += kept(entry[k]) ? 1 : 0;
    }
  }
  next_start[ncell] = static_cast<std::uint32_t>(out);
  next_entries.resize(out);
  s.cell_start.swap(next_start);
  s.cell_entries.swap(next_entries);
  for (std::size_t k = 0; k < nchanged; ++k)
    s.grid_ranges[s.grid_changed_ids[k]] = s.grid_changed_ranges[k];
  s.grid_patched_boxes = static_cast<std::int64_t>(nchanged);
  return true;
}

/// Method Grid (x0, x1 already in s.grid_vertex_boxes). A pair whose two boxes have a gap above
/// far_gap on some axis is flagged 0 in out's close flags (see find_candidates). With
/// float_superset and the AVX-512 loop, the pairs whose float boxes overlap, all flagged close
/// (see find_candidates_in_vertex_boxes). Returns -1
/// (nothing done) if the grid would degenerate (see GRID_WORK_PER_BOX), otherwise the number of
/// box pairs that overlap after rounding outward to float, adjacent ones included (VF, plus EE
/// once per unordered pair).
std::int64_t grid_pairs(const CollisionTopology& topo, double far_gap, CandidatePairs& out,
                        bool float_superset = false) {
  BroadPhaseScratch& s = *out.scratch;
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  const std::size_t nf = static_cast<std::size_t>(topo.faces.rows());
  const std::size_t ne = static_cast<std::size_t>(topo.edges.rows());
  const std::size_t nboxes = nv + nf + ne;
  // The output lists are cleared only where nothing is found; the output stage resizes them
  // from the last call's sizes, so that only growth is value-initialized (clearing first made
  // the resize zero-fill every pair: 0.3% of perf's samples of bear's P = 4 run, ~0.13 ms of the
  // speculative task per step).
  auto nothing = [&](std::int64_t result) {
    out.vertex_face.clear();
    out.edge_edge.clear();
    out.vertex_face_close.clear();
    out.edge_edge_close.clear();
    return result;
  };
  const auto t_start = std::chrono::steady_clock::now();
  s.grid_build_seconds = s.grid_cell_loop_seconds = s.grid_output_seconds = 0.0;
  auto seconds_since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  // The last call's grid, if complete, and what it was built for (see patch_grid).
  const bool had_grid =
      s.grid_kept && s.grid_ranges.size() == nboxes &&
      s.cell_start.size() == s.grid_dims[0] * s.grid_dims[1] * s.grid_dims[2] + 1;
  s.grid_kept = false;
  s.grid_patched_boxes = -1;
  if (nv == 0) return nothing(0);
  if (nboxes >= GRID_MAX_BOXES) return nothing(-1);
  const GridPrimitives prim{topo, s, nv, nf};
  const std::vector<detail::GridVertexBox>& vbox = s.grid_vertex_boxes;

  // Scene bounds: every face and edge box is a union of vertex boxes.
  std::array<double, 3> lo = vbox[0].lo, hi = vbox[0].hi;
  for (const detail::GridVertexBox& b : vbox)
    for (std::size_t d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], b.lo[d]);
      hi[d] = std::max(hi[d], b.hi[d]);
    }

  // Cell size from the median largest side of a deterministic sample of face and edge boxes.
  s.extent_sample.clear();
  const std::size_t stride = std::max<std::size_t>(1, (nf + ne) / GRID_EXTENT_SAMPLES);
  for (std::size_t i = nv; i < nboxes; i += stride) {
    const detail::GridVertexBox b = prim.box(prim.ids(i));
    s.extent_sample.push_back(std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]}));
  }
  double h = 0.0;
  if (!s.extent_sample.empty()) {
    const auto mid =
        s.extent_sample.begin() + static_cast<std::ptrdiff_t>(s.extent_sample.size() / 2);
    std::nth_element(s.extent_sample.begin(), mid, s.extent_sample.end());
    h = GRID_CELL_FACTOR * *mid;
  }
  const double span = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  // Degenerate extents (points: no motion, no inflation, zero-length edges) or no primitives.
  if (!(h > 0.0)) h = span > 0.0 ? span : 1.0;

  // Float boxes relative to the scene minimum (better precision than absolute coordinates).
  // Each double is rounded outward after the subtraction; the rounded subtraction is monotone,
  // so whenever two double boxes overlap, so do their float boxes: the float test only culls.
  // The AVX-512 cell loop tests the double boxes directly and needs none, unless the caller
  // takes a superset (float_superset: find_candidates_in_vertex_boxes), which it then emits
  // from float boxes alone.
  const bool avx512 = s.grid_isa == detail::GridIsa::Auto && detail::grid_avx512_available();
  const bool float_cells = avx512 && float_superset;
  s.grid_vertex_floats.resize(avx512 && !float_cells ? 0 : nv);
  if (float_cells) {
    // The superset loop needs only a monotone map from the doubles to the floats (it keeps
    // every overlap: a <= b implies f(a) <= f(b)), and a rounded subtraction followed by a
    // rounded conversion is one; the outward rounding of the portable path costs 10x more here
    // (bench_broad_phase, 0.5 ms per call on bear).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, GRID_VERTEX_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t v = r.begin(); v < r.end(); ++v)
                          for (std::size_t d = 0; d < 3; ++d) {
                            detail::GridFloatBox& f = s.grid_vertex_floats[v];
                            f.lo[d] = static_cast<float>(vbox[v].lo[d] - lo[d]);
                            f.hi[d] = static_cast<float>(vbox[v].hi[d] - lo[d]);
                          }
                      });
  } else if (!avx512) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, GRID_VERTEX_GRAIN),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t v = r.begin(); v < r.end(); ++v)
                        for (std::size_t d = 0; d < 3; ++d) {
                          s.grid_vertex_floats[v].lo[d] = round_down(vbox[v].lo[d] - lo[d]);
                          s.grid_vertex_floats[v].hi[d] = round_up(vbox[v].hi[d] - lo[d]);
                        }
                    });
  }

  // The counting sort below runs in `parts` parts, each over a contiguous range of box ids with
  // its own counters; part p's entries of a cell follow those of parts < p, so every cell lists
  // its boxes in id order whatever the number of parts (and threads).
  const std::size_t parts = std::clamp<std::size_t>(
      static_cast<std::size_t>(tbb::this_task_arena::max_concurrency()), 1, GRID_MAX_PARTS);
  auto part_begin = [&](std::size_t p) { return nboxes * p / parts; };

  // Count the (cell, box) entries per cell; double the cell size while there are too many.
  const std::size_t max_cells = std::max<std::size_t>(64, GRID_CELLS_PER_BOX * nboxes);
  Grid g;
  std::vector<std::uint32_t>& start = s.cell_start;
  std::size_t entries = 0;
  auto vertex_ranges = [&] {
    s.grid_vertex_ranges.resize(nv);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, GRID_VERTEX_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t v = r.begin(); v < r.end(); ++v)
                          for (std::size_t d = 0; d < 3; ++d) {
                            s.grid_vertex_ranges[v].lo[d] = g.coord(vbox[v].lo[d], d);
                            s.grid_vertex_ranges[v].hi[d] = g.coord(vbox[v].hi[d], d);
                          }
                      });
  };
  // Temporal coherence: from one step to the next most boxes keep their cell ranges, so the
  // last call's grid is kept while its cell size is still about the desired one and the scene
  // is inside it, and its counting sort is patched for the boxes that changed ranges.
  bool reuse = had_grid && s.grid_patch;
  if (reuse) {
    const double kept_h = 1.0 / s.grid_inv_h;
    reuse = kept_h <= GRID_REUSE_FACTOR * h && h <= GRID_REUSE_FACTOR * kept_h;
    for (std::size_t d = 0; d < 3 && reuse; ++d)
      reuse = lo[d] >= s.grid_origin[d] &&
              (hi[d] - s.grid_origin[d]) * s.grid_inv_h < static_cast<double>(s.grid_dims[d]);
  }
  bool patched = false;
  if (reuse) {
    g.origin = s.grid_origin;
    g.inv_h = s.grid_inv_h;
    g.dims = s.grid_dims;
    // The last call's vertex ranges are on this grid too (it kept it, or made it): patch_grid
    // compares them with this call's.
    s.grid_vertex_ranges_prev.swap(s.grid_vertex_ranges);
    vertex_ranges();
    if (!s.grid_patch_always_rebuild) patched = patch_grid(g, prim, nboxes, s);
    if (patched) entries = start[g.cells()];
  }
  s.grid_ranges.resize(nboxes);
  for (bool first = true; !patched; first = false) {
    if (!(first && reuse)) {
      // Half a cell of margin on every side, so that a scene that drifts or grows a little
      // keeps the grid (and its patches) in the next steps.
      std::array<double, 3> glo = lo, ghi = hi;
      for (std::size_t d = 0; d < 3; ++d) {
        glo[d] -= GRID_MARGIN_CELLS * h;
        ghi[d] += GRID_MARGIN_CELLS * h;
      }
      g = make_grid(glo, ghi, h, max_cells);
      vertex_ranges();
    }
    const std::size_t ncell = g.cells();
    // Part p counts cell c in cell_count[p * (ncell + 1) + c]; the extra slot per part absorbs
    // the invalid visits of the 2x2x2 pattern.
    s.cell_count.assign(parts * (ncell + 1), 0);
    tbb::parallel_for(std::size_t{0}, parts, [&](std::size_t p) {
      std::uint32_t* count = s.cell_count.data() + p * (ncell + 1);
      for (std::size_t i = part_begin(p); i < part_begin(p + 1); ++i) {
        s.grid_ranges[i] = prim.range(prim.ids(i));
        for_each_cell(g, s.grid_ranges[i],
                      [&](std::size_t c, std::uint32_t, bool valid) { count[c] += valid; });
      }
    });
    start.assign(ncell + 1, 0);
    for (std::size_t p = 0; p < parts; ++p) {
      const std::uint32_t* count = s.cell_count.data() + p * (ncell + 1);
      for (std::size_t c = 0; c < ncell; ++c) start[c + 1] += count[c];
    }
    entries = 0;
    for (std::size_t c = 1; c <= ncell; ++c) entries += start[c];
    if (entries <= GRID_ENTRIES_PER_BOX * nboxes || ncell == 1) break;
    h = 2.0 / g.inv_h;
  }
  const std::size_t ncell = g.cells();
  // Cell sizes: counts from the counting sort, offsets from a patch.
  std::int64_t work = 0;
  for (std::size_t c = 1; c <= ncell; ++c) {
    const std::int64_t k = patched ? start[c] - start[c - 1] : start[c];
    work += k * (k - 1) / 2;
  }
  if (work > GRID_WORK_PER_BOX * static_cast<std::int64_t>(nboxes)) return nothing(-1);
  if (!patched) {
    for (std::size_t c = 1; c <= ncell; ++c) start[c] += start[c - 1];
    // Counting-sort scatter. Part p's cursor of cell c starts after the entries of parts < p;
    // invalid visits write to the part's own sink slot past the end (cursor ncell), which keeps
    // the 2x2x2 pattern branch-free. Boxes go in in id order within each part, so each cell lists
    // its vertices, then faces, then edges, each by increasing id.
    s.cell_fill.resize(parts * (ncell + 1));
    for (std::size_t c = 0; c < ncell; ++c) {
      std::uint32_t cursor = start[c];
      for (std::size_t p = 0; p < parts; ++p) {
        s.cell_fill[p * (ncell + 1) + c] = cursor;
        cursor += s.cell_count[p * (ncell + 1) + c];
      }
    }
    s.cell_entries.resize(entries + parts);
    tbb::parallel_for(std::size_t{0}, parts, [&](std::size_t p) {
      std::uint32_t* fill = s.cell_fill.data() + p * (ncell + 1);
      std::uint32_t* entry = s.cell_entries.data();
      fill[ncell] = static_cast<std::uint32_t>(entries + p);
      for (std::size_t i = part_begin(p); i < part_begin(p + 1); ++i) {
        const std::uint32_t tag = static_cast<std::uint32_t>(i) << 3;
        for_each_cell(g, s.grid_ranges[i], [&](std::size_t c, std::uint32_t flags, bool valid) {
                        const std::size_t slot = valid ? c : ncell;
                        entry[fill[slot]] = tag | flags;
                        fill[slot] += valid;
                      });
      }
    });
  }

  s.grid_kept = true;
  s.grid_build_seconds = seconds_since(t_start);
  const auto t_cells = std::chrono::steady_clock::now();
  s.grid_origin = g.origin;
  s.grid_inv_h = g.inv_h;
  s.grid_dims = g.dims;

  // Per cell: gather the items (float boxes, vertex ids, flags) into structure-of-arrays
  // buffers, build the candidate masks (cell_masks), and confirm the rare survivors with the
  // exact double boxes. Cells are split into GRID_CHUNKS chunks of about equal entry counts,
  // processed in parallel, each into its own key buffers, concatenated in chunk order
  // afterwards (each pair is emitted exactly once).
  const int vf_shift = std::max(1, bit_width(nf));
  const int ee_shift = std::max(1, bit_width(ne));
  s.chunks.resize(GRID_CHUNKS);
  s.chunk_cells.assign(GRID_CHUNKS + 1, g.cells());
  s.chunk_cells[0] = 0;
  for (std::size_t c = 0, k = 1; c < g.cells() && k < GRID_CHUNKS; ++c)
    while (k < GRID_CHUNKS && start[c] >= entries * k / GRID_CHUNKS) s.chunk_cells[k++] = c;
  const std::uint32_t* entry = s.cell_entries.data();
  tbb::parallel_for(std::size_t{0}, GRID_CHUNKS, [&](std::size_t chunk) {
    detail::GridChunk& out_chunk = s.chunks[chunk];
    out_chunk.reported = 0;
    detail::GridCell& cell = out_chunk.cell;
#if SHELLCONTRACT_GRID_AVX512
    if (float_cells) {
      grid_chunk_avx512<true>(prim, start.data(), entry, s.chunk_cells[chunk],
                              s.chunk_cells[chunk + 1], vf_shift, ee_shift, far_gap, out_chunk);
      return;
    }
    if (avx512) {
      grid_chunk_avx512<false>(prim, start.data(), entry, s.chunk_cells[chunk],
                               s.chunk_cells[chunk + 1], vf_shift, ee_shift, far_gap, out_chunk);
      return;
    }
#endif
    out_chunk.vf_keys.clear();
    out_chunk.ee_keys.clear();
    for (std::size_t c = s.chunk_cells[chunk]; c < s.chunk_cells[chunk + 1]; ++c) {
      const std::uint32_t b = start[c], e = start[c + 1];
      if (e - b < 2) continue;
      const std::size_t k = e - b;
      // The AVX-512 loop may have sized the shared buffers but not these.
      if (cell.flags.size() < k || cell.lo[0].size() < k || cell.mask.size() < k) {
        for (std::size_t d = 0; d < 3; ++d) {
          cell.lo[d].resize(k);
          cell.hi[d].resize(k);
          cell.v[d].resize(k);
        }
        cell.flags.resize(k);
        cell.gid.resize(k);
        cell.mask.resize(k);
      }
      std::size_t fb = 0, eb = 0;
      for (std::size_t t = 0; t < k; ++t) {
        const std::uint32_t tag = entry[b + t];
        const std::size_t gid = tag >> 3;
        const std::array<int, 3> v = prim.ids(gid);
        const detail::GridFloatBox fbox = prim.float_box(v);
        for (std::size_t d = 0; d < 3; ++d) {
          cell.lo[d][t] = fbox.lo[d];
          cell.hi[d][t] = fbox.hi[d];
          cell.v[d][t] = v[d];
        }
        cell.flags[t] = tag & GRID_ALL_FIRST;
        cell.gid[t] = static_cast<std::uint32_t>(gid);
        fb += gid < nv;
        eb += gid < nv + nf;
      }
      std::uint32_t* mask = cell.mask.data();
      for (std::size_t i = 0; i < fb && eb > fb; ++i) {
        if (!cell_masks(cell, i, fb, eb, mask, out_chunk.reported)) continue;
        for (std::size_t j = fb; j < eb; ++j) {
          if (mask[j] == 0) continue;
          const std::array<int, 3> fv = {cell.v[0][j], cell.v[1][j], cell.v[2][j]};
          const int vi = cell.v[0][i];
          const detail::GridVertexBox& a = vbox[static_cast<std::size_t>(vi)];
          const detail::GridVertexBox fbox = prim.box(fv);
          if (!overlap(a, fbox)) continue;
          const std::uint64_t close = gap_above(a, fbox, far_gap) ? 0u : 1u;
          out_chunk.vf_keys.push_back(
              (static_cast<std::uint64_t>(vi) << vf_shift | (cell.gid[j] - nv)) << 1 | close);
        }
      }
      for (std::size_t i = eb; i + 1 < k; ++i) {
        if (!cell_masks(cell, i, i + 1, k, mask, out_chunk.reported)) continue;
        const detail::GridVertexBox pbox = prim.box({cell.v[0][i], cell.v[1][i], -2});
        const std::uint64_t high = static_cast<std::uint64_t>(cell.gid[i] - nv - nf) << ee_shift;
        for (std::size_t j = i + 1; j < k; ++j) {
          if (mask[j] == 0) continue;
          const detail::GridVertexBox qbox = prim.box({cell.v[0][j], cell.v[1][j], -2});
          if (!overlap(pbox, qbox)) continue;
          const std::uint64_t close = gap_above(pbox, qbox, far_gap) ? 0u : 1u;
          // Entries of a cell are in increasing id order, so a < b.
          out_chunk.ee_keys.push_back((high | (cell.gid[j] - nv - nf)) << 1 | close);
        }
      }
    }
  });
  s.grid_cell_loop_seconds = seconds_since(t_cells);
  const auto t_output = std::chrono::steady_clock::now();
  // The chunks' pairs one after the other: the chunks are cut by entry counts, not by threads,
  // so this order (cells, then rows within a cell) does not depend on the thread count. No sort:
  // it cost 2 ms per call on the collapsed bear, and callers need a fixed order, not a sorted one.
  std::int64_t reported = 0;
  std::size_t vf_total = 0, ee_total = 0;
  std::vector<std::size_t>& offset = s.chunk_offsets;  // VF offsets, then EE offsets, per chunk
  offset.assign(2 * GRID_CHUNKS, 0);
  for (std::size_t c = 0; c < GRID_CHUNKS; ++c) {
    reported += s.chunks[c].reported;
    offset[c] = vf_total;
    offset[GRID_CHUNKS + c] = ee_total;
    vf_total += s.chunks[c].vf_keys.size();
    ee_total += s.chunks[c].ee_keys.size();
  }
  out.vertex_face.resize(vf_total);
  out.vertex_face_close.resize(vf_total);
  out.edge_edge.resize(ee_total);
  out.edge_edge_close.resize(ee_total);
  tbb::parallel_for(std::size_t{0}, GRID_CHUNKS, [&](std::size_t c) {
    unpack_keys(s.chunks[c].vf_keys, vf_shift, offset[c], out.vertex_face, out.vertex_face_close);
    unpack_keys(s.chunks[c].ee_keys, ee_shift, offset[GRID_CHUNKS + c], out.edge_edge,
                out.edge_edge_close);
  });
  s.grid_output_seconds = seconds_since(t_output);
  return reported;
}


/// Thrown by has_any_candidate's callbacks to stop CGAL's search at the first pair.
struct CandidateFound {};

}  // namespace

namespace detail {
bool grid_avx512_available() {
#if SHELLCONTRACT_GRID_AVX512
  static const bool available =
      __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
  return available;
#else
  return false;
#endif
}
}  // namespace detail

CandidatePairs::CandidatePairs() : scratch(std::make_unique<BroadPhaseScratch>()) {}
CandidatePairs::~CandidatePairs() = default;
CandidatePairs::CandidatePairs(CandidatePairs&&) noexcept = default;
CandidatePairs& CandidatePairs::operator=(CandidatePairs&&) noexcept = default;

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

  std::vector<std::uint8_t> referenced(static_cast<std::size_t>(num_vertices), 0);
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) referenced[static_cast<std::size_t>(faces(f, k))] = 1;
  for (int v = 0; v < num_vertices; ++v)
    if (!referenced[static_cast<std::size_t>(v)]) topo.orphan_vertices.push_back(v);

  // Table 2 "no culling": every pair a brute-force narrow phase would test.
  topo.all_vertex_face_pairs = static_cast<std::int64_t>(num_vertices) * nf - 3 * nf;
  std::int64_t sharing = 0;  // unordered edge pairs with a common vertex (exactly one, edges unique)
  for (const std::int64_t d : degree) sharing += d * (d - 1) / 2;
  topo.all_edge_edge_pairs = static_cast<std::int64_t>(ne) * (ne - 1) / 2 - sharing;
  return topo;
}

double far_gap_threshold(const Positions& x0, const Positions& x1, double inflation,
                         double far_distance) {
  // A pair is flagged far if on some axis the gap g between its two (inflated, rounded) boxes
  // exceeds far_gap. Each box bound is fl(c -+ inflation) for an exact coordinate c with
  // |c| <= M, off by at most u (M + inflation), and the computed difference adds u (2M +
  // 2 inflation) (1 + u); so g > far_gap = (far - 2 inflation) + 8 u (M + inflation + far),
  // itself rounded a few times (a few u (far + 2 inflation) more), leaves the exact gap of the
  // boxes before inflation above `far`.
  if (!(far_distance >= 0.0) || !std::isfinite(far_distance))
    return std::numeric_limits<double>::infinity();
  const double m =
      x0.rows() > 0 ? std::max(x0.cwiseAbs().maxCoeff(), x1.cwiseAbs().maxCoeff()) : 0.0;
  return far_gap_threshold_for_magnitude(m, inflation, far_distance);
}

double far_gap_threshold_for_magnitude(double max_abs, double inflation, double far_distance) {
  if (!(far_distance >= 0.0) || !std::isfinite(far_distance))
    return std::numeric_limits<double>::infinity();
  constexpr double u = std::numeric_limits<double>::epsilon() / 2.0;
  return (far_distance - 2.0 * inflation) + 8.0 * u * (max_abs + inflation + far_distance);
}

bool find_candidates_in_vertex_boxes(const std::vector<detail::GridVertexBox>& boxes,
                                     const CollisionTopology& topo, CandidatePairs& out) {
  if (boxes.size() != static_cast<std::size_t>(topo.num_vertices))
    throw UsageError("broad phase: " + std::to_string(boxes.size()) + " vertex boxes for " +
                     std::to_string(topo.num_vertices) + " vertices");
  out.scratch->grid_vertex_boxes = boxes;
  if (grid_pairs(topo, std::numeric_limits<double>::infinity(), out,
                 out.scratch->grid_float_superset) >= 0)
    return true;
  out.scratch->grid_kept = false;
  return false;
}

void query_kept_grid(const CandidatePairs& pairs, const CollisionTopology& topo,
                     const detail::GridVertexBox& box, std::vector<std::uint32_t>& out,
                     std::uint32_t first_id, std::uint32_t end_id) {
  const BroadPhaseScratch& s = *pairs.scratch;
  if (!s.grid_kept) throw UsageError("query_kept_grid: no grid is kept");
  Grid g;
  g.origin = s.grid_origin;
  g.inv_h = s.grid_inv_h;
  g.dims = s.grid_dims;
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  const GridPrimitives prim{topo, s, nv, static_cast<std::size_t>(topo.faces.rows())};
  std::array<std::size_t, 3> lo{}, hi{};
  for (std::size_t d = 0; d < 3; ++d) {
    lo[d] = g.coord(box.lo[d], d);
    hi[d] = g.coord(box.hi[d], d);
  }
  // A stored box meets the query in every cell of the intersection of their cell ranges (coord
  // is monotone); it is reported in the first of them, where on each axis the cell is the stored
  // box's first (its entry flag) or the query's first.
  const std::size_t sy = g.dims[0], sz = g.dims[0] * g.dims[1];
  for (std::size_t z = lo[2]; z <= hi[2]; ++z)
    for (std::size_t y = lo[1]; y <= hi[1]; ++y)
      for (std::size_t x = lo[0]; x <= hi[0]; ++x) {
        const std::size_t c = z * sz + y * sy + x;
        const std::uint32_t query_first =
            (x == lo[0] ? 1u : 0u) | (y == lo[1] ? 2u : 0u) | (z == lo[2] ? 4u : 0u);
        // The cell's entries are in increasing id order (the counting sort's), so the ids
        // asked for are one run of them: found by binary search, the rest never touched (a
        // vertex's query asks for the faces only, about a third of a cell's entries; a face's
        // for the vertices, about a sixth).
        const std::uint32_t* const cell_begin = s.cell_entries.data() + s.cell_start[c];
        const std::uint32_t* const cell_end = s.cell_entries.data() + s.cell_start[c + 1];
        const std::uint32_t* k = std::partition_point(
            cell_begin, cell_end, [&](std::uint32_t tag) { return (tag >> 3) < first_id; });
        for (; k != cell_end; ++k) {
          const std::uint32_t tag = *k;
          const std::uint32_t gid = tag >> 3;
          if (gid >= end_id) break;
          if (((tag | query_first) & GRID_ALL_FIRST) != GRID_ALL_FIRST) continue;
          if (overlap(box, prim.box(prim.ids(gid)))) out.push_back(gid);
        }
      }
}

void find_candidates(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                     double inflation, CandidatePairs& out, BroadPhaseStats* stats,
                     BroadPhaseMethod method, double far_distance) {
  const auto start = std::chrono::steady_clock::now();
  check_inputs(x0, x1, topo, inflation);
  const double far_gap = far_gap_threshold(x0, x1, inflation, far_distance);
  // Grid keeps only vertex boxes (GridVertexBox); the others share BroadPhaseBox.
  if (method == BroadPhaseMethod::Grid)
    build_grid_vertex_boxes(x0, x1, inflation, out.scratch->grid_vertex_boxes);
  else
    build_boxes(x0, x1, topo, inflation, *out.scratch, true, true);
  std::int64_t reported = 0;
  BroadPhaseMethod ran = method;
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
    case BroadPhaseMethod::Grid:
      reported = grid_pairs(topo, far_gap, out);
      if (reported < 0) {
        ran = BroadPhaseMethod::PrimitiveBoxes;
        build_boxes(x0, x1, topo, inflation, *out.scratch, true, true);
        reported = primitive_boxes(topo, out);
      }
      break;
  }
  if (ran != BroadPhaseMethod::Grid) {
    // Only the grid has the exact boxes at hand when it emits a pair: the others flag none far.
    out.vertex_face_close.assign(out.vertex_face.size(), 1);
    out.edge_edge_close.assign(out.edge_edge.size(), 1);
  }
  if (stats) {
    stats->no_culling_vertex_face = topo.all_vertex_face_pairs;
    stats->no_culling_edge_edge = topo.all_edge_edge_pairs;
    stats->box_overlaps = reported;
    stats->method_run = ran;
    stats->vertex_face = static_cast<std::int64_t>(out.vertex_face.size());
    stats->edge_edge = static_cast<std::int64_t>(out.edge_edge.size());
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
}

bool has_any_candidate(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                       double inflation, CandidatePairs& buffers) {
  BroadPhaseScratch& scratch = *buffers.scratch;
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
