// Self-collision handling for one time step (paper section 4, math-spec 10): broad phase,
// non-penetration filter, narrow phase, signed-constraint response in rounds, and a fail-safe
// that guarantees the step creates no new contact. Eigen only (CGAL stays in broad_phase.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "shellcontract/collision/broad_phase.hpp"
#include "shellcontract/collision/contact.hpp"
#include "shellcontract/core/types.hpp"

namespace shellcontract {

/// Options of the collision handling (normalized units: bounding-box diagonal 1).
struct CollisionOptions {
  /// delta: contact distance. Primitives that come closer than delta during a step are pushed
  /// apart to 2 delta (math-spec 10.8, 14: paper value 1e-4, here relative to the diagonal).
  double delta = 1e-4;
  int rounds = 5;  ///< N_c detection/response rounds before the fail-safe (math-spec 10.8)
  BroadPhaseMethod method = DEFAULT_BROAD_PHASE_METHOD;
  /// Threads of the broad phase's cell loop, the filter and the narrow phase (0 = all cores).
  /// Results do not depend on it.
  int threads = 0;
  /// Warm start: before detection, push the end positions apart along the frozen frames of the
  /// previous step's contacts, detected or still pressed (resting contact persists from step to
  /// step, see SelfCollision::resolve), so that detection finds and pushes fewer pairs.
  /// Detection and the fail-safe still decide; off gives the plain per-step response of
  /// math-spec 10.8.
  bool warm_start = true;
  /// m / delta >= 0: the step's broad phase inflates by delta + m/2 (broad_phase_inflation), and
  /// the response keeps each vertex within m/2 of its swept box (see SelfCollision::resolve;
  /// measurements in self_collision.cpp).
  double region_margin = 4.0;
  /// Speculative broad phase: predict() builds the step's broad phase on predicted end positions
  /// on a spare thread while the constraint solve runs, and resolve() completes it for the
  /// actual ones (see predict). The candidate pairs are the same as without it, but their order
  /// differs (and pairs far apart are always flagged, also where the plain grid falls back to
  /// CGAL), so the step's result can differ in its last bits; it never depends on the thread
  /// count. Off, or when predict is not called, resolve runs the broad phase itself. The
  /// Simulator sets it from SimOptions::speculative_broad_phase.
  bool speculative = true;
  /// After a response push, the passes that mark the pairs of the moved vertices and collect
  /// the next tests visit only the pairs around the step's moved vertices while no other vertex
  /// moves (see SelfCollision::mark_moved_and_collect); off, every pass visits every live pair.
  /// The same tests in the same order either way, so the result does not depend on it.
  bool narrow_rescans = true;
};

/// The broad phase's inflation of every swept box: delta + m/2, m = region_margin * delta. Each
/// box keeps math-spec 10.2's inflation by delta, grown by the region every vertex stays in (see
/// SelfCollision::resolve), so every pair the step can still bring within delta is a candidate
/// (the argument, rounding included, is at its definition in self_collision.cpp).
double broad_phase_inflation(const CollisionOptions& options);

/// Counters of one step (CSV log) and the stages of the paper's Table 2.
struct CollisionStepStats {
  std::int64_t pairs_no_culling = 0;  ///< all non-adjacent VF + EE pairs
  std::int64_t pairs_broad = 0;       ///< after the broad phase (broad_phase_inflation)
  std::int64_t pairs_filtered = 0;    ///< left after the box cull and the filter (first round)
  std::int64_t filter_tests = 0;      ///< non-penetration filter evaluations, all passes
  std::int64_t narrow_tests = 0;      ///< narrow-phase queries run, all rounds
  /// narrow-phase queries that separating_axis_culls settled before the interval search (the
  /// rest, narrow_tests - axis_culls, went through the coplanarity cubic's root isolation)
  std::int64_t axis_culls = 0;
  std::int64_t contacts = 0;          ///< contacts found, all rounds
  int rounds = 0;                     ///< detection rounds run
  /// Passes that marked the moved vertices' pairs and collected the next tests: over every live
  /// pair, or over the zone around the step's moved vertices (CollisionOptions::narrow_rescans)
  int rescans_full = 0;
  int rescans_in_zone = 0;
  int broad_phase_calls = 0;          ///< broad phases run (one per step, see resolve)
  std::int64_t failsafe_vertices = 0; ///< vertices reverted to their start position
  std::int64_t unresolved = 0;        ///< static pairs still reported after the fail-safe
  double broad_seconds = 0.0;
  double filter_seconds = 0.0;
  double narrow_seconds = 0.0;
  double response_seconds = 0.0;
  /// 1 if the step's broad phase was the speculative one (SelfCollision::predict), completed for
  /// the actual end positions; 0 if resolve ran it itself.
  int speculative = 0;
  /// Speculative steps: vertices whose swept box left its predicted box (their primitives were
  /// queried again).
  std::int64_t escaped_vertices = 0;
  /// Wall time of the speculative broad phase's task on the spare thread, which overlaps the
  /// constraint solve: not part of `seconds`, which holds what the calling thread spends (in
  /// predict, waiting for the task, completing it).
  double background_seconds = 0.0;
  /// Parts of background_seconds (diagnostics; 0 when it is): the task's grid construction or
  /// patch, the grid's cell loop, the grid's output of the pairs, and the per-pair records. The
  /// rest of the task is bookkeeping between them.
  double background_grid_seconds = 0.0;
  double background_cell_loop_seconds = 0.0;
  double background_output_seconds = 0.0;
  double background_records_seconds = 0.0;
  /// Steps with a prediction: the calling thread's time in predict, before the solve (part of
  /// broad_seconds and of seconds).
  double predict_seconds = 0.0;
  /// Steps with a prediction: wall time the calling thread spent on the speculative task after
  /// the solve (waiting for it, or taking over its remaining work; with one thread, running it
  /// all). Part of broad_seconds: the time the task still cost the step.
  double wait_seconds = 0.0;
  /// Wall time the calling thread spends on the step's collision handling: the whole resolve
  /// call (the four stages plus the bookkeeping between them: pair lists, stale marks) and the
  /// step's predict call (also counted in broad_seconds). The collision cost per step that the
  /// logs report.
  double seconds = 0.0;
};

/// Keeps a deforming closed mesh from passing through itself.
class SelfCollision {
 public:
  /// @param faces     #F by 3 faces
  /// @param rest      #V by 3 rest positions: primitive pairs that already touch there are
  ///                  excluded from then on; pairs closer than delta there get no response push
  ///                  (the rest state is kept) but are still kept from crossing
  /// @param options   see CollisionOptions
  SelfCollision(const Faces& faces, const Positions& rest, const CollisionOptions& options);
  ~SelfCollision();
  SelfCollision(const SelfCollision&) = delete;
  SelfCollision& operator=(const SelfCollision&) = delete;

