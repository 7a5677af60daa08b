// SelfCollision's state and stages (the pimpl behind include/shellcontract/collision/
// self_collision.hpp): shared by the files of src/collision/self_collision/, one per stage:
// self_collision.cpp (set-up and the public calls), step_broad_phase.cpp (the step's pairs),
// speculation.cpp and speculation_complete.cpp (the speculative broad phase), detect.cpp (filter
// and narrow phase), live_pairs.cpp (live pairs and rescans), contact_cache.cpp (warm start),
// rounds.cpp (the response rounds and the fail-safe).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "shellcontract/collision/broad_phase.hpp"
#include "shellcontract/collision/ccd.hpp"
#include "shellcontract/collision/contact.hpp"
#include "shellcontract/collision/cull_batch.hpp"
#include "shellcontract/collision/self_collision.hpp"
#include "shellcontract/core/error.hpp"
#include "shellcontract/core/no_zero_allocator.hpp"
#include "shellcontract/core/stage_timer.hpp"

namespace shellcontract {

/// A per-pair array of the collision step (its records and flags, the live list and the tests):
/// every broad phase sizes it with resize_for_rewrite and then rewrites it whole, in parallel.
template <class T>
using PairArray = NoZeroVector<T>;

struct SelfCollision::Impl {
  Impl(const Faces& faces, const Positions& rest, const CollisionOptions& options);
  ~Impl();

  // The public calls (see SelfCollision).
  void resolve(const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
               CollisionStepStats& stats);
  void predict(const Positions& x0, const Positions& x_guess, const Eigen::VectorXd& w);
  bool live_pairs_consistent() const;
  std::pair<std::vector<std::array<int, 2>>, std::vector<std::array<int, 2>>> candidate_pairs()
      const;

  // Constants and helpers of the stages.
  static Vec3 row(const Positions& x, int i) { return Vec3(x(i, 0), x(i, 1), x(i, 2)); }

  /// Response target: contacts closer than delta are pushed to RESPONSE_FACTOR * delta, so that a
  /// resolved pair is not detected again in the next round (detection thickness < response
  /// thickness, as in Bridson et al. 2002).
  static constexpr double RESPONSE_FACTOR = 2.0;

  /// Region margin (CollisionOptions::region_margin, see resolve): the step's one broad phase
  /// inflates the swept boxes by (delta + m)/2 with m = region_margin * delta
  /// (broad_phase_inflation), and every vertex then stays inside its swept box grown by m/2 (the
  /// response is clamped to it). A small region clamps more pushes, which later rounds or the
  /// fail-safe must finish; a large one gives more candidates. Measured on bear's default run and
  /// on hand at P = 4 (lab/history.md): a wider margin costs more filter tests and collision
  /// time and leaves fewer fail-safe vertices on hand. The scheme before the clamp (a second broad
  /// phase with an 8 delta margin whenever a push left the region) was slower still, though it
  /// left fewer fail-safe vertices on hand.

  /// Warm start: a previous contact is projected again only while its contact points have slid
  /// apart (tangentially) by at most this many push distances (2 delta each): farther, the frozen
  /// normal no longer describes the pair. Measured on bear (default run, 200 frames, contacts
  /// detected per step, with the contacts of the last step only, before the contact cache below):
  /// no warm start 10,160; limit 0.5: 5,224; 1: 4,758; 2: 4,659; none: 4,698.
  ///
  /// The contacts the warm start projects are those of the last step: the ones detected then, and
  /// the ones its own warm start projected (SelfCollision::update_contact_cache). With only the
  /// detected ones, a resting contact alternated: detected in one step, warm-started (so not
  /// detected) in the next, forgotten in the one after, detected again. Measured on bear (default
  /// run; P = 4 for 300 frames), detected contacts / filter tests per step: last step's
  /// detections only 4,648 / 113k (11,749 / 243k); with the cache 864 / 78k (1,721 / 158k); V/V0
  /// at the end 0.0234 both (0.0149, 0.0150). Times: README, "Self-collision".
  static constexpr double WARM_START_SLIDE = 2.0;

