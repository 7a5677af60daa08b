// The step's broad phase (when not speculative): candidate pairs, their records and rest-state
// roles, and the regions the response keeps the vertices in.
#include "collision/self_collision/state.hpp"

namespace shellcontract {

SelfCollision::Impl::PairRole SelfCollision::Impl::rest_role(CcdPrimitive kind,
                                                             const std::array<int, 2>& pair) const {
  auto listed = [&](const std::vector<std::array<int, 2>>& list) {
    return !list.empty() && std::binary_search(list.begin(), list.end(), pair);
  };
  const bool vf = kind == CcdPrimitive::VertexFace;
  if (listed(vf ? excluded_vf_ : excluded_ee_)) return EXCLUDED;
  if (listed(vf ? near_vf_ : near_ee_)) return NEAR;
  return NORMAL;
}

void SelfCollision::Impl::fill_records(std::size_t begin, std::size_t end, std::size_t nvf,
                                       std::uint8_t* roles) {
  // One loop per kind over raw pointers, and the rest-state lists searched only if the kind has
  // any (none on bear): the per-pair call with its member reloads was a visible share of the
  // background task's thread at strong pressure (perf; lab/history.md).
  PairRecord* const rec = pairs_.data();
  const std::size_t split = std::clamp(nvf, begin, end);
  const bool vf_listed = !excluded_vf_.empty() || !near_vf_.empty();
  const bool ee_listed = !excluded_ee_.empty() || !near_ee_.empty();
  const std::array<int, 2>* const vf = candidates_.vertex_face.data();
  const std::array<int, 2>* const ee = candidates_.edge_edge.data();
  for (std::size_t i = begin; i < split; ++i) {
    PairRecord& p = rec[i];
    p.kind = CcdPrimitive::VertexFace;
    p.pair = vf[i];
    p.v = stencil(p.kind, p.pair, topo_);
    roles[i] = vf_listed ? rest_role(p.kind, p.pair) : NORMAL;
  }
  for (std::size_t i = split; i < end; ++i) {
    PairRecord& p = rec[i];
    p.kind = CcdPrimitive::EdgeEdge;
    p.pair = ee[i - nvf];
    p.v = stencil(p.kind, p.pair, topo_);
    roles[i] = ee_listed ? rest_role(p.kind, p.pair) : NORMAL;
  }
}

std::pair<std::vector<std::array<int, 2>>, std::vector<std::array<int, 2>>>
SelfCollision::Impl::candidate_pairs() const {
  std::pair<std::vector<std::array<int, 2>>, std::vector<std::array<int, 2>>> out;
  for (std::size_t i = 0; i < pairs_.size(); ++i) {
    if (i < role_.size() && role_[i] == NOT_CANDIDATE) continue;
    (pairs_[i].kind == CcdPrimitive::VertexFace ? out.first : out.second).push_back(pairs_[i].pair);
  }
  std::sort(out.first.begin(), out.first.end());
  std::sort(out.second.begin(), out.second.end());
  return out;
}

void SelfCollision::Impl::set_regions(const Positions& x0, const Positions& x1) {
  // In parallel blocks of rows: a serial pass is too slow on the largest meshes (lab/history.md).
  const double half = 0.5 * options_.region_margin * options_.delta;
  region_lo_.resize(x0.rows(), 3);
  region_hi_.resize(x0.rows(), 3);
  workers_->arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, x0.rows(), 4096),
                      [&](const tbb::blocked_range<Eigen::Index>& r) {
                        const Eigen::Index b = r.begin(), n = r.end() - r.begin();
                        region_lo_.middleRows(b, n) =
                            x0.middleRows(b, n).cwiseMin(x1.middleRows(b, n)).array() - half;
                        region_hi_.middleRows(b, n) =
                            x0.middleRows(b, n).cwiseMax(x1.middleRows(b, n)).array() + half;
                      });
  });
}

double SelfCollision::Impl::max_abs(const Positions& a, const Positions& b) const {
  // Per fixed block of rows, then over the blocks in order (a max is exact: any order gives it).
  const Eigen::Index n = a.rows(), block = 4096;
  const Eigen::Index blocks = (n + block - 1) / block;
  std::vector<double> partial(static_cast<std::size_t>(blocks), 0.0);
  workers_->arena.execute([&] {
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

void SelfCollision::Impl::broad_phase(const Positions& x0, const Positions& x1,
                                      CollisionStepStats& stats) {
  BroadPhaseStats bs;
  const double inflation = broad_phase_inflation(options_, max_abs(x0, x1));
  workers_->arena.execute([&] {
    find_candidates(x0, x1, topo_, inflation, candidates_, &bs, options_.method, options_.delta);
  });
  const StageTimer t0;
  // One record per candidate, filled in parallel (each writes its own slot). Excluded pairs keep
  // their slot but are never tested. The excluded and near lists are short (pairs within delta
  // at rest) and sorted.
  const std::size_t nvf = candidates_.vertex_face.size();
  const std::size_t n = nvf + candidates_.edge_edge.size();
  resize_for_rewrite(pairs_, n);
  resize_for_rewrite(role_, n);
  resize_for_rewrite(stale_, n);
  resize_for_rewrite(free_, n);
  // Without rest-state exclusions (most meshes; bear and its subdivisions) every pair is live,
  // and the live list (collect_live) is the identity: the record pass writes it while the
  // stencils are in cache. As a second pass it re-read every record, a measurable share of the
  // records' time (lab/scripts/scale_benchmark.py --phases, the pair records row; lab/history.md).
  const bool all_live = excluded_vf_.empty() && excluded_ee_.empty();
  if (all_live) {
    if (live_.size() < n) resize_for_rewrite(live_, n);
    if (live_v_.size() < n) resize_for_rewrite(live_v_, n);
  }
  workers_->arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, PAIR_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        fill_records(r.begin(), r.end(), nvf, role_.data());
                        for (std::size_t i = r.begin(); i < r.end(); ++i) {
                          const std::uint8_t role = role_[i];
                          // A pair the broad phase shows farther than delta apart over the whole
                          // step cannot come within delta: it is marked free without a test,
                          // until a response moves one of its vertices.
                          const bool close = i < nvf ? candidates_.vertex_face_close[i]
                                                     : candidates_.edge_edge_close[i - nvf];
                          stale_[i] = close && role != EXCLUDED;
                          free_[i] = !stale_[i];
                        }
                        if (!all_live) return;
                        for (std::size_t i = r.begin(); i < r.end(); ++i) {
                          live_[i] = static_cast<std::uint32_t>(i);
                          live_v_[i] = pairs_[i].v;
                        }
                      });
  });
  if (all_live)
    set_live_units(n);
  else
    collect_live();
  stats.broad_records_seconds += t0.elapsed();
  if (bs.method_run == BroadPhaseMethod::Grid) {
    const GridPartSeconds g = grid_part_seconds(candidates_);
    stats.broad_grid_seconds += g.build;
    stats.broad_cell_loop_seconds += g.cell_loop;
    stats.broad_output_seconds += g.output;
  }
  set_regions(x0, x1);
  stats.broad_seconds += bs.seconds + t0.elapsed();
  ++stats.broad_phase_calls;
  stats.pairs_no_culling = bs.no_culling_vertex_face + bs.no_culling_edge_edge;
  stats.pairs_broad = bs.vertex_face + bs.edge_edge;
}

}  // namespace shellcontract