  /// Changes the end positions x1 of the step x0 -> x1 so that no pair that is not excluded
  /// touches at any t in [0,1]: response rounds (math-spec 10.8), then the fail-safe, which
  /// reverts the vertices of each still-touching pair to x0 until none is left. If x0 is free of
  /// contacts (true by induction from the rest state), so is the result.
  ///
  /// With CollisionOptions::warm_start, the previous step's contacts are first projected on x1
  /// (their frozen frames), so a resting contact is not detected and pushed again every step:
  /// those detected in the previous step and those its warm start still had to push (a contact
  /// stays in this cache while it is pressed together, one entry per pair).
  ///
  /// Work is incremental. One broad phase per step, on the swept boxes inflated by delta plus
  /// m/2 for a margin m (CollisionOptions::region_margin; broad_phase_inflation), gives the
  /// candidates of every round and of the fail-safe, because the response is clamped so that no
  /// vertex leaves its swept box grown by m/2 (a push it cannot complete is finished by the
  /// pair's other vertices in a later round, or by the fail-safe, whose revert to x0 stays inside
  /// too). After round 0 only the pairs with a vertex that the previous response moved are tested
  /// again: the others' positions, hence their answers, have not changed. The fail-safe tests the
  /// pairs not known to be free at their current positions. Before the filter, each pair's own
  /// swept boxes are compared (swept_boxes_apart): pairs kept only by the margin leave for a few
  /// nanoseconds.
  /// @param w  inverse masses (pinned vertices are not moved by the response)
  void resolve(const Positions& x0, Positions& x1, const Eigen::VectorXd& w, CollisionStepStats& stats);

