// The speculative broad phase, second half: complete_speculation() keeps the predicted grid's
// pairs whose actual boxes overlap and queries the grid again for the vertices that escaped
// their predicted boxes.
#include "collision/broad_phase/scratch.hpp"
#include "collision/self_collision/state.hpp"

namespace shellcontract {

bool SelfCollision::Impl::complete_speculation(const Positions& x0, const Positions& x1,
                                               CollisionStepStats& stats) {
  const StageTimer t0;
  spec_pending_ = false;
  // Waits for the task (or runs it here); false if it failed. Its time is the step's wait.
  auto finish_task = [&] {
    const StageTimer tw;
    bool ok = true;
    try {
      if (spec_enqueued_) {
        spec_enqueued_ = false;
        workers_->arena.execute([&] { workers_->background.wait(); });
        stats.background_seconds = spec_seconds_;
        const GridPartSeconds g = grid_part_seconds(candidates_);
        stats.background_grid_seconds = g.build;
        stats.background_cell_loop_seconds = g.cell_loop;
        stats.background_output_seconds = g.output;
        stats.background_records_seconds = spec_records_seconds_;
      } else {  // run here: its time is this thread's (broad_seconds)
        workers_->arena.execute([&] { run_speculation(); });
      }
    } catch (...) {
      // Whatever failed in the speculative task, the plain broad phase decides (and reports a
      // failure of its own, if it has one).
      ok = false;
    }
    tw.add_to(stats.wait_seconds);
    return ok;
  };
  // Arrays that do not match the mesh, or non-finite end positions: the plain broad phase
  // reports them (find_candidates' checks) or handles them.
  // A failed completion's time (the wait included) is broad-phase time of the step too.
  auto fail = [&] {
    t0.add_to(stats.broad_seconds);
    return false;
  };
  if (x0.rows() != topo_.num_vertices || x1.rows() != topo_.num_vertices || !x1.allFinite()) {
    finish_task();
    return fail();
  }
  // What needs only x0 and x1 comes first, while the task may still be running (it reads
  // spec_boxes_ and writes the pair buffers; this part writes neither). The largest coordinate
  // (for the inflation and far_gap_threshold's), then one pass over the vertices, in parallel
  // fixed blocks (each with its own counts, so nothing depends on the threads): the actual boxes
  // (the arithmetic of find_candidates), which vertices left their predicted boxes, the skins of
  // the next prediction (the end positions after the warm start are what was predicted), the
  // response regions (set_regions' arithmetic) and whether x0 is the one predict saw. As four
  // serial passes these were a visible share of the step at strong pressure
  // (docs/design/self-collision.md).
  const Eigen::Index nv = x0.rows();
  const std::size_t nvs = static_cast<std::size_t>(nv);
  const double max_abs_x = max_abs(x0, x1);
  const double inflation = broad_phase_inflation(options_, max_abs_x);
  const double half_margin = 0.5 * (options_.region_margin * options_.delta);
  exact_boxes_.resize(nvs);
  escaped_.resize(nvs);
  region_lo_.resize(nv, 3);
  region_hi_.resize(nv, 3);
  vertex_blocks_.resize((nvs + VERTEX_BLOCK - 1) / VERTEX_BLOCK);
  for_vertex_blocks(workers_->arena, nvs, [&](std::size_t blk, std::size_t begin, std::size_t end) {
    VertexBlock& out = vertex_blocks_[blk];
    out = VertexBlock{};
    for (std::size_t i = begin; i < end; ++i) {
      const Eigen::Index v = static_cast<Eigen::Index>(i);
      detail::GridVertexBox& e = exact_boxes_[i];
      const detail::GridVertexBox& p = spec_boxes_[i];
      bool inside = true;
      double error = 0.0;
      for (Eigen::Index d = 0; d < 3; ++d) {
        const std::size_t k = static_cast<std::size_t>(d);
        const double a = x0(v, d), c = x1(v, d);
        const double lo = std::min(a, c), hi = std::max(a, c);
        e.lo[k] = lo - inflation;
        e.hi[k] = hi + inflation;
        region_lo_(v, d) = lo - half_margin;
        region_hi_(v, d) = hi + half_margin;
        inside = inside && p.lo[k] <= e.lo[k] && e.hi[k] <= p.hi[k];
        error = std::max(error, std::abs(c - spec_pred_(v, d)));
        out.other_x0 = out.other_x0 || a != spec_x0_(v, d);
      }
      escaped_[i] = !inside;
      out.escaped += !inside;
      skin_(v) = SKIN_MIN * options_.delta + SKIN_GROWTH * (std::isfinite(error) ? error : 0.0);
    }
  });
  std::size_t escaped = 0;
  bool other_x0 = false;
  for (const VertexBlock& b : vertex_blocks_) {
    escaped += b.escaped;
    other_x0 = other_x0 || b.other_x0;
  }
  const bool too_many = static_cast<double>(escaped) >
                        std::max(ESCAPE_LIMIT, ESCAPE_FRACTION * static_cast<double>(nvs));
  // The primitives with a vertex outside its predicted box (grid ids), for the queries below.
  const std::size_t nf = static_cast<std::size_t>(topo_.faces.rows());
  escaped_prims_.clear();
  if (escaped > 0 && !too_many) {
    auto esc = [&](Eigen::Index v) { return escaped_[static_cast<std::size_t>(v)] != 0; };
    for (Eigen::Index v = 0; v < nv; ++v)
      if (esc(v)) escaped_prims_.push_back(static_cast<std::uint32_t>(v));
    for (Eigen::Index f = 0; f < topo_.faces.rows(); ++f)
      if (esc(topo_.faces(f, 0)) | esc(topo_.faces(f, 1)) | esc(topo_.faces(f, 2)))
        escaped_prims_.push_back(static_cast<std::uint32_t>(nvs + static_cast<std::size_t>(f)));
    for (Eigen::Index e = 0; e < topo_.edges.rows(); ++e)
      if (esc(topo_.edges(e, 0)) | esc(topo_.edges(e, 1)))
        escaped_prims_.push_back(
            static_cast<std::uint32_t>(nvs + nf + static_cast<std::size_t>(e)));
  }
  const double far_gap = far_gap_threshold_for_magnitude(max_abs_x, inflation, options_.delta);
  const bool task_ok = finish_task();
  if (!task_ok || !spec_ok_ || too_many || other_x0) return fail();

  // The grid's pairs of two primitives inside their predicted boxes whose actual boxes overlap
  // are exactly find_candidates' pairs of such primitives (containment keeps every overlap).
  // Pairs with a vertex outside are left out here and found by the queries below.
  const std::size_t n_spec = pairs_.size();
  const std::size_t nvf_spec = candidates_.vertex_face.size();
  resize_for_rewrite(role_, n_spec);
  resize_for_rewrite(stale_, n_spec);
  resize_for_rewrite(free_, n_spec);
  const std::size_t blocks = (n_spec + PAIR_GRAIN - 1) / PAIR_GRAIN;
  block_kept_.assign(blocks, 0);
  block_live_.assign(blocks, 0);
  block_tests_.assign(blocks, 0);
  if (live_.size() < n_spec) resize_for_rewrite(live_, n_spec);
  if (live_v_.size() < n_spec) resize_for_rewrite(live_v_, n_spec);
  if (tests_.size() < n_spec) resize_for_rewrite(tests_, n_spec);
  auto overlap = [](const detail::GridVertexBox& a, const detail::GridVertexBox& b) {
    return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1] &&
           a.lo[2] <= b.hi[2] && b.lo[2] <= a.hi[2];
  };
  auto far = [&](const detail::GridVertexBox& a, const detail::GridVertexBox& b) {
    return b.lo[0] - a.hi[0] > far_gap || a.lo[0] - b.hi[0] > far_gap ||
           b.lo[1] - a.hi[1] > far_gap || a.lo[1] - b.hi[1] > far_gap ||
           b.lo[2] - a.hi[2] > far_gap || a.lo[2] - b.hi[2] > far_gap;
  };
  // Raw pointers copied into each task: with the byte stores of the flags the compiler would
  // otherwise reload every vector's data pointer per pair (measured slower; lab/history.md).
  const PairRecord* const rec_data = pairs_.data();
  const detail::GridVertexBox* const box_data = exact_boxes_.data();
  const std::uint8_t* const esc_data = escaped_.data();
  const std::uint8_t* const base_data = base_role_.data();
  std::uint8_t* const role_data = role_.data();
  std::uint8_t* const stale_data = stale_.data();
  std::uint8_t* const free_data = free_.data();
  std::size_t* const kept_data = block_kept_.data();
  std::size_t* const live_counts = block_live_.data();
  std::size_t* const test_counts = block_tests_.data();
  std::uint32_t* const live_data = live_.data();
  std::array<int, 4>* const live_v_data = live_v_.data();
  std::uint32_t* const tests_data = tests_.data();
  workers_->arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, blocks, [=](std::size_t blk) {
      const PairRecord* __restrict rec = rec_data;
      const detail::GridVertexBox* __restrict eb = box_data;
      const std::uint8_t* __restrict esc = esc_data;
      const std::uint8_t* __restrict base = base_data;
      std::uint8_t* __restrict role = role_data;
      std::uint8_t* __restrict stale = stale_data;
      std::uint8_t* __restrict fr = free_data;
      const double gap = far_gap;
      std::size_t kept = 0;
      // The same pass compacts the block's live pairs (collect_live) and round 0's tests (the
      // live pairs that are stale and NORMAL, as mark_moved_and_collect) to the front of the
      // block's own slices of live_ and tests_ (branch-free stores), closed up after the loop:
      // two fewer passes over the pairs.
      std::uint32_t* __restrict live_out = live_data + blk * PAIR_GRAIN;
      std::array<int, 4>* __restrict live_v_out = live_v_data + blk * PAIR_GRAIN;
      std::uint32_t* __restrict test_out = tests_data + blk * PAIR_GRAIN;
      std::size_t nlive = 0, ntests = 0;
      // VF pairs come first (the grid's lists, VF then EE): one loop per kind, so the kind is no
      // per-pair branch, and the tests are branch-free (measured faster; lab/history.md).
      // The boxes of the pair PF ahead are prefetched: the four box reads per pair are the
      // loop's cost (perf, bear at P = 4: its share against the solve's membrane kernel 0.61 ->
      // 0.57; 16 and 32 ahead the same).
      constexpr std::size_t PF = 16;
      auto classify_range = [&](auto vf_tag, std::size_t begin, std::size_t stop) {
        constexpr bool vf = decltype(vf_tag)::value;
        for (std::size_t i = begin; i < stop; ++i) {
          if (i + PF < stop) {
            const PairRecord& q = rec[i + PF];
            for (int k = 0; k < 4; ++k) __builtin_prefetch(&eb[static_cast<std::size_t>(q.v[k])]);
          }
          const PairRecord& p = rec[i];
          const std::size_t v0 = static_cast<std::size_t>(p.v[0]);
          const std::size_t v1 = static_cast<std::size_t>(p.v[1]);
          const std::size_t v2 = static_cast<std::size_t>(p.v[2]);
          const std::size_t v3 = static_cast<std::size_t>(p.v[3]);
          const bool out = (esc[v0] | esc[v1] | esc[v2] | esc[v3]) != 0;
          // The two primitives' actual boxes: VF vertex | face, EE edge | edge (the unions of
          // vertex boxes that find_candidates forms; min and max are exact).
          const detail::GridVertexBox &b0 = eb[v0], &b1 = eb[v1], &b2 = eb[v2], &b3 = eb[v3];
          bool meet = !out, far = false;
          for (std::size_t d = 0; d < 3; ++d) {
            const double alo = vf ? b0.lo[d] : std::min(b0.lo[d], b1.lo[d]);
            const double ahi = vf ? b0.hi[d] : std::max(b0.hi[d], b1.hi[d]);
            double blo = std::min(b2.lo[d], b3.lo[d]), bhi = std::max(b2.hi[d], b3.hi[d]);
            if (vf) {
              blo = std::min(blo, b1.lo[d]);
              bhi = std::max(bhi, b1.hi[d]);
            }
            meet = meet & (alo <= bhi) & (blo <= ahi);
            far = far | (blo - ahi > gap) | (alo - bhi > gap);
          }
          // A pair with a vertex outside its predicted box is left to the queries below.
          const std::uint8_t r = meet ? base[i] : std::uint8_t{NOT_CANDIDATE};
          const bool st = meet & (r != EXCLUDED) & !far;
          role[i] = r;
          stale[i] = st;
          fr[i] = !st;
          kept += meet;
          live_out[nlive] = static_cast<std::uint32_t>(i);
          live_v_out[nlive] = p.v;
          nlive += r < EXCLUDED;
          test_out[ntests] = static_cast<std::uint32_t>(i);
          ntests += st & (r == NORMAL);
        }
      };
      const std::size_t begin = blk * PAIR_GRAIN, end = std::min(n_spec, begin + PAIR_GRAIN);
      const std::size_t split = std::clamp(nvf_spec, begin, end);
      classify_range(std::true_type{}, begin, split);
      classify_range(std::false_type{}, split, end);
      kept_data[blk] = kept;
      live_counts[blk] = nlive;
      test_counts[blk] = ntests;
    });
  });
  std::size_t kept = 0;
  for (const std::size_t k : block_kept_) kept += k;
  // The live pairs stay in the blocks' slices (the passes over them visit the slices, so they
  // are not moved together: that would copy megabytes a step at strong pressure).
  live_units_.resize(blocks);
  live_count_ = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    live_units_[b] = LiveUnit{b * PAIR_GRAIN, block_live_[b]};
    live_count_ += block_live_[b];
  }
  test_count_ = close_up(tests_, PAIR_GRAIN, block_tests_);

  // The primitives with a vertex outside its predicted box: each against the grid's primitives
  // without one (whose actual boxes are inside their predicted ones, so the query sees every
  // actual overlap), then against each other by a sweep along x. A few hundred queries per step
  // (bear at P = 4), in parallel blocks, which measured faster than serial (lab/history.md).
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
    h.role = rest_role(kind, pair);
    h.stale = h.role != EXCLUDED && !far(prim_box(a), prim_box(b));
    return h;
  };
  // Appends hits to the pairs, sizing the arrays once (push_back per pair was measurably slower;
  // lab/history.md).
  auto append = [&](const std::vector<QueryHit>& hits) {
    std::size_t at = pairs_.size();
    pairs_.resize(at + hits.size());
    role_.resize(at + hits.size());
    stale_.resize(at + hits.size());
    free_.resize(at + hits.size());
    kept += hits.size();
    for (const QueryHit& h : hits) {
      pairs_[at] = h.record;
      role_[at] = h.role;
      stale_[at] = h.stale;
      free_[at] = !h.stale;
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
  workers_->arena.execute([&] {
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
        query_kept_grid(candidates_, topo_, prim_box(a), out.hits, first, end);
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

  // The appended pairs' live and round-0 test entries, after the grid's (increasing index):
  // their live entries in one more unit after the blocks' slices.
  const std::size_t appended = pairs_.size() - n_spec;
  const std::size_t tail = blocks * PAIR_GRAIN;
  if (live_.size() < tail + appended) live_.resize(tail + appended);
  if (live_v_.size() < tail + appended) live_v_.resize(tail + appended);
  if (tests_.size() < pairs_.size()) tests_.resize(pairs_.size());
  std::size_t tail_count = 0;
  for (std::size_t i = n_spec; i < pairs_.size(); ++i) {
    if (role_[i] < EXCLUDED) {
      live_v_[tail + tail_count] = pairs_[i].v;
      live_[tail + tail_count++] = static_cast<std::uint32_t>(i);
    }
    if (stale_[i] && role_[i] == NORMAL) tests_[test_count_++] = static_cast<std::uint32_t>(i);
  }
  if (tail_count > 0) live_units_.push_back(LiveUnit{tail, tail_count});
  live_count_ += tail_count;
  round0_tests_ready_ = true;
  stats.speculative = 1;
  stats.escaped_vertices = static_cast<std::int64_t>(escaped);
  t0.add_to(stats.broad_seconds);
  ++stats.broad_phase_calls;
  stats.pairs_no_culling = topo_.all_vertex_face_pairs + topo_.all_edge_edge_pairs;
  stats.pairs_broad = static_cast<std::int64_t>(kept);
  return true;
}

}  // namespace shellcontract
