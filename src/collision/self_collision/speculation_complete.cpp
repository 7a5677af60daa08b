// The speculative broad phase, second half: complete() keeps the predicted grid's pairs whose
// actual boxes overlap (classify) and queries the grid again for the vertices that escaped their
// predicted boxes (query_escaped, speculation_queries.cpp).
#include <cmath>
#include <type_traits>

#include "collision/broad_phase/scratch.hpp"
#include "collision/self_collision/speculation.hpp"
#include "core/stage_timer.hpp"

namespace shellcontract::collision_pipeline {

bool Speculation::complete(const Positions& x0, const Positions& x1, const RestPairs& rest,
                           CandidatePairs& candidates, StepPairs& pairs, Regions& regions,
                           CollisionStepStats& stats) {
  const StageTimer t0;
  pending_ = false;
  // Waits for the task (or runs it here); false if it failed. Its time is the step's wait.
  auto finish_task = [&] {
    const StageTimer tw;
    bool ok = true;
    try {
      if (enqueued_) {
        enqueued_ = false;
        workers_.arena.execute([&] { workers_.background.wait(); });
        stats.background_seconds = task_seconds_;
        const GridPartSeconds g = grid_part_seconds(candidates);
        stats.background_grid_seconds = g.build;
        stats.background_cell_loop_seconds = g.cell_loop;
        stats.background_output_seconds = g.output;
        stats.background_records_seconds = task_records_seconds_;
      } else {  // run here: its time is this thread's (broad_seconds)
        workers_.arena.execute([&] { run_task(rest, candidates, pairs); });
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
  // boxes_ and writes the pair buffers; this part writes neither). The largest coordinate
  // (for the inflation and far_gap_threshold's), then one pass over the vertices, in parallel
  // fixed blocks (each with its own counts, so nothing depends on the threads): the actual boxes
  // (the arithmetic of find_candidates), which vertices left their predicted boxes, the skins of
  // the next prediction (the end positions after the warm start are what was predicted), the
  // response regions (Regions::set's arithmetic) and whether x0 is the one predict saw. As four
  // serial passes these were a visible share of the step at strong pressure
  // (docs/design/self-collision.md).
  const Eigen::Index nv = x0.rows();
  const std::size_t nvs = static_cast<std::size_t>(nv);
  const double max_abs_x = max_abs(workers_.arena, x0, x1);
  const double inflation = broad_phase_inflation(options_, max_abs_x);
  const double half_margin = 0.5 * (options_.region_margin * options_.delta);
  exact_boxes_.resize(nvs);
  escaped_.resize(nvs);
  regions.lo.resize(nv, 3);
  regions.hi.resize(nv, 3);
  vertex_blocks_.resize((nvs + VERTEX_BLOCK - 1) / VERTEX_BLOCK);
  for_vertex_blocks(workers_.arena, nvs, [&](std::size_t blk, std::size_t begin, std::size_t end) {
    VertexBlock& out = vertex_blocks_[blk];
    out = VertexBlock{};
    for (std::size_t i = begin; i < end; ++i) {
      const Eigen::Index v = static_cast<Eigen::Index>(i);
      detail::GridVertexBox& e = exact_boxes_[i];
      const detail::GridVertexBox& p = boxes_[i];
      bool inside = true;
      double error = 0.0;
      for (Eigen::Index d = 0; d < 3; ++d) {
        const std::size_t k = static_cast<std::size_t>(d);
        const double a = x0(v, d), c = x1(v, d);
        const double lo = std::min(a, c), hi = std::max(a, c);
        e.lo[k] = lo - inflation;
        e.hi[k] = hi + inflation;
        regions.lo(v, d) = lo - half_margin;
        regions.hi(v, d) = hi + half_margin;
        inside = inside && p.lo[k] <= e.lo[k] && e.hi[k] <= p.hi[k];
        error = std::max(error, std::abs(c - pred_(v, d)));
        out.other_x0 = out.other_x0 || a != x0_(v, d);
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
  if (!task_ok || !task_ok_ || too_many || other_x0) return fail();

  // The grid's pairs of two primitives inside their predicted boxes whose actual boxes overlap
  // (classify), then the pairs of the primitives with a vertex outside (query_escaped).
  const std::size_t n_spec = pairs.records.size();
  const std::size_t blocks = (n_spec + PAIR_GRAIN - 1) / PAIR_GRAIN;
  std::size_t kept = classify(pairs, candidates.vertex_face.size(), far_gap);
  kept += query_escaped(rest, candidates, pairs, far_gap);

  // The appended pairs' live and round-0 test entries, after the grid's (increasing index):
  // their live entries in one more unit after the blocks' slices.
  const std::size_t appended = pairs.records.size() - n_spec;
  const std::size_t tail = blocks * PAIR_GRAIN;
  if (pairs.live.size() < tail + appended) pairs.live.resize(tail + appended);
  if (pairs.live_v.size() < tail + appended) pairs.live_v.resize(tail + appended);
  if (pairs.tests.size() < pairs.records.size()) pairs.tests.resize(pairs.records.size());
  std::size_t tail_count = 0;
  for (std::size_t i = n_spec; i < pairs.records.size(); ++i) {
    if (pairs.role[i] < EXCLUDED) {
      pairs.live_v[tail + tail_count] = pairs.records[i].v;
      pairs.live[tail + tail_count++] = static_cast<std::uint32_t>(i);
    }
    if (pairs.stale[i] && pairs.role[i] == NORMAL)
      pairs.tests[pairs.test_count++] = static_cast<std::uint32_t>(i);
  }
  if (tail_count > 0) pairs.live_units.push_back(LiveUnit{tail, tail_count});
  pairs.live_count += tail_count;
  stats.speculative = 1;
  stats.escaped_vertices = static_cast<std::int64_t>(escaped);
  t0.add_to(stats.broad_seconds);
  ++stats.broad_phase_calls;
  stats.pairs_no_culling = topo_.all_vertex_face_pairs + topo_.all_edge_edge_pairs;
  stats.pairs_broad = static_cast<std::int64_t>(kept);
  return true;
}

std::size_t Speculation::classify(StepPairs& pairs, std::size_t nvf_spec, double far_gap) {
  // The grid's pairs of two primitives inside their predicted boxes whose actual boxes overlap
  // are exactly find_candidates' pairs of such primitives (containment keeps every overlap).
  // Pairs with a vertex outside are left out here and found by the queries below.
  const std::size_t n_spec = pairs.records.size();
  resize_for_rewrite(pairs.role, n_spec);
  resize_for_rewrite(pairs.stale, n_spec);
  resize_for_rewrite(pairs.is_free, n_spec);
  const std::size_t blocks = (n_spec + PAIR_GRAIN - 1) / PAIR_GRAIN;
  block_kept_.assign(blocks, 0);
  block_live_.assign(blocks, 0);
  block_tests_.assign(blocks, 0);
  if (pairs.live.size() < n_spec) resize_for_rewrite(pairs.live, n_spec);
  if (pairs.live_v.size() < n_spec) resize_for_rewrite(pairs.live_v, n_spec);
  if (pairs.tests.size() < n_spec) resize_for_rewrite(pairs.tests, n_spec);
  // Raw pointers copied into each task: with the byte stores of the flags the compiler would
  // otherwise reload every vector's data pointer per pair (measured slower; lab/history.md).
  const PairRecord* const rec_data = pairs.records.data();
  const detail::GridVertexBox* const box_data = exact_boxes_.data();
  const std::uint8_t* const esc_data = escaped_.data();
  const std::uint8_t* const base_data = base_role_.data();
  std::uint8_t* const role_data = pairs.role.data();
  std::uint8_t* const stale_data = pairs.stale.data();
  std::uint8_t* const free_data = pairs.is_free.data();
  std::size_t* const kept_data = block_kept_.data();
  std::size_t* const live_counts = block_live_.data();
  std::size_t* const test_counts = block_tests_.data();
  std::uint32_t* const live_data = pairs.live.data();
  std::array<int, 4>* const live_v_data = pairs.live_v.data();
  std::uint32_t* const tests_data = pairs.tests.data();
  workers_.arena.execute([&] {
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
      // The same pass compacts the block's live pairs (StepPairs::collect_live) and round 0's
      // tests (the live pairs that are stale and NORMAL, as Rescan::collect) to the front of the
      // block's own slices of pairs.live and pairs.tests (branch-free stores), closed up after
      // the loop: two fewer passes over the pairs.
      std::uint32_t* __restrict live_out = live_data + blk * PAIR_GRAIN;
      std::array<int, 4>* __restrict live_v_out = live_v_data + blk * PAIR_GRAIN;
      std::uint32_t* __restrict test_out = tests_data + blk * PAIR_GRAIN;
      std::size_t nlive = 0, ntests = 0;
      // VF pairs come first (the grid's lists, VF then EE): one loop per kind, so the kind is no
      // per-pair branch, and the tests are branch-free (measured faster; lab/history.md).
      // The boxes of the pair PF ahead are prefetched: the four box reads per pair are the
      // loop's cost (perf; lab/history.md).
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
  pairs.live_units.resize(blocks);
  pairs.live_count = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    pairs.live_units[b] = LiveUnit{b * PAIR_GRAIN, block_live_[b]};
    pairs.live_count += block_live_[b];
  }
  pairs.test_count = close_up(pairs.tests, PAIR_GRAIN, block_tests_);
  return kept;
}

}  // namespace shellcontract::collision_pipeline