  /// Starts the broad phase of the step from x0 in the background (CollisionOptions::speculative),
  /// to overlap it with the constraint solve; call it with the solver's initial guess before the
  /// solve, then resolve(x0, solved positions, ...) with the same x0.
  ///
  /// The prediction of each vertex's end position is the guess plus the solve's correction of
  /// the last step, then the warm start (resolve's first move). Each predicted swept box (x0 to
  /// the prediction, inflated as resolve's broad phase) is grown by a skin: SKIN_MIN delta plus
  /// SKIN_GROWTH times the vertex's prediction error of the last step. The grid over these boxes
  /// and the pairs' records are built on a spare thread of the collision arena. resolve() then
  /// keeps the pairs whose actual boxes overlap (every pair of two primitives whose actual boxes
  /// lie inside their predicted ones is among the grid's pairs) and queries the grid again for
  /// the primitives of the vertices whose actual box left the predicted one (plus those pairs
  /// among themselves). If x0 differs, or too many vertices left, resolve runs the plain broad
  /// phase. With CollisionOptions::threads == 1 there is no spare thread: resolve runs the same
  /// task itself (the same result as with more threads, no time gained).
  /// @param x0       the step's start positions
  /// @param x_guess  the solver's initial guess of the end positions (copied)
  /// @param w        inverse masses (the warm start's weights)
  void predict(const Positions& x0, const Positions& x_guess, const Eigen::VectorXd& w);

  /// The contact cache the next step's warm start projects (CollisionOptions::warm_start): the
  /// last resolve's detections and the contacts its warm start still had to push, one per pair.
  const std::vector<Contact>& contact_cache() const { return previous_contacts_; }

  /// For tests: whether the last resolve's list of live pairs is what its rounds assume: in
  /// increasing order, none excluded or out of the candidates, each with its stencil beside it.
  bool live_pairs_consistent() const;

  /// The candidate pairs of the last resolve's broad phase, excluded ones included: VF pairs
  /// (vertex, face) and EE pairs (edge a < edge b), each list sorted (for tests and tools).
  /// Not between predict and resolve: the speculative task may be rewriting them.
  std::pair<std::vector<std::array<int, 2>>, std::vector<std::array<int, 2>>> candidate_pairs()
      const;

  /// Number of VF and EE pairs excluded because they touch in the rest state.
  std::size_t excluded_pairs() const { return excluded_vf_.size() + excluded_ee_.size(); }

  const CollisionTopology& topology() const { return topo_; }

 private:
  /// A candidate VF or EE pair of the current broad phase, ready for the narrow phase.
  struct PairRecord {
    std::array<int, 4> v;     ///< vertex ids in the CCD stencil order (ccd.hpp)
    std::array<int, 2> pair;  ///< (vertex, face) or (edge a, edge b)
    CcdPrimitive kind;
  };

  /// Per pair (role_): how the rest state classed it.
  enum PairRole : std::uint8_t {
    NORMAL = 0,
    NEAR = 1,      ///< closer than delta at rest: no response push, fail-safe only
    EXCLUDED = 2,  ///< touching at rest: never tested
    NOT_CANDIDATE = 3,  ///< speculative pair whose actual boxes do not overlap: never tested
  };

