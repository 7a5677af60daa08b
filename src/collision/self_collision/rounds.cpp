// resolve(): the response rounds (detect, push, clamp to the regions, rescan) and the fail-safe
// that reverts vertices to x0 until no pair touches.
#include "collision/self_collision/state.hpp"

namespace shellcontract {

void SelfCollision::Impl::resolve(const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
                                  CollisionStepStats& stats) {
  stats = CollisionStepStats{};
  const StageTimer start;
  resolve_impl(x0, x1, w, stats);
  // predict's share on the calling thread (the prediction, its boxes, the hand-off) is
  // collision work of this step too.
  stats.broad_seconds += predict_seconds_;
  stats.predict_seconds = predict_seconds_;
  stats.seconds = start.elapsed() + predict_seconds_;
  predict_seconds_ = 0.0;
}

void SelfCollision::Impl::resolve_impl(const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
                                       CollisionStepStats& stats) {
  const double delta = options_.delta;
  // The solve's correction of the guess, for the next step's prediction.
  if (guess_set_ && x1.rows() == spec_guess_.rows()) correction_ = x1 - spec_guess_;
  guess_set_ = false;
  pressed_contacts_.clear();
  if (options_.warm_start) {
    const StageTimer t0;
    warm_start(x1, w, &pressed_contacts_);
    t0.add_to(stats.response_seconds);
  }
  previous_contacts_.clear();
  round0_tests_ready_ = false;
  // A new step's pairs: no zone yet (see mark_moved_and_collect).
  for (int v : zone_vertices_) moved_[static_cast<std::size_t>(v)] &= ~ZONE;
  zone_vertices_.clear();
  zone_state_ = ZoneState::None;
  if (!spec_pending_ || !complete_speculation(x0, x1, stats)) broad_phase(x0, x1, stats);
  auto mark = [&](int v) {
    std::uint8_t& f = moved_[static_cast<std::size_t>(v)];
    if (f & MOVED) return;
    f |= MOVED;
    moved_list_.push_back(v);
  };
  // Round 0 tests every pair not flagged far; later rounds the pairs a response push made
  // stale. Pairs closer than delta at rest get no push (fail-safe only). Nothing has moved yet
  // (the fail-safe of the last step ends with moved_ cleared), so round 0's collection marks
  // nothing; complete_speculation collects round 0's tests in its own pass over the pairs.
  if (options_.rounds > 0 && !round0_tests_ready_) mark_moved_and_collect<false>(stats);
  for (int round = 0; round < options_.rounds; ++round) {
    if (test_count_ == 0) break;
    detect(x0, x1, delta, stats, round == 0);
    ++stats.rounds;
    if (contacts_.empty()) break;
    stats.contacts += static_cast<std::int64_t>(contacts_.size());
    previous_contacts_.insert(previous_contacts_.end(), contacts_.begin(), contacts_.end());
    const StageTimer t0;
    for (const Contact& c : contacts_) {
      if (!project_contact(c, RESPONSE_FACTOR * delta, x1.data(), w.data())) continue;
      for (int v : c.v) {
        mark(v);
        // Clamped to its region, a vertex keeps every pair it can form inside the candidates of
        // the step's broad phase, so no second one is needed; a push it cannot complete is left
        // to the pair's other vertices in the next round, or to the fail-safe.
        x1.row(v) = x1.row(v).cwiseMax(region_lo_.row(v)).cwiseMin(region_hi_.row(v));
      }
    }
    t0.add_to(stats.response_seconds);
    if (round + 1 < options_.rounds) mark_moved_and_collect<false>(stats);
  }
  if (options_.warm_start) {
    const StageTimer t0;
    update_contact_cache();
    t0.add_to(stats.response_seconds);
  }
  // Fail-safe (math-spec 10.8): test, with tolerance 0, every pair not known to be free at its
  // current positions, and revert the vertices of each pair that touches (a real crossing or
  // contact) to x0 until none is left. Reverting shrinks a swept box to a subset of the one the
  // broad phase saw, so its pairs stay a superset.
  for (;;) {
    mark_moved_and_collect<true>(stats);
    detect(x0, x1, 0.0, stats, false);
    if (contacts_.empty()) return;
    std::int64_t reverted = 0;
    for (const Contact& c : contacts_)
      for (int v : c.v)
        if (x1.row(v) != x0.row(v)) {
          x1.row(v) = x0.row(v);
          mark(v);
          ++reverted;
        }
    stats.failsafe_vertices += reverted;
    if (reverted == 0) {
      // Only pairs that do not move are left: they touch at t = 0 already, or the narrow phase
      // cannot prove their gap in floating point (a conservative hit). Nothing to revert.
      stats.unresolved = static_cast<std::int64_t>(contacts_.size());
      return;
    }
  }
}

}  // namespace shellcontract
