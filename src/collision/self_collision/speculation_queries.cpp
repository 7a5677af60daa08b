// The speculative broad phase's queries: the primitives with a vertex outside its predicted box,
// against the kept grid and against each other; their pairs are appended after the grid's.
#include <algorithm>

#include "collision/broad_phase/scratch.hpp"
#include "collision/self_collision/speculation.hpp"

namespace shellcontract::collision_pipeline {

std::size_t Speculation::query_escaped(const RestPairs& rest, const CandidatePairs& candidates,
                                       StepPairs& pairs, double far_gap) {
  const std::size_t nvs = static_cast<std::size_t>(topo_.num_vertices);
  const std::size_t nf = static_cast<std::size_t>(topo_.faces.rows());
  std::size_t appended = 0;
  auto overlap = [](const detail::GridVertexBox& a, const detail::GridVertexBox& b) {
    return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1] &&
           a.lo[2] <= b.hi[2] && b.lo[2] <= a.hi[2];
  };
  auto far = [&](const detail::GridVertexBox& a, const detail::GridVertexBox& b) {
    return b.lo[0] - a.hi[0] > far_gap || a.lo[0] - b.hi[0] > far_gap ||
           b.lo[1] - a.hi[1] > far_gap || a.lo[1] - b.hi[1] > far_gap ||
           b.lo[2] - a.hi[2] > far_gap || a.lo[2] - b.hi[2] > far_gap;
  };
  // The primitives with a vertex outside its predicted box: each against the grid's primitives
  // without one (whose actual boxes are inside their predicted ones, so the query sees every
  // actual overlap), then against each other by a sweep along x. The queries run in parallel
  // blocks, which measured faster than serial (lab/history.md).
  auto ids = [&](std::uint32_t gid) { return detail::primitive_vertices(topo_, gid); };
  auto outside = [&](std::uint32_t gid) {
    const std::array<int, 3> v = ids(gid);
    for (int k = 0; k < detail::primitive_corners(v); ++k)
      if (escaped_[static_cast<std::size_t>(v[static_cast<std::size_t>(k)])]) return true;
    return false;
  };
  auto prim_box = [&](std::uint32_t gid) { return detail::primitive_box(exact_boxes_, ids(gid)); };
  // If primitives a, b (any order) are a VF or EE pair sharing no vertex whose actual boxes
  // overlap: true, and the pair.
  auto pair_of = [&](std::uint32_t a, std::uint32_t b, CcdPrimitive& kind,
                     std::array<int, 2>& pair) {
    const bool a_vertex = a < nvs, b_vertex = b < nvs;
    const bool a_face = !a_vertex && a < nvs + nf, b_face = !b_vertex && b < nvs + nf;
    const bool a_edge = a >= nvs + nf, b_edge = b >= nvs + nf;
    if (a_vertex && b_face) {
      kind = CcdPrimitive::VertexFace;
      pair = {static_cast<int>(a), static_cast<int>(b - nvs)};
    } else if (a_face && b_vertex) {
      kind = CcdPrimitive::VertexFace;
      pair = {static_cast<int>(b), static_cast<int>(a - nvs)};
    } else if (a_edge && b_edge) {
      kind = CcdPrimitive::EdgeEdge;
      const int ea = static_cast<int>(a - nvs - nf), eb = static_cast<int>(b - nvs - nf);
      pair = {std::min(ea, eb), std::max(ea, eb)};
    } else {
      return false;
    }
    const std::array<int, 3> va = ids(a), vb = ids(b);
    for (int i = 0; i < detail::primitive_corners(va); ++i)
      for (int j = 0; j < detail::primitive_corners(vb); ++j)
        if (va[static_cast<std::size_t>(i)] == vb[static_cast<std::size_t>(j)]) return false;
    return overlap(prim_box(a), prim_box(b));
  };
  // The record and flags of the pair (kind, pair) of primitives a, b, as the classification
  // pass sets them: its rest-state role; stale (to test) unless excluded or flagged far.
  auto make_hit = [&](std::uint32_t a, std::uint32_t b, CcdPrimitive kind,
                      const std::array<int, 2>& pair) {
    QueryHit h;
    h.record.kind = kind;
    h.record.pair = pair;
    h.record.v = stencil(kind, pair, topo_);
    h.role = rest.role(kind, pair);
    h.stale = h.role != EXCLUDED && !far(prim_box(a), prim_box(b));
    return h;
  };
  // Appends hits to the pairs, sizing the arrays once (push_back per pair was measurably slower;
  // lab/history.md).
  auto append = [&](const std::vector<QueryHit>& hits) {
    std::size_t at = pairs.records.size();
    pairs.records.resize(at + hits.size());
    pairs.role.resize(at + hits.size());
    pairs.stale.resize(at + hits.size());
    pairs.is_free.resize(at + hits.size());
    appended += hits.size();
    for (const QueryHit& h : hits) {
      pairs.records[at] = h.record;
      pairs.role[at] = h.role;
      pairs.stale[at] = h.stale;
      pairs.is_free[at] = !h.stale;
      ++at;
    }
  };
  // The grid queries in parallel (fixed blocks, each its own buffers, which also hold the new
  // pairs' records and flags), the appends in order.
  const std::size_t query_blocks = (escaped_prims_.size() + QUERY_BLOCK - 1) / QUERY_BLOCK;
  const std::uint32_t nv32 = static_cast<std::uint32_t>(nvs);
  const std::uint32_t nvs_nf32 = static_cast<std::uint32_t>(nvs + nf);
  const std::uint32_t all32 = static_cast<std::uint32_t>(nvs + nf + topo_.edges.rows());
  if (query_blocks_.size() < query_blocks) query_blocks_.resize(query_blocks);
  workers_.arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, query_blocks, [&](std::size_t blk) {
      QueryBlock& out = query_blocks_[blk];
      out.pairs.clear();
      const std::size_t stop = std::min(escaped_prims_.size(), (blk + 1) * QUERY_BLOCK);
      for (std::size_t k = blk * QUERY_BLOCK; k < stop; ++k) {
        const std::uint32_t a = escaped_prims_[k];
        out.hits.clear();
        // Only the kind a pairs with: a vertex the faces, a face the vertices, an edge the edges.
        const std::uint32_t first = a < nvs ? nv32 : a < nvs + nf ? 0 : nvs_nf32;
        const std::uint32_t end = a < nvs ? nvs_nf32 : a < nvs + nf ? nv32 : all32;
        query_kept_grid(candidates, topo_, prim_box(a), out.hits, first, end);
        // The kept grid reports in its cells' order, which a resumed run's grid does not share.
        std::sort(out.hits.begin(), out.hits.end());
        CcdPrimitive kind;
        std::array<int, 2> pair;
        for (const std::uint32_t b : out.hits)
          if (!outside(b) && pair_of(a, b, kind, pair))
            out.pairs.push_back(make_hit(a, b, kind, pair));
      }
    });
  });
  for (std::size_t blk = 0; blk < query_blocks; ++blk) append(query_blocks_[blk].pairs);
  // Sweep and prune along x over the escaped primitives (sorted by lower x bound, then id).
  std::vector<std::pair<double, std::uint32_t>>& order = sweep_order_;
  order.clear();
  for (const std::uint32_t a : escaped_prims_) order.emplace_back(prim_box(a).lo[0], a);
  std::sort(order.begin(), order.end());
  sweep_hits_.clear();
  for (std::size_t i = 0; i < order.size(); ++i) {
    const double hi = prim_box(order[i].second).hi[0];
    for (std::size_t j = i + 1; j < order.size() && order[j].first <= hi; ++j) {
      const std::uint32_t a = order[i].second, b = order[j].second;
      CcdPrimitive kind;
      std::array<int, 2> pair;
      if (pair_of(a, b, kind, pair)) sweep_hits_.push_back(make_hit(a, b, kind, pair));
    }
  }
  append(sweep_hits_);
  return appended;
}

}  // namespace shellcontract::collision_pipeline
