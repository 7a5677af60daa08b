// Detection: the non-penetration filter and the narrow phase on the pairs to test, in fixed
// blocks (the result does not depend on the threads).
#include "collision/self_collision/detection.hpp"

#include "collision/cull_batch.hpp"
#include "core/stage_timer.hpp"

namespace shellcontract::collision_pipeline {

const std::vector<Contact>& Detection::detect(tbb::task_arena& arena, const Positions& x0,
                                              const Positions& x1, double tol, StepPairs& pairs,
                                              CollisionStepStats& stats, bool count_stage) {
  contacts_.clear();
  const std::size_t n = pairs.test_count;
  if (n == 0) return contacts_;
  const PairArray<PairRecord>& records = pairs.records;
  const PairArray<std::uint32_t>& tests = pairs.tests;
  PairArray<std::uint8_t>& stale = pairs.stale;
  PairArray<std::uint8_t>& is_free = pairs.is_free;
  // One parallel region per call: each task takes a fixed block of tests (never cut by the
  // thread count), runs the filter on it, then the narrow phase on the block's survivors, and
  // keeps its hits in test order. A region per stage and compaction (five per call) spent most
  // of the later rounds, a few thousand tests each, on hand-offs between the threads
  // (lab/history.md). Each test is a different pair, so the tasks write different
  // bytes of is_free and stale.
  const std::size_t blocks = (n + DETECT_BLOCK - 1) / DETECT_BLOCK;
  if (blocks_.size() < blocks) blocks_.resize(blocks);
  CcdOptions ccd;
  ccd.tolerance = tol;
  ccd.tighten_toi = false;  // the response uses the contact data, not the time of impact
  const StageTimer start;
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      Block& out = blocks_[b];
      out.hits.clear();
      const std::size_t begin = b * DETECT_BLOCK, end = std::min(n, begin + DETECT_BLOCK);
      const StageTimer t0;
      // Stage 1: the box cull and the certain non-penetration filter (math-spec 10.4), four
      // tests at a time (cull_batch: the same answers as swept_boxes_apart and
      // nonpenetration_filter_culls one by one); a group of four is cut where the kind changes.
      // A culled pair is free at its current positions. The same batch gives the narrow phase's
      // axes cull (separating_axes_culls) from the positions it has loaded: a survivor it settles
      // is free as well, and counted as the narrow phase's. On large meshes it settles most
      // of the survivors (neighbours that move together), which the narrow phase
      // gathered again one by one (lab/scripts/scale_benchmark.py --phases, the narrow phase row).
      out.kept.clear();
      out.axes_settled = 0;
      std::array<int, 4> v[CULL_LANES];
      std::uint8_t culled[CULL_LANES], axes[CULL_LANES];
      for (std::size_t i = begin; i < end;) {
        const CcdPrimitive kind = records[tests[i]].kind;
        const std::size_t group_end = std::min(end, i + CULL_LANES);
        int count = 0;
        for (std::size_t j = i; j < group_end && records[tests[j]].kind == kind; ++j)
          v[count++] = records[tests[j]].v;
        cull_batch(kind, x0.data(), x1.data(), v, count, tol, culled, CullIsa::Auto, axes);
        for (int k = 0; k < count; ++k, ++i) {
          if (!culled[k] && !axes[k]) {
            out.kept.push_back(tests[i]);
            continue;
          }
          out.axes_settled += !culled[k];
          stale[tests[i]] = 0;
          is_free[tests[i]] = 1;
        }
      }
      out.axis_culls = out.axes_settled;
      out.filter_seconds = t0.elapsed();
      const StageTimer t1;
      // Stage 2: the narrow phase on the survivors, in test order.
      CcdStencil s0, s1;
      for (const std::uint32_t pair : out.kept) {
        const PairRecord& p = records[pair];
        gather(x0, x1, p.v, s0, s1);
        stale[pair] = 0;
        // Most survivors of the filter are neighbours apart within a common plane: the
        // separating-axis test settles them for less than a third of the interval search's
        // cost, with the same answer (ccd.hpp); its axes half ran in stage 1.
        if (separating_direction_culls(p.kind, s0, s1, tol)) {
          is_free[pair] = 1;
          ++out.axis_culls;
          continue;
        }
        const CcdResult res = primitive_ccd(p.kind, s0, s1, ccd);
        is_free[pair] = !res.hit;
        if (!res.hit) continue;
        Contact& c = out.hits.emplace_back();
        c.kind = p.kind;
        c.pair = p.pair;
        c.v = p.v;
        c.weights = res.weights;
        c.normal = res.normal;
        c.side = res.side;
      }
      out.narrow_seconds = t1.elapsed();
    });
  });
  // The hits in the order of the tests: block after block.
  double filter_cpu = 0.0, narrow_cpu = 0.0;
  std::size_t m = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    const Block& block = blocks_[b];
    contacts_.insert(contacts_.end(), block.hits.begin(), block.hits.end());
    m += block.kept.size() + block.axes_settled;
    stats.axis_culls += block.axis_culls;
    filter_cpu += block.filter_seconds;
    narrow_cpu += block.narrow_seconds;
  }
  // The stages share one region: its wall time is split in proportion to their CPU time.
  const double wall = start.elapsed(), cpu = filter_cpu + narrow_cpu;
  const double filter_share = cpu > 0.0 ? filter_cpu / cpu : 0.5;
  stats.filter_seconds += wall * filter_share;
  stats.narrow_seconds += wall * (1.0 - filter_share);
  stats.narrow_tests += static_cast<std::int64_t>(m);
  stats.filter_tests += static_cast<std::int64_t>(n);
  if (count_stage) stats.pairs_filtered = static_cast<std::int64_t>(m);
  return contacts_;
}

}  // namespace shellcontract::collision_pipeline
