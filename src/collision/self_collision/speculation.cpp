// The speculative broad phase, first half: predict() builds the predicted swept boxes and
// starts the grid over them on a spare thread (run_speculation) while the constraint solve runs.
#include "collision/self_collision/state.hpp"

namespace shellcontract {

void SelfCollision::Impl::predict(const Positions& x0, const Positions& x_guess,
                                  const Eigen::VectorXd& w) {
  if (!options_.speculative || options_.method != BroadPhaseMethod::Grid) return;
  const StageTimer t0;
  if (x0.rows() != topo_.num_vertices || x_guess.rows() != topo_.num_vertices ||
      w.size() != topo_.num_vertices)
    throw UsageError("SelfCollision::Impl::predict: position or mass arrays do not match the mesh");
  if (spec_enqueued_) {  // a prediction resolve never used: wait for it, then replace it
    spec_enqueued_ = false;
    workers_->arena.execute([&] { workers_->background.wait(); });
  }
  spec_pending_ = false;
  const Eigen::Index n = x0.rows();
  const double delta = options_.delta;
  // The copies and the prediction, then (after the warm start) the boxes, in parallel blocks
  // of vertices: the spare thread is idle before the solve. Elementwise, so the values do not
  // depend on the blocks.
  const std::size_t nvs = static_cast<std::size_t>(n);
  spec_x0_.resize(n, 3);
  spec_guess_.resize(n, 3);
  spec_pred_.resize(n, 3);
  const bool corrected = correction_.rows() == n;
  for_vertex_blocks(workers_->arena, nvs, [&](std::size_t, std::size_t begin, std::size_t end) {
    const Eigen::Index b = static_cast<Eigen::Index>(begin);
    const Eigen::Index m = static_cast<Eigen::Index>(end - begin);
    spec_x0_.middleRows(b, m) = x0.middleRows(b, m);
    spec_guess_.middleRows(b, m) = x_guess.middleRows(b, m);
    if (corrected)
      spec_pred_.middleRows(b, m) = x_guess.middleRows(b, m) + correction_.middleRows(b, m);
    else
      spec_pred_.middleRows(b, m) = x_guess.middleRows(b, m);
  });
  guess_set_ = true;
  if (options_.warm_start) warm_start(spec_pred_, w);
  if (skin_.size() != n) skin_ = Eigen::VectorXd::Constant(n, SKIN_MIN * delta);
  // The inflation for the predicted positions' magnitude: the actual step's may differ in its
  // rounding margin (a few u of the coordinates), which the skin covers. A non-finite
  // prediction makes no grid whatever this gives (the finiteness test below).
  const double inflation = broad_phase_inflation(options_, max_abs(x0, spec_pred_));
  spec_boxes_.resize(nvs);
  // Non-finite predictions or boxes (a blow-up the simulator will report) make no grid: plain
  // path. (A NaN prediction can leave its box finite: std::min and std::max pass the other
  // argument.)
  block_finite_.assign((nvs + VERTEX_BLOCK - 1) / VERTEX_BLOCK, 1);
  for_vertex_blocks(workers_->arena, nvs, [&](std::size_t blk, std::size_t begin, std::size_t end) {
    bool finite = true;
    for (std::size_t i = begin; i < end; ++i) {
      const Eigen::Index v = static_cast<Eigen::Index>(i);
      VertexBox& b = spec_boxes_[i];
      for (Eigen::Index d = 0; d < 3; ++d) {
        const std::size_t k = static_cast<std::size_t>(d);
        const double a = x0(v, d), c = spec_pred_(v, d);
        b.lo[k] = std::min(a, c) - inflation - skin_(v);
        b.hi[k] = std::max(a, c) + inflation + skin_(v);
        finite = finite && std::isfinite(c) && std::isfinite(b.lo[k]) && std::isfinite(b.hi[k]);
      }
    }
    block_finite_[blk] = finite;
  });
  const bool finite = std::all_of(block_finite_.begin(), block_finite_.end(),
                                  [](std::uint8_t f) { return f != 0; });
  if (finite) {
    spec_pending_ = true;
    spec_ok_ = false;
    // One thread asked for: no spare thread; resolve runs the same task itself, so that the
    // result is the same for any thread count.
    spec_enqueued_ = options_.threads != 1;
    if (spec_enqueued_)
      workers_->arena.enqueue(workers_->background.defer([this] { run_speculation(); }));
  }
  t0.add_to(predict_seconds_);
}

void SelfCollision::Impl::run_speculation() {
  const StageTimer t0;
  spec_ok_ = find_candidates_in_vertex_boxes(spec_boxes_, topo_, candidates_);
  spec_records_seconds_ = 0.0;
  if (spec_ok_) {
    const StageTimer tr;
    const std::size_t nvf = candidates_.vertex_face.size();
    const std::size_t n = nvf + candidates_.edge_edge.size();
    resize_for_rewrite(pairs_, n);
    resize_for_rewrite(base_role_, n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, PAIR_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        fill_records(r.begin(), r.end(), nvf, base_role_.data());
                      });
    spec_records_seconds_ = tr.elapsed();
  }
  spec_seconds_ = t0.elapsed();
}

}  // namespace shellcontract