  /// Broad phase on (x0, x1) with broad_phase_inflation; rebuilds pairs_ (excluded pairs
  /// marked, never tested). A pair is stale unless the broad phase shows its swept boxes farther
  /// than delta apart (CandidatePairs' close flags): then it is free already. Sets the regions
  /// (set_regions).
  void broad_phase(const Positions& x0, const Positions& x1, CollisionStepStats& stats);

  /// The speculative broad phase's completion (see predict): waits for the background task,
  /// then sets pairs_, role_, stale_, free_ and the regions as broad_phase would, with the same
  /// candidate pairs. Returns false (nothing set) if resolve must run broad_phase instead.
  bool complete_speculation(const Positions& x0, const Positions& x1, CollisionStepStats& stats);

  /// The regions the response keeps each vertex in: its swept box over (x0, x1) grown by m/2,
  /// m = region_margin * delta (region_lo_, region_hi_).
  void set_regions(const Positions& x0, const Positions& x1);

  /// Runs on the spare thread: the grid over spec_boxes_ and the records of its pairs.
  void run_speculation();

  /// pairs_[i] from the broad phase's candidate i (VF first) and roles[i] its rest-state role,
  /// for i in [begin, end).
  void fill_records(std::size_t begin, std::size_t end, std::size_t nvf, std::uint8_t* roles);

  /// The rest-state role of a VF or EE pair (excluded and near lists).
  PairRole rest_role(CcdPrimitive kind, const std::array<int, 2>& pair) const;

  /// Filter and narrow phase with tolerance tol on the pairs listed in tests_[0, test_count_)
  /// (indices into pairs_), in parallel, one region for both stages; afterwards free_ and stale_
  /// of those pairs are updated and contacts_ holds their hits in the order of tests_ (so the
  /// result does not depend on the threads).
  void detect(const Positions& x0, const Positions& x1, double tol, CollisionStepStats& stats,
              bool count_stage);

  /// resolve without the timer (stats already reset).
  void resolve_impl(const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
                    CollisionStepStats& stats);

  /// Projects the contact cache (previous_contacts_) on x1 once (see
  /// CollisionOptions::warm_start); appends those it moved (still pressed together) to
  /// `pressed` if given.
  void warm_start(Positions& x1, const Eigen::VectorXd& w,
                  std::vector<Contact>* pressed = nullptr) const;

  /// The next step's contact cache: the step's detections (previous_contacts_, the last one of
  /// each pair) and the warm start's pressed contacts that were not detected again.
  void update_contact_cache();

  /// Marks stale every live pair with a vertex in moved_ and clears moved_, then sets tests_ to
  /// the live pairs to test next, in increasing order, in the same pass over the pairs: the
  /// rounds' (stale and NORMAL) or, with FAILSAFE, the fail-safe's (stale, or not free, or NEAR).
  /// Visits only the zone's pairs where that gives the same (CollisionOptions::narrow_rescans);
  /// counts the pass in stats.
  template <bool FAILSAFE>
  void mark_moved_and_collect(CollisionStepStats& stats);

  /// Sets the live pairs (live_, live_v_, live_units_) to the pairs that may ever be tested (role
  /// NORMAL or NEAR), in increasing order: the later passes over the pairs skip the excluded
  /// ones and the speculative broad phase's non-candidates.
  void collect_live();

  /// Writes the i in [0, n) with keep(i) to out[0, count), in increasing order, in parallel
  /// (the same result for any number of threads); returns count. out keeps its capacity.
  template <class Keep>
  std::size_t compact(std::size_t n, Keep keep, std::vector<std::uint32_t>& out);

  /// Closes up blocks compacted in place: block b's counts[b] entries, at the front of its slice
  /// out[b block, (b + 1) block), are moved after those of the blocks before it; returns the
  /// total.
  template <class T>
  static std::size_t close_up(std::vector<T>& out, std::size_t block,
                              const std::vector<std::size_t>& counts);

