// The response rounds (detect, push, clamp to the regions, rescan) and the fail-safe that
// reverts vertices to x0 until no pair touches.
#include "collision/self_collision/response.hpp"

#include "core/stage_timer.hpp"

namespace shellcontract::collision_pipeline {

Response::Response(std::size_t vertices, const CollisionOptions& options)
    : delta_(options.delta), rounds_(options.rounds), rescan_(vertices, options.narrow_rescans) {}

void Response::rounds(tbb::task_arena& arena, const Positions& x0, Positions& x1,
                      const Eigen::VectorXd& w, StepPairs& pairs, const Regions& regions,
                      bool round0_collected, Detection& detection, ContactCache& cache,
                      CollisionStepStats& stats) {
  const double delta = delta_;
  // Round 0 tests every pair not flagged far; later rounds the pairs a response push made
  // stale. Pairs closer than delta at rest get no push (fail-safe only). Nothing has moved yet
  // (the fail-safe of the last step ends with no vertex marked), so round 0's collection marks
  // nothing; the speculative broad phase collects round 0's tests in its own pass over the pairs.
  if (rounds_ > 0 && !round0_collected) rescan_.collect<false>(arena, pairs, stats);
  for (int round = 0; round < rounds_; ++round) {
    if (pairs.test_count == 0) break;
    const std::vector<Contact>& contacts =
        detection.detect(arena, x0, x1, delta, pairs, stats, round == 0);
    ++stats.rounds;
    if (contacts.empty()) break;
    stats.contacts += static_cast<std::int64_t>(contacts.size());
    cache.add_detections(contacts);
    const StageTimer t0;
    for (const Contact& c : contacts) {
      if (!project_contact(c, RESPONSE_FACTOR * delta, x1.data(), w.data())) continue;
      for (int v : c.v) {
        rescan_.mark(v);
        // Clamped to its region, a vertex keeps every pair it can form inside the candidates of
        // the step's broad phase, so no second one is needed; a push it cannot complete is left
        // to the pair's other vertices in the next round, or to the fail-safe.
        x1.row(v) = x1.row(v).cwiseMax(regions.lo.row(v)).cwiseMin(regions.hi.row(v));
      }
    }
    t0.add_to(stats.response_seconds);
    if (round + 1 < rounds_) rescan_.collect<false>(arena, pairs, stats);
  }
}

void Response::failsafe(tbb::task_arena& arena, const Positions& x0, Positions& x1,
                        StepPairs& pairs, Detection& detection, CollisionStepStats& stats) {
  // Reverting shrinks a swept box to a subset of the one the broad phase saw, so its pairs stay
  // a superset. A pair that touches is a real crossing or contact.
  for (;;) {
    rescan_.collect<true>(arena, pairs, stats);
    const std::vector<Contact>& contacts =
        detection.detect(arena, x0, x1, 0.0, pairs, stats, false);
    if (contacts.empty()) return;
    std::int64_t reverted = 0;
    for (const Contact& c : contacts)
      for (int v : c.v)
        if (x1.row(v) != x0.row(v)) {
          x1.row(v) = x0.row(v);
          rescan_.mark(v);
          ++reverted;
        }
    stats.failsafe_vertices += reverted;
    if (reverted == 0) {
      // Only pairs that do not move are left: they touch at t = 0 already, or the narrow phase
      // cannot prove their gap in floating point (a conservative hit). Nothing to revert.
      stats.unresolved = static_cast<std::int64_t>(contacts.size());
      return;
    }
  }
}

}  // namespace shellcontract::collision_pipeline