  /// Speculative broad phase (SelfCollision::predict): the skin of a vertex's predicted box is
  /// SKIN_MIN delta plus SKIN_GROWTH times its prediction error (max norm) of the last step.
  /// The prediction error is small for most vertices, with a tail at the contacts, and the same
  /// vertices keep large errors from step to step; so a skin that grows with a vertex's last
  /// error leaves few vertices outside their boxes at a smaller mean skin than a fixed skin, whose
  /// grid would cost more (measured on bear; lab/history.md).
  static constexpr double SKIN_MIN = 1.5;
  static constexpr double SKIN_GROWTH = 4.0;
  /// If more than ESCAPE_LIMIT vertices, or this fraction of them if more, left their predicted
  /// boxes, the queries would approach a full broad phase: resolve runs the plain one.
  static constexpr double ESCAPE_LIMIT = 64.0;
  static constexpr double ESCAPE_FRACTION = 1.0 / 32.0;

  /// Per-vertex flags of SelfCollision::moved_ (see mark_moved_and_collect).
  static constexpr std::uint8_t MOVED = 1;  ///< moved since the last pass over the pairs
  static constexpr std::uint8_t ZONE = 2;   ///< moved since the step's start: a zone vertex

  /// End of a chain in update_contact_cache's lookup.
  static constexpr std::uint32_t NO_ENTRY = std::numeric_limits<std::uint32_t>::max();

  /// Escaped primitives per task of the speculative broad phase's grid queries (a few hundred per
  /// step on bear at P = 4, ~5 microseconds each).
  static constexpr std::size_t QUERY_BLOCK = 8;
  /// Tests per task of detect() (filter and narrow phase of one block): fixed, so the result never
  /// depends on the threads. Bear's first round has ~100k tests, later rounds a few thousand.
  static constexpr std::size_t DETECT_BLOCK = 512;
  /// Vertices per task of the passes over the vertices (predict, complete_speculation).
  static constexpr std::size_t VERTEX_BLOCK = 4096;
  /// Pairs per task of the per-pair bookkeeping loops (records, stale marks).
  static constexpr std::size_t PAIR_GRAIN = 4096;
  /// Indices per block of compact(): fixed, so the result never depends on the threads.
  static constexpr std::size_t COMPACT_BLOCK = 8192;

