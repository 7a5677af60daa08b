// SelfCollision: its public calls, and resolve() wiring the pipeline's parts in order (contact
// cache, broad phase, detection, response; docs/design/collision-pipeline.md).
#include "collision/self_collision/impl.hpp"
#include "core/stage_timer.hpp"

namespace shellcontract {

using namespace collision_pipeline;

SelfCollision::Impl::Impl(const Faces& faces, const Positions& rest, const CollisionOptions& opts)
    : topo(make_collision_topology(faces, static_cast<int>(rest.rows()))),
      options(opts),
      workers(std::make_unique<Workers>(opts.threads)),
      cache(opts.delta),
      broad_phase(rest, topo, options, *workers),
      response(static_cast<std::size_t>(rest.rows()), options) {}

void SelfCollision::Impl::predict(const Positions& x0, const Positions& x_guess,
                                  const Eigen::VectorXd& w) {
  broad_phase.predict(x0, x_guess, w, cache);
}

void SelfCollision::Impl::resolve(const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
                                  CollisionStepStats& stats) {
  stats = CollisionStepStats{};
  const StageTimer start;
  resolve_steps(x0, x1, w, stats);
  // predict's share on the calling thread (the prediction, its boxes, the hand-off) is
  // collision work of this step too.
  const double predict_seconds = broad_phase.speculation().take_predict_seconds();
  stats.broad_seconds += predict_seconds;
  stats.predict_seconds = predict_seconds;
  stats.seconds = start.elapsed() + predict_seconds;
}

void SelfCollision::Impl::resolve_steps(const Positions& x0, Positions& x1,
                                        const Eigen::VectorXd& w, CollisionStepStats& stats) {
  tbb::task_arena& arena = workers->arena;
  // The solve's correction of the guess, for the next step's prediction (before the warm start
  // moves x1).
  broad_phase.speculation().take_correction(x1);
  // 1. Contact cache: the last step's contacts projected on x1, then emptied for this step's.
  if (options.warm_start) {
    const StageTimer t0;
    cache.warm_start(x1, w);
    t0.add_to(stats.response_seconds);
  }
  cache.clear_detections();
  // 2. Broad phase: the step's pairs and regions (a new step's pairs: no zone yet).
  response.begin_step();
  const bool round0_collected = broad_phase.run(x0, x1, stats);
  // 3. and 4. Detection and response: the rounds, whose detections the cache keeps.
  response.rounds(arena, x0, x1, w, broad_phase.pairs(), broad_phase.regions(), round0_collected,
                  detection, cache, stats);
  // The next step's cache: this step's detections and the warm start's pressed contacts.
  if (options.warm_start) {
    const StageTimer t0;
    cache.update(static_cast<std::size_t>(topo.num_vertices),
                 static_cast<std::size_t>(topo.edges.rows()));
    t0.add_to(stats.response_seconds);
  }
  // The fail-safe, on the same pairs: reverting shrinks a swept box to a subset of the one the
  // broad phase saw.
  response.failsafe(arena, x0, x1, broad_phase.pairs(), detection, stats);
}

SelfCollision::SelfCollision(const Faces& faces, const Positions& rest,
                             const CollisionOptions& options)
    : impl_(std::make_unique<Impl>(faces, rest, options)) {}

SelfCollision::~SelfCollision() = default;

void SelfCollision::resolve(const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
                            CollisionStepStats& stats) {
  impl_->resolve(x0, x1, w, stats);
}

void SelfCollision::predict(const Positions& x0, const Positions& x_guess,
                            const Eigen::VectorXd& w) {
  impl_->predict(x0, x_guess, w);
}

const std::vector<Contact>& SelfCollision::contact_cache() const { return impl_->cache.contacts(); }

SelfCollision::PersistentState SelfCollision::persistent_state() const {
  const Speculation& s = impl_->broad_phase.speculation();
  return {impl_->cache.contacts(), s.correction(), s.skin()};
}

void SelfCollision::restore_persistent_state(PersistentState state) {
  impl_->cache.restore(std::move(state.contact_cache));
  impl_->broad_phase.speculation().restore(std::move(state.correction), std::move(state.skin));
}

bool SelfCollision::live_pairs_consistent() const {
  return impl_->broad_phase.pairs().live_consistent();
}

std::pair<std::vector<std::array<int, 2>>, std::vector<std::array<int, 2>>>
SelfCollision::candidate_pairs() const {
  return impl_->broad_phase.pairs().candidate_pairs();
}

std::size_t SelfCollision::excluded_pairs() const { return impl_->broad_phase.excluded_pairs(); }

const CollisionTopology& SelfCollision::topology() const { return impl_->topo; }

}  // namespace shellcontract