  /// Live pairs live_[begin, begin + count) (and their stencils in live_v_): the unit of work
  /// of the passes over the live pairs (see live_units_).
  struct LiveUnit {
    std::size_t begin = 0, count = 0;
  };
  /// close_up for slices that start at the units' begins: unit u's counts[u] entries.
  static std::size_t close_up(std::vector<std::uint32_t>& out, const std::vector<LiveUnit>& units,
                              const std::vector<std::size_t>& counts);

  CollisionTopology topo_;
  CollisionOptions options_;
  CandidatePairs candidates_;
  std::vector<PairRecord> pairs_;        ///< candidates of the last broad phase, in its order
  std::vector<std::uint8_t> role_;       ///< per pair: a PairRole
  std::vector<std::uint8_t> stale_;      ///< per pair: a vertex moved since its last test
  std::vector<std::uint8_t> free_;       ///< per pair: its last test found no contact
  std::vector<std::uint32_t> tests_;     ///< [0, test_count_): pairs to test in the next detect()
  /// The live pairs (see collect_live), in the slices live_units_ lists, in increasing order
  /// across them: the speculative broad phase's classification leaves them in its blocks'
  /// slices, as they are written.
  std::vector<std::uint32_t> live_;
  /// live_v_[j] = pairs_[live_[j]].v: the rounds' collection passes read the stencils in order
  /// instead of through the indices (see mark_moved_and_collect).
  std::vector<std::array<int, 4>> live_v_;
  std::vector<LiveUnit> live_units_;
  std::size_t live_count_ = 0;           ///< the live pairs in all units
  std::size_t test_count_ = 0;
  std::vector<std::size_t> block_count_; ///< compact(): kept indices per block
  /// One block of tests of detect(): what its task found (buffers reused between calls).
  struct DetectBlock {
    std::vector<std::uint32_t> kept;  ///< pairs the filter did not cull, in test order
    std::vector<Contact> hits;        ///< narrow-phase hits, in test order
    std::int64_t axis_culls = 0;      ///< survivors separating_axis_culls settled
    double filter_seconds = 0.0, narrow_seconds = 0.0;  ///< the task's time in each stage
  };
  std::vector<DetectBlock> blocks_;
  /// per vertex: flags MOVED (by the response or the fail-safe, since the last pass over the
  /// pairs) and ZONE (a zone vertex), see mark_moved_and_collect
  std::vector<std::uint8_t> moved_;
  std::vector<int> moved_list_;          ///< the vertices with MOVED set
  /// The zone of mark_moved_and_collect: per live unit, the unit's live pairs that touch a zone
  /// vertex or were stale or not free after the pass that listed them (pair ids and stencils,
  /// zone_count_[u] from the unit's begin).
  std::vector<std::uint32_t> zone_pair_;
  std::vector<std::array<int, 4>> zone_v_;
  std::vector<std::size_t> zone_count_;
  std::vector<int> zone_vertices_;       ///< the vertices with ZONE set
  enum class ZoneState : std::uint8_t { None, Ready, TooLarge };
  ZoneState zone_state_ = ZoneState::None;
  Positions region_lo_, region_hi_;      ///< per vertex, the box the response keeps it in
  struct Workers;                        ///< the thread arena (TBB stays in the .cpp)
  std::unique_ptr<Workers> workers_;
  std::vector<std::array<int, 2>> excluded_vf_;  ///< sorted
  std::vector<std::array<int, 2>> excluded_ee_;  ///< sorted
  std::vector<std::array<int, 2>> near_vf_;      ///< closer than delta at rest, sorted
  std::vector<std::array<int, 2>> near_ee_;      ///< closer than delta at rest, sorted
  std::vector<Contact> contacts_;
  /// The contact cache the warm start projects: during resolve's rounds the step's detections,
  /// afterwards (update_contact_cache) also the pressed ones of the warm start, one per pair.
  std::vector<Contact> previous_contacts_;
  std::vector<Contact> pressed_contacts_;  ///< this step's warm start moved them
  std::vector<Contact> cache_next_;        ///< update_contact_cache's output buffer
  std::vector<std::pair<std::uint64_t, std::uint32_t>> cache_keys_;  ///< (pair key, index)
  /// update_contact_cache's lookup of the detected pairs: per vertex (VF) and per edge (EE, the
  /// pair's first edge) the first of its detections in cache_next_, then cache_chain_ to the
  /// next one; NO_ENTRY ends a chain. All NO_ENTRY between calls.
  std::vector<std::uint32_t> cache_head_vf_, cache_head_ee_, cache_chain_;

