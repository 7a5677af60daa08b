// The speculative broad phase, first half: predict() builds the predicted swept boxes and
// starts the grid over them on a spare thread (run_task) while the constraint solve runs.
#include "collision/self_collision/speculation.hpp"

#include <tbb/blocked_range.h>

#include <cmath>

#include "core/stage_timer.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract::collision_pipeline {

Speculation::Speculation(const CollisionTopology& topo, const CollisionOptions& options,
                         Workers& workers)
    : topo_(topo), options_(options), workers_(workers) {}

void Speculation::take_correction(const Positions& x1) {
  if (guess_set_ && x1.rows() == guess_.rows()) correction_ = x1 - guess_;
  guess_set_ = false;
}

void Speculation::wait() noexcept {
  if (!enqueued_) return;
  try {
    workers_.arena.execute([&] { workers_.background.wait(); });
  } catch (...) {
    // The task's own failure does not matter any more; it must only not outlive the members.
  }
}

void Speculation::predict(const Positions& x0, const Positions& x_guess, const Eigen::VectorXd& w,
                          const ContactCache& cache, const RestPairs& rest,
                          CandidatePairs& candidates, StepPairs& pairs) {
  if (!options_.speculative || options_.method != BroadPhaseMethod::Grid) return;
  const StageTimer t0;
  if (x0.rows() != topo_.num_vertices || x_guess.rows() != topo_.num_vertices ||
      w.size() != topo_.num_vertices)
    throw UsageError("SelfCollision::Impl::predict: position or mass arrays do not match the mesh");
  if (enqueued_) {  // a prediction resolve never used: wait for it, then replace it
    enqueued_ = false;
    workers_.arena.execute([&] { workers_.background.wait(); });
  }
  pending_ = false;
  const Eigen::Index n = x0.rows();
  const double delta = options_.delta;
  // The copies and the prediction, then (after the warm start) the boxes, in parallel blocks
  // of vertices: the spare thread is idle before the solve. Elementwise, so the values do not
  // depend on the blocks.
  const std::size_t nvs = static_cast<std::size_t>(n);
  x0_.resize(n, 3);
  guess_.resize(n, 3);
  pred_.resize(n, 3);
  const bool corrected = correction_.rows() == n;
  for_vertex_blocks(workers_.arena, nvs, [&](std::size_t, std::size_t begin, std::size_t end) {
    const Eigen::Index b = static_cast<Eigen::Index>(begin);
    const Eigen::Index m = static_cast<Eigen::Index>(end - begin);
    x0_.middleRows(b, m) = x0.middleRows(b, m);
    guess_.middleRows(b, m) = x_guess.middleRows(b, m);
    if (corrected)
      pred_.middleRows(b, m) = x_guess.middleRows(b, m) + correction_.middleRows(b, m);
    else
      pred_.middleRows(b, m) = x_guess.middleRows(b, m);
  });
  guess_set_ = true;
  if (options_.warm_start) cache.warm_start_prediction(pred_, w);
  if (skin_.size() != n) skin_ = Eigen::VectorXd::Constant(n, SKIN_MIN * delta);
  // The inflation for the predicted positions' magnitude: the actual step's may differ in its
  // rounding margin (a few u of the coordinates), which the skin covers. A non-finite
  // prediction makes no grid whatever this gives (the finiteness test below).
  const double inflation = broad_phase_inflation(options_, max_abs(workers_.arena, x0, pred_));
  boxes_.resize(nvs);
  // Non-finite predictions or boxes (a blow-up the simulator will report) make no grid: plain
  // path. (A NaN prediction can leave its box finite: std::min and std::max pass the other
  // argument.)
  block_finite_.assign((nvs + VERTEX_BLOCK - 1) / VERTEX_BLOCK, 1);
  for_vertex_blocks(workers_.arena, nvs, [&](std::size_t blk, std::size_t begin, std::size_t end) {
    bool finite = true;
    for (std::size_t i = begin; i < end; ++i) {
      const Eigen::Index v = static_cast<Eigen::Index>(i);
      VertexBox& b = boxes_[i];
      for (Eigen::Index d = 0; d < 3; ++d) {
        const std::size_t k = static_cast<std::size_t>(d);
        const double a = x0(v, d), c = pred_(v, d);
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
    pending_ = true;
    task_ok_ = false;
    // One thread asked for: no spare thread; resolve runs the same task itself, so that the
    // result is the same for any thread count.
    enqueued_ = options_.threads != 1;
    if (enqueued_)
      workers_.arena.enqueue(workers_.background.defer(
          [this, &rest, &candidates, &pairs] { run_task(rest, candidates, pairs); }));
  }
  t0.add_to(predict_seconds_);
}

void Speculation::run_task(const RestPairs& rest, CandidatePairs& candidates, StepPairs& pairs) {
  const StageTimer t0;
  task_ok_ = find_candidates_in_vertex_boxes(boxes_, topo_, candidates);
  task_records_seconds_ = 0.0;
  if (task_ok_) {
    const StageTimer tr;
    const std::size_t nvf = candidates.vertex_face.size();
    const std::size_t n = nvf + candidates.edge_edge.size();
    resize_for_rewrite(pairs.records, n);
    resize_for_rewrite(base_role_, n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, PAIR_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        rest.fill_records(candidates, topo_, r.begin(), r.end(), nvf,
                                          pairs.records.data(), base_role_.data());
                      });
    task_records_seconds_ = tr.elapsed();
  }
  task_seconds_ = t0.elapsed();
}

}  // namespace shellcontract::collision_pipeline
