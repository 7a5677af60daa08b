// The broad phase part: the step's pairs, their records and rest-state roles, and the regions
// the response keeps the vertices in, from the speculative broad phase or a plain one.
#include "collision/self_collision/step_broad_phase.hpp"

#include <tbb/blocked_range.h>

#include <limits>

#include "core/stage_timer.hpp"

namespace shellcontract {

// A pair can come within delta in the step only if its swept boxes, each grown by its vertices'
// regions (m/2 and the rounding of the region bounds, at most u (M + m/2); M = max |coordinate|,
// u the unit roundoff), come within delta on every axis: if the boxes' gap G <= delta + m +
// 2u (M + m/2). Boxes grown by I overlap for every G <= 2I, their rounded bounds included
// (rounding is monotone: hi + I >= lo' - I gives fl(hi + I) >= fl(lo' - I)). So I = (delta +
// m)/2 + s covers the bound when s >= u (M + m/2) plus the rounding of I itself, which s = 4u (M
// + delta + m) does. The inflation was delta + m/2, a band of gaps up to 2 delta + m (6 delta)
// where delta + m (5 delta) are needed, and the wider band gave measurably more candidates
// (lab/scripts/scale_benchmark.py's pairs per face; lab/history.md).
double broad_phase_inflation(const CollisionOptions& options, double max_abs) {
  constexpr double u = std::numeric_limits<double>::epsilon() / 2.0;
  const double band = options.delta + options.region_margin * options.delta;
  return 0.5 * band + 4.0 * u * (max_abs + band);
}

}  // namespace shellcontract

namespace shellcontract::collision_pipeline {

double max_abs(tbb::task_arena& arena, const Positions& a, const Positions& b) {
  // Per fixed block of rows, then over the blocks in order (a max is exact: any order gives it).
  const Eigen::Index n = a.rows(), block = 4096;
  const Eigen::Index blocks = (n + block - 1) / block;
  std::vector<double> partial(static_cast<std::size_t>(blocks), 0.0);
  arena.execute([&] {
    tbb::parallel_for(Eigen::Index{0}, blocks, [&](Eigen::Index k) {
      const Eigen::Index begin = k * block, rows = std::min(block, n - begin);
      partial[static_cast<std::size_t>(k)] =
          std::max(a.middleRows(begin, rows).cwiseAbs().maxCoeff(),
                   b.middleRows(begin, rows).cwiseAbs().maxCoeff());
    });
  });
  double m = 0.0;
  for (const double p : partial) m = std::max(m, p);
  return m;
}

StepBroadPhase::StepBroadPhase(const Positions& rest, const CollisionTopology& topo,
                               const CollisionOptions& options, Workers& workers)
    : topo_(topo),
      options_(options),
      workers_(workers),
      rest_(rest, topo, options, candidates_),
      speculation_(topo, options, workers) {}

StepBroadPhase::~StepBroadPhase() { speculation_.wait(); }

bool StepBroadPhase::run(const Positions& x0, const Positions& x1, CollisionStepStats& stats) {
  if (speculation_.pending() &&
      speculation_.complete(x0, x1, rest_, candidates_, pairs_, regions_, stats))
    return true;
  plain(x0, x1, stats);
  return false;
}

void StepBroadPhase::plain(const Positions& x0, const Positions& x1, CollisionStepStats& stats) {
  BroadPhaseStats bs;
  const double inflation = broad_phase_inflation(options_, max_abs(workers_.arena, x0, x1));
  workers_.arena.execute([&] {
    find_candidates(x0, x1, topo_, inflation, candidates_, &bs, options_.method, options_.delta);
  });
  const StageTimer t0;
  // One record per candidate, filled in parallel (each writes its own slot). Excluded pairs keep
  // their slot but are never tested. The excluded and near lists are short (pairs within delta
  // at rest) and sorted.
  const std::size_t nvf = candidates_.vertex_face.size();
  const std::size_t n = nvf + candidates_.edge_edge.size();
  resize_for_rewrite(pairs_.records, n);
  resize_for_rewrite(pairs_.role, n);
  resize_for_rewrite(pairs_.stale, n);
  resize_for_rewrite(pairs_.is_free, n);
  // Without rest-state exclusions (most meshes; bear and its subdivisions) every pair is live,
  // and the live list (collect_live) is the identity: the record pass writes it while the
  // stencils are in cache. As a second pass it re-read every record, a measurable share of the
  // records' time (lab/scripts/scale_benchmark.py --phases, the pair records row; lab/history.md).
  const bool all_live = rest_.none_excluded();
  if (all_live) {
    if (pairs_.live.size() < n) resize_for_rewrite(pairs_.live, n);
    if (pairs_.live_v.size() < n) resize_for_rewrite(pairs_.live_v, n);
  }
  workers_.arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, PAIR_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        rest_.fill_records(candidates_, topo_, r.begin(), r.end(), nvf,
                                           pairs_.records.data(), pairs_.role.data());
                        for (std::size_t i = r.begin(); i < r.end(); ++i) {
                          const std::uint8_t role = pairs_.role[i];
                          // A pair the broad phase shows farther than delta apart over the whole
                          // step cannot come within delta: it is marked free without a test,
                          // until a response moves one of its vertices.
                          const bool close = i < nvf ? candidates_.vertex_face_close[i]
                                                     : candidates_.edge_edge_close[i - nvf];
                          pairs_.stale[i] = close && role != EXCLUDED;
                          pairs_.is_free[i] = !pairs_.stale[i];
                        }
                        if (!all_live) return;
                        for (std::size_t i = r.begin(); i < r.end(); ++i) {
                          pairs_.live[i] = static_cast<std::uint32_t>(i);
                          pairs_.live_v[i] = pairs_.records[i].v;
                        }
                      });
  });
  if (all_live)
    pairs_.set_live_units(n);
  else
    pairs_.collect_live(workers_.arena);
  stats.broad_records_seconds += t0.elapsed();
  if (bs.method_run == BroadPhaseMethod::Grid) {
    const GridPartSeconds g = grid_part_seconds(candidates_);
    stats.broad_grid_seconds += g.build;
    stats.broad_cell_loop_seconds += g.cell_loop;
    stats.broad_output_seconds += g.output;
  }
  regions_.set(workers_.arena, x0, x1, 0.5 * options_.region_margin * options_.delta);
  stats.broad_seconds += bs.seconds + t0.elapsed();
  ++stats.broad_phase_calls;
  stats.pairs_no_culling = bs.no_culling_vertex_face + bs.no_culling_edge_edge;
  stats.pairs_broad = bs.vertex_face + bs.edge_edge;
}

}  // namespace shellcontract::collision_pipeline