  // Speculative broad phase (predict, run_speculation, complete_speculation).
  bool guess_set_ = false;           ///< predict ran since the last resolve (spec_guess_ is its)
  bool spec_pending_ = false;        ///< predict made a prediction resolve has not used yet
  bool spec_enqueued_ = false;       ///< ... and enqueued its task (not with one thread)
  bool spec_ok_ = false;             ///< the task built a grid (set by the task)
  double spec_seconds_ = 0.0;        ///< the task's wall time (set by the task)
  double spec_records_seconds_ = 0.0;  ///< the task's time filling the pair records
  double predict_seconds_ = 0.0;     ///< predict's own wall time, until resolve reports it
  Positions spec_x0_;                ///< x0 given to predict
  Positions spec_guess_;             ///< x_guess given to predict
  Positions spec_pred_;              ///< predicted end positions
  Positions correction_;             ///< last step: solved end positions minus the guess
  Eigen::VectorXd skin_;             ///< per vertex, for the next prediction
  std::vector<VertexBox> spec_boxes_;               ///< predicted boxes, grown by the skin
  std::vector<VertexBox> exact_boxes_;               ///< actual boxes (resolve)
  std::vector<std::uint8_t> base_role_;  ///< per speculative pair: its rest-state PairRole
  std::vector<std::uint8_t> escaped_;    ///< per vertex: actual box not inside the predicted one
  std::vector<std::uint32_t> escaped_prims_;  ///< their vertices, faces and edges (grid ids)
  /// One block of complete_speculation's pass over the vertices: its escaped vertices, largest
  /// |coordinate| of x0 and x1, and whether its x0 differs from predict's.
  struct VertexBlock {
    std::size_t escaped = 0;
    double max_abs = 0.0;
    bool other_x0 = false;
  };
  std::vector<VertexBlock> vertex_blocks_;
  std::vector<std::uint8_t> block_finite_;  ///< predict: per block of vertices, all finite
  /// A pair the grid queries of complete_speculation found, ready to append.
  struct QueryHit {
    PairRecord record;
    std::uint8_t role = NORMAL;  ///< its rest-state PairRole
    std::uint8_t stale = 0;      ///< to test (not flagged far, not excluded)
  };
  /// One block of the grid queries of complete_speculation (buffers reused between calls).
  struct QueryBlock {
    std::vector<std::uint32_t> hits;  ///< query_kept_grid's output
    std::vector<QueryHit> pairs;      ///< the (escaped, grid) pairs to append, in query order
  };
  std::vector<QueryBlock> query_blocks_;
  std::vector<QueryHit> sweep_hits_;  ///< the escaped primitives' pairs among themselves
  std::vector<std::size_t> block_kept_;       ///< per block of the completion: pairs kept
  std::vector<std::size_t> block_live_;       ///< ... its live pairs (see collect_live)
  std::vector<std::size_t> block_tests_;      ///< ... its round-0 tests
  /// complete_speculation set live_ and round 0's tests_ itself (resolve skips collecting them)
  bool round0_tests_ready_ = false;
  std::vector<std::pair<double, std::uint32_t>> sweep_order_;  ///< escaped primitives by x
};

}  // namespace shellcontract