  /// Runs body(block, begin, end) for the fixed blocks [begin, end) of VERTEX_BLOCK vertices of
  /// n, in parallel on `arena`.
  template <class Body>
  static void for_vertex_blocks(tbb::task_arena& arena, std::size_t n, Body body) {
    const std::size_t blocks = (n + VERTEX_BLOCK - 1) / VERTEX_BLOCK;
    arena.execute([&] {
      tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
        body(b, b * VERTEX_BLOCK, std::min(n, (b + 1) * VERTEX_BLOCK));
      });
    });
  }

  /// The narrow-phase stencil (ccd.hpp order) of a VF pair (vertex, face) or an EE pair.
  static std::array<int, 4> stencil(CcdPrimitive kind, const std::array<int, 2>& p,
                                    const CollisionTopology& topo) {
    if (kind == CcdPrimitive::VertexFace)
      return {p[0], topo.faces(p[1], 0), topo.faces(p[1], 1), topo.faces(p[1], 2)};
    return {topo.edges(p[0], 0), topo.edges(p[0], 1), topo.edges(p[1], 0), topo.edges(p[1], 1)};
  }

  /// The VF and EE candidate pairs of `c` as narrow-phase stencils.
  template <class Visit>
  static void for_each_pair(const CandidatePairs& c, const CollisionTopology& topo, Visit visit) {
    for (const auto& p : c.vertex_face)
      visit(CcdPrimitive::VertexFace, p, stencil(CcdPrimitive::VertexFace, p, topo));
    for (const auto& p : c.edge_edge)
      visit(CcdPrimitive::EdgeEdge, p, stencil(CcdPrimitive::EdgeEdge, p, topo));
  }

  static void gather(const Positions& x0, const Positions& x1, const std::array<int, 4>& v,
                     CcdStencil& s0, CcdStencil& s1) {
    for (int k = 0; k < 4; ++k) {
      s0[static_cast<std::size_t>(k)] = row(x0, v[static_cast<std::size_t>(k)]);
      s1[static_cast<std::size_t>(k)] = row(x1, v[static_cast<std::size_t>(k)]);
    }
  }

  /// A candidate VF or EE pair of the current broad phase, ready for the narrow phase.
  struct PairRecord {
    std::array<int, 4> v;     ///< vertex ids in the CCD stencil order (ccd.hpp)
    std::array<int, 2> pair;  ///< (vertex, face) or (edge a, edge b)
    CcdPrimitive kind;
  };

  /// Per pair (role_): how the rest state classed it.
  enum PairRole : std::uint8_t {
    NORMAL = 0,
    NEAR = 1,           ///< closer than delta at rest: no response push, fail-safe only
    EXCLUDED = 2,       ///< touching at rest: never tested
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

  /// The largest |coordinate| of a and b (same row counts), in parallel fixed blocks; unspecified
  /// (possibly NaN) if a coordinate is not finite.
  double max_abs(const Positions& a, const Positions& b) const;

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
  /// Sets live_count_ to count and cuts live_[0, count) into live_units_ (collect_live's units);
  /// live_ and live_v_ must hold the live pairs already.
  void set_live_units(std::size_t count);

  /// Writes the i in [0, n) with keep(i) to out[0, count), in increasing order, in parallel
  /// (the same result for any number of threads); returns count. out keeps its capacity.
  template <class Keep>
  std::size_t compact(std::size_t n, Keep keep, PairArray<std::uint32_t>& out);

  /// Closes up blocks compacted in place: block b's counts[b] entries, at the front of its slice
  /// out[b block, (b + 1) block), are moved after those of the blocks before it; returns the
  /// total.
  template <class T>
  static std::size_t close_up(PairArray<T>& out, std::size_t block,
                              const std::vector<std::size_t>& counts);

  /// Live pairs live_[begin, begin + count) (and their stencils in live_v_): the unit of work
  /// of the passes over the live pairs (see live_units_).
  struct LiveUnit {
    std::size_t begin = 0, count = 0;
  };
  /// close_up for slices that start at the units' begins: unit u's counts[u] entries.
  static std::size_t close_up(PairArray<std::uint32_t>& out, const std::vector<LiveUnit>& units,
                              const std::vector<std::size_t>& counts);

  CollisionTopology topo_;
  CollisionOptions options_;
  CandidatePairs candidates_;
  PairArray<PairRecord> pairs_;     ///< candidates of the last broad phase, in its order
  PairArray<std::uint8_t> role_;    ///< per pair: a PairRole
  PairArray<std::uint8_t> stale_;   ///< per pair: a vertex moved since its last test
  PairArray<std::uint8_t> free_;    ///< per pair: its last test found no contact
  PairArray<std::uint32_t> tests_;  ///< [0, test_count_): pairs to test in the next detect()
  /// The live pairs (see collect_live), in the slices live_units_ lists, in increasing order
  /// across them: the speculative broad phase's classification leaves them in its blocks'
  /// slices, as they are written.
  PairArray<std::uint32_t> live_;
  /// live_v_[j] = pairs_[live_[j]].v: the rounds' collection passes read the stencils in order
  /// instead of through the indices (see mark_moved_and_collect).
  PairArray<std::array<int, 4>> live_v_;
  std::vector<LiveUnit> live_units_;
  std::size_t live_count_ = 0;  ///< the live pairs in all units
  std::size_t test_count_ = 0;
  std::vector<std::size_t> block_count_;  ///< compact(): kept indices per block
  /// One block of tests of detect(): what its task found (buffers reused between calls).
  struct DetectBlock {
    std::vector<std::uint32_t> kept;  ///< pairs the filter and the axes cull kept, in test order
    std::vector<Contact> hits;        ///< narrow-phase hits, in test order
    std::int64_t axis_culls = 0;      ///< survivors separating_axis_culls settled
    std::size_t axes_settled = 0;     ///< of them, those its axes half settled in the filter
    double filter_seconds = 0.0, narrow_seconds = 0.0;  ///< the task's time in each stage
  };
  std::vector<DetectBlock> blocks_;
  /// per vertex: flags MOVED (by the response or the fail-safe, since the last pass over the
  /// pairs) and ZONE (a zone vertex), see mark_moved_and_collect
  std::vector<std::uint8_t> moved_;
  std::vector<int> moved_list_;  ///< the vertices with MOVED set
  /// The zone of mark_moved_and_collect: per live unit, the unit's live pairs that touch a zone
  /// vertex or were stale or not free after the pass that listed them (pair ids and stencils,
  /// zone_count_[u] from the unit's begin).
  PairArray<std::uint32_t> zone_pair_;
  PairArray<std::array<int, 4>> zone_v_;
  std::vector<std::size_t> zone_count_;
  std::vector<int> zone_vertices_;  ///< the vertices with ZONE set
  enum class ZoneState : std::uint8_t { None, Ready, TooLarge };
  ZoneState zone_state_ = ZoneState::None;
  Positions region_lo_, region_hi_;  ///< per vertex, the box the response keeps it in
  /// The thread arena and the speculative broad phase's task group.
  struct Workers {
    tbb::task_arena arena;
    tbb::task_group background;  ///< the speculative broad phase (predict)
    explicit Workers(int threads) : arena(threads > 0 ? threads : tbb::task_arena::automatic) {}
  };
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
  bool guess_set_ = false;              ///< predict ran since the last resolve (spec_guess_ is its)
  bool spec_pending_ = false;           ///< predict made a prediction resolve has not used yet
  bool spec_enqueued_ = false;          ///< ... and enqueued its task (not with one thread)
  bool spec_ok_ = false;                ///< the task built a grid (set by the task)
  double spec_seconds_ = 0.0;           ///< the task's wall time (set by the task)
  double spec_records_seconds_ = 0.0;   ///< the task's time filling the pair records
  double predict_seconds_ = 0.0;        ///< predict's own wall time, until resolve reports it
  Positions spec_x0_;                   ///< x0 given to predict
  Positions spec_guess_;                ///< x_guess given to predict
  Positions spec_pred_;                 ///< predicted end positions
  Positions correction_;                ///< last step: solved end positions minus the guess
  Eigen::VectorXd skin_;                ///< per vertex, for the next prediction
  std::vector<VertexBox> spec_boxes_;   ///< predicted boxes, grown by the skin
  std::vector<VertexBox> exact_boxes_;  ///< actual boxes (resolve)
  PairArray<std::uint8_t> base_role_;  ///< per speculative pair: its rest-state PairRole
  std::vector<std::uint8_t> escaped_;    ///< per vertex: actual box not inside the predicted one
  std::vector<std::uint32_t> escaped_prims_;  ///< their vertices, faces and edges (grid ids)
  /// One block of complete_speculation's pass over the vertices: its escaped vertices and
  /// whether its x0 differs from predict's.
  struct VertexBlock {
    std::size_t escaped = 0;
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
  std::vector<QueryHit> sweep_hits_;      ///< the escaped primitives' pairs among themselves
  std::vector<std::size_t> block_kept_;   ///< per block of the completion: pairs kept
  std::vector<std::size_t> block_live_;   ///< ... its live pairs (see collect_live)
  std::vector<std::size_t> block_tests_;  ///< ... its round-0 tests
  /// complete_speculation set live_ and round 0's tests_ itself (resolve skips collecting them)
  bool round0_tests_ready_ = false;
  std::vector<std::pair<double, std::uint32_t>> sweep_order_;  ///< escaped primitives by x
};

template <class T>
std::size_t SelfCollision::Impl::close_up(PairArray<T>& out, std::size_t block,
                                          const std::vector<std::size_t>& counts) {
  std::size_t total = 0;
  for (std::size_t b = 0; b < counts.size(); ++b) {
    if (total != b * block)
      std::memmove(out.data() + total, out.data() + b * block, counts[b] * sizeof(T));
    total += counts[b];
  }
  return total;
}

}  // namespace shellcontract
