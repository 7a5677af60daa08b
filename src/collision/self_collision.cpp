#include "shellcontract/collision/self_collision.hpp"
#include "collision/broad_phase/scratch.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "shellcontract/collision/ccd.hpp"
#include "shellcontract/collision/cull_batch.hpp"
#include "shellcontract/core/error.hpp"

namespace shellcontract {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

Vec3 row(const Positions& x, int i) { return Vec3(x(i, 0), x(i, 1), x(i, 2)); }

/// Response target: contacts closer than delta are pushed to RESPONSE_FACTOR * delta, so that a
/// resolved pair is not detected again in the next round (detection thickness < response
/// thickness, as in Bridson et al. 2002).
constexpr double RESPONSE_FACTOR = 2.0;

/// Region margin (CollisionOptions::region_margin, see resolve): the step's one broad phase
/// inflates the swept boxes by delta + m/2 with m = region_margin * delta (broad_phase_inflation,
/// below), and every vertex then stays inside its swept box grown by m/2 (the response is
/// clamped to it). A small region clamps more pushes, which later rounds or the fail-safe must
/// finish; a large one gives more candidates. Measured (this machine, quiet, warm start on, with
/// the inflation delta + m of the time): bear default run, per step filter tests / rounds /
/// collision ms, fail-safe vertices over the run; and hand at P = 4 for 300 frames, fail-safe
/// vertices:
///   m = 2 delta: 128k / 3.65 / 30.5 ms, 0; hand 2004
///   m = 4 delta: 166k / 3.17 / 31.3-32.7 ms, 0; hand 1032
///   m = 8 delta: 257k / 2.96 / 37.2 ms, 0; hand 266
/// The scheme before the clamp (a second broad phase with an 8 delta margin whenever a push left
/// the region, 1.93 per step on bear): 196k / 2.81 / 49.8 ms, 0; hand 32.

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
constexpr double WARM_START_SLIDE = 2.0;

/// Speculative broad phase (SelfCollision::predict): the skin of a vertex's predicted box is
/// SKIN_MIN delta plus SKIN_GROWTH times its prediction error (max norm) of the last step.
/// Measured on bear (default run, prediction = guess + last correction, before the warm start
/// was added to it): the error has median 1e-5 and 99th percentile 1-2e-4 per step, with a tail
/// to 1e-3 at the contacts, and the same vertices keep large errors from step to step. A fixed
/// skin of 2.5 delta left 59 vertices per step outside their boxes (5 delta: 8, for a grid
/// that costs 30% more); 1.5 delta plus 4 times the last error, 9 (mean skin 2.2 delta).
constexpr double SKIN_MIN = 1.5;
constexpr double SKIN_GROWTH = 4.0;
/// If more than ESCAPE_LIMIT vertices, or this fraction of them if more, left their predicted
/// boxes, the queries would approach a full broad phase: resolve runs the plain one.
constexpr double ESCAPE_LIMIT = 64.0;
constexpr double ESCAPE_FRACTION = 1.0 / 32.0;

/// Per-vertex flags of SelfCollision::moved_ (see mark_moved_and_collect).
constexpr std::uint8_t MOVED = 1;   ///< moved since the last pass over the pairs
constexpr std::uint8_t ZONE = 2;    ///< moved since the step's start: a zone vertex

/// End of a chain in update_contact_cache's lookup.
constexpr std::uint32_t NO_ENTRY = std::numeric_limits<std::uint32_t>::max();

/// Escaped primitives per task of the speculative broad phase's grid queries (a few hundred per
/// step on bear at P = 4, ~5 microseconds each).
constexpr std::size_t QUERY_BLOCK = 8;
/// Tests per task of detect() (filter and narrow phase of one block): fixed, so the result never
/// depends on the threads. Bear's first round has ~100k tests, later rounds a few thousand.
constexpr std::size_t DETECT_BLOCK = 512;
/// Vertices per task of the passes over the vertices (predict, complete_speculation).
constexpr std::size_t VERTEX_BLOCK = 4096;
/// Pairs per task of the per-pair bookkeeping loops (records, stale marks).
constexpr std::size_t PAIR_GRAIN = 4096;
/// Indices per block of compact(): fixed, so the result never depends on the threads.
constexpr std::size_t COMPACT_BLOCK = 8192;

/// Runs body(block, begin, end) for the fixed blocks [begin, end) of VERTEX_BLOCK vertices of
/// n, in parallel on `arena`.
template <class Body>
void for_vertex_blocks(tbb::task_arena& arena, std::size_t n, Body body) {
  const std::size_t blocks = (n + VERTEX_BLOCK - 1) / VERTEX_BLOCK;
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      body(b, b * VERTEX_BLOCK, std::min(n, (b + 1) * VERTEX_BLOCK));
    });
  });
}

/// The narrow-phase stencil (ccd.hpp order) of a VF pair (vertex, face) or an EE pair.
std::array<int, 4> stencil(CcdPrimitive kind, const std::array<int, 2>& p,
                           const CollisionTopology& topo) {
  if (kind == CcdPrimitive::VertexFace)
    return {p[0], topo.faces(p[1], 0), topo.faces(p[1], 1), topo.faces(p[1], 2)};
  return {topo.edges(p[0], 0), topo.edges(p[0], 1), topo.edges(p[1], 0), topo.edges(p[1], 1)};
}

/// The VF and EE candidate pairs of `c` as narrow-phase stencils.
template <class Visit>
void for_each_pair(const CandidatePairs& c, const CollisionTopology& topo, Visit visit) {
  for (const auto& p : c.vertex_face)
    visit(CcdPrimitive::VertexFace, p, stencil(CcdPrimitive::VertexFace, p, topo));
  for (const auto& p : c.edge_edge)
    visit(CcdPrimitive::EdgeEdge, p, stencil(CcdPrimitive::EdgeEdge, p, topo));
}

void gather(const Positions& x0, const Positions& x1, const std::array<int, 4>& v, CcdStencil& s0,
            CcdStencil& s1) {
  for (int k = 0; k < 4; ++k) {
    s0[static_cast<std::size_t>(k)] = row(x0, v[static_cast<std::size_t>(k)]);
    s1[static_cast<std::size_t>(k)] = row(x1, v[static_cast<std::size_t>(k)]);
  }
}

}  // namespace

struct SelfCollision::Workers {
  tbb::task_arena arena;
  tbb::task_group background;  ///< the speculative broad phase (predict)
  explicit Workers(int threads) : arena(threads > 0 ? threads : tbb::task_arena::automatic) {}
};

// Each box is inflated by delta + m/2. A pair can come within delta in the step only if its swept
// boxes, each grown by its vertices' regions (m/2, plus the rounding of the region bounds), come
// within delta on every axis: if the boxes' gap G <= delta + m + 2u (M + m) (M = max |coordinate|,
// u the unit roundoff). Boxes grown by delta + m/2 overlap, the rounding of their bounds included,
// for every G <= 2 delta + m - 4u (M + delta + m), which covers that unless delta is below
// 6u (M + delta + m), about 1e-15 of the coordinates. An inflation of delta + m would add headroom
// for rounding that delta gives already, and widen the candidates' gap band from 6 delta to 10
// (bear at P = 4: 173k instead of 132k candidates per step; docs/design/self-collision.md).
double broad_phase_inflation(const CollisionOptions& options) {
  return options.delta + 0.5 * (options.region_margin * options.delta);
}

SelfCollision::SelfCollision(const Faces& faces, const Positions& rest,
                             const CollisionOptions& options)
    : topo_(make_collision_topology(faces, static_cast<int>(rest.rows()))),
      options_(options),
      workers_(std::make_unique<Workers>(options.threads)) {
  // Pairs that touch (distance 0) in the rest state cannot be separated by a response that
  // keeps each pair on its starting side: exclude them for the whole run. Pairs closer than
  // delta (but not touching) are the input's own thin features: the response leaves them at
  // their rest distance (a shell at rest stays at rest), but the fail-safe still keeps them
  // from crossing.
  find_candidates(rest, rest, topo_, options_.delta, candidates_, nullptr, options_.method);
  CcdOptions touch, near;
  touch.tolerance = 0.0;
  near.tolerance = options_.delta;
  for_each_pair(candidates_, topo_, [&](CcdPrimitive kind, const std::array<int, 2>& pair,
                                        const std::array<int, 4>& v) {
    CcdStencil s0, s1;
    gather(rest, rest, v, s0, s1);
    const bool vf = kind == CcdPrimitive::VertexFace;
    if (primitive_ccd(kind, s0, s1, touch).hit)
      (vf ? excluded_vf_ : excluded_ee_).push_back(pair);
    else if (primitive_ccd(kind, s0, s1, near).hit)
      (vf ? near_vf_ : near_ee_).push_back(pair);
  });
  // Sorted for the binary searches of broad_phase (the Grid's candidates are in cell order).
  for (auto* list : {&excluded_vf_, &excluded_ee_, &near_vf_, &near_ee_})
    std::sort(list->begin(), list->end());
  moved_.assign(static_cast<std::size_t>(rest.rows()), 0);
}

SelfCollision::~SelfCollision() {
  if (!spec_enqueued_) return;
  try {
    workers_->arena.execute([&] { workers_->background.wait(); });
  } catch (...) {
    // The task's own failure does not matter any more; it must only not outlive the members.
  }
}

SelfCollision::PairRole SelfCollision::rest_role(CcdPrimitive kind,
                                                 const std::array<int, 2>& pair) const {
  auto listed = [&](const std::vector<std::array<int, 2>>& list) {
    return !list.empty() && std::binary_search(list.begin(), list.end(), pair);
  };
  const bool vf = kind == CcdPrimitive::VertexFace;
  if (listed(vf ? excluded_vf_ : excluded_ee_)) return EXCLUDED;
  if (listed(vf ? near_vf_ : near_ee_)) return NEAR;
  return NORMAL;
}

void SelfCollision::fill_records(std::size_t begin, std::size_t end, std::size_t nvf,
                                 std::uint8_t* roles) {
  // One loop per kind over raw pointers, and the rest-state lists searched only if the kind has
  // any (none on bear): the per-pair call with its member reloads took 1.2 ms of CPU per step
  // for bear's 221k speculative pairs at P = 4 (perf), on the background task's thread.
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
SelfCollision::candidate_pairs() const {
  std::pair<std::vector<std::array<int, 2>>, std::vector<std::array<int, 2>>> out;
  for (std::size_t i = 0; i < pairs_.size(); ++i) {
    if (i < role_.size() && role_[i] == NOT_CANDIDATE) continue;
    (pairs_[i].kind == CcdPrimitive::VertexFace ? out.first : out.second).push_back(pairs_[i].pair);
  }
  std::sort(out.first.begin(), out.first.end());
  std::sort(out.second.begin(), out.second.end());
  return out;
}

bool SelfCollision::live_pairs_consistent() const {
  std::size_t count = 0, next = 0;
  bool first = true;
  std::uint32_t last = 0;
  for (const LiveUnit& u : live_units_) {
    if (u.begin < next || u.begin + u.count > live_.size() || u.begin + u.count > live_v_.size())
      return false;
    next = u.begin + u.count;
    for (std::size_t j = u.begin; j < next; ++j) {
      const std::uint32_t i = live_[j];
      if (i >= pairs_.size() || i >= role_.size() || role_[i] >= EXCLUDED) return false;
      if (!first && last >= i) return false;
      if (live_v_[j] != pairs_[i].v) return false;
      first = false;
      last = i;
    }
    count += u.count;
  }
  return count == live_count_;
}

void SelfCollision::predict(const Positions& x0, const Positions& x_guess,
                            const Eigen::VectorXd& w) {
  if (!options_.speculative || options_.method != BroadPhaseMethod::Grid) return;
  const auto t0 = Clock::now();
  if (x0.rows() != topo_.num_vertices || x_guess.rows() != topo_.num_vertices ||
      w.size() != topo_.num_vertices)
    throw UsageError("SelfCollision::predict: position or mass arrays do not match the mesh");
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
  const double inflation = broad_phase_inflation(options_);
  spec_boxes_.resize(nvs);
  // Non-finite predictions or boxes (a blow-up the simulator will report) make no grid: plain
  // path. (A NaN prediction can leave its box finite: std::min and std::max pass the other
  // argument.)
  block_finite_.assign((nvs + VERTEX_BLOCK - 1) / VERTEX_BLOCK, 1);
  for_vertex_blocks(workers_->arena, nvs, [&](std::size_t blk, std::size_t begin, std::size_t end) {
    bool finite = true;
    for (std::size_t i = begin; i < end; ++i) {
      const Eigen::Index v = static_cast<Eigen::Index>(i);
      detail::GridVertexBox& b = spec_boxes_[i];
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
  predict_seconds_ += since(t0);
}

void SelfCollision::run_speculation() {
  const auto t0 = Clock::now();
  spec_ok_ = find_candidates_in_vertex_boxes(spec_boxes_, topo_, candidates_);
  spec_records_seconds_ = 0.0;
  if (spec_ok_) {
    const auto tr = Clock::now();
    const std::size_t nvf = candidates_.vertex_face.size();
    const std::size_t n = nvf + candidates_.edge_edge.size();
    pairs_.resize(n);
    base_role_.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, PAIR_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        fill_records(r.begin(), r.end(), nvf, base_role_.data());
                      });
    spec_records_seconds_ = since(tr);
  }
  spec_seconds_ = since(t0);
}

bool SelfCollision::complete_speculation(const Positions& x0, const Positions& x1,
                                         CollisionStepStats& stats) {
  const auto t0 = Clock::now();
  spec_pending_ = false;
  // Waits for the task (or runs it here); false if it failed. Its time is the step's wait.
  auto finish_task = [&] {
    const auto tw = Clock::now();
    bool ok = true;
    try {
      if (spec_enqueued_) {
        spec_enqueued_ = false;
        workers_->arena.execute([&] { workers_->background.wait(); });
        stats.background_seconds = spec_seconds_;
        const BroadPhaseScratch& g = *candidates_.scratch;
        stats.background_grid_seconds = g.grid_build_seconds;
        stats.background_cell_loop_seconds = g.grid_cell_loop_seconds;
        stats.background_output_seconds = g.grid_output_seconds;
        stats.background_records_seconds = spec_records_seconds_;
      } else {  // run here: its time is this thread's (broad_seconds)
        workers_->arena.execute([&] { run_speculation(); });
      }
    } catch (...) {
      // Whatever failed in the speculative task, the plain broad phase decides (and reports a
      // failure of its own, if it has one).
      ok = false;
    }
    stats.wait_seconds += since(tw);
    return ok;
  };
  // Arrays that do not match the mesh, or non-finite end positions: the plain broad phase
  // reports them (find_candidates' checks) or handles them.
  // A failed completion's time (the wait included) is broad-phase time of the step too.
  auto fail = [&] {
    stats.broad_seconds += since(t0);
    return false;
  };
  if (x0.rows() != topo_.num_vertices || x1.rows() != topo_.num_vertices || !x1.allFinite()) {
    finish_task();
    return fail();
  }
  // What needs only x0 and x1 comes first, while the task may still be running (it reads
  // spec_boxes_ and writes the pair buffers; this part writes neither). One pass over the
  // vertices, in parallel fixed blocks (each with its own counts, so nothing depends on the
  // threads): the actual boxes (the arithmetic of find_candidates), which vertices left their
  // predicted boxes, the skins of the next prediction (the end positions after the warm start
  // are what was predicted), the response regions (set_regions' arithmetic), the largest
  // coordinate (far_gap_threshold's) and whether x0 is the one predict saw. As four serial
  // passes these took 0.31 ms per step on bear at P = 4 (docs/design/self-collision.md).
  const Eigen::Index nv = x0.rows();
  const std::size_t nvs = static_cast<std::size_t>(nv);
  const double inflation = broad_phase_inflation(options_);
  const double half_margin = 0.5 * (options_.region_margin * options_.delta);
  exact_boxes_.resize(nvs);
  escaped_.resize(nvs);
  region_lo_.resize(nv, 3);
  region_hi_.resize(nv, 3);
  vertex_blocks_.resize((nvs + VERTEX_BLOCK - 1) / VERTEX_BLOCK);
  for_vertex_blocks(workers_->arena, nvs, [&](std::size_t blk, std::size_t begin, std::size_t end) {
    VertexBlock& out = vertex_blocks_[blk];
    out = VertexBlock{};
    for (std::size_t i = begin; i < end; ++i) {
      const Eigen::Index v = static_cast<Eigen::Index>(i);
      detail::GridVertexBox& e = exact_boxes_[i];
      const detail::GridVertexBox& p = spec_boxes_[i];
      bool inside = true;
      double error = 0.0;
      for (Eigen::Index d = 0; d < 3; ++d) {
        const std::size_t k = static_cast<std::size_t>(d);
        const double a = x0(v, d), c = x1(v, d);
        const double lo = std::min(a, c), hi = std::max(a, c);
        e.lo[k] = lo - inflation;
        e.hi[k] = hi + inflation;
        region_lo_(v, d) = lo - half_margin;
        region_hi_(v, d) = hi + half_margin;
        inside = inside && p.lo[k] <= e.lo[k] && e.hi[k] <= p.hi[k];
        error = std::max(error, std::abs(c - spec_pred_(v, d)));
        out.max_abs = std::max(out.max_abs, std::max(std::abs(a), std::abs(c)));
        out.other_x0 = out.other_x0 || a != spec_x0_(v, d);
      }
      escaped_[i] = !inside;
      out.escaped += !inside;
      skin_(v) = SKIN_MIN * options_.delta + SKIN_GROWTH * (std::isfinite(error) ? error : 0.0);
    }
  });
  std::size_t escaped = 0;
  double max_abs = 0.0;
  bool other_x0 = false;
  for (const VertexBlock& b : vertex_blocks_) {
    escaped += b.escaped;
    max_abs = std::max(max_abs, b.max_abs);
    other_x0 = other_x0 || b.other_x0;
  }
  const bool too_many = static_cast<double>(escaped) >
                        std::max(ESCAPE_LIMIT, ESCAPE_FRACTION * static_cast<double>(nvs));
  // The primitives with a vertex outside its predicted box (grid ids), for the queries below.
  const std::size_t nf = static_cast<std::size_t>(topo_.faces.rows());
  escaped_prims_.clear();
  if (escaped > 0 && !too_many) {
    auto esc = [&](Eigen::Index v) { return escaped_[static_cast<std::size_t>(v)] != 0; };
    for (Eigen::Index v = 0; v < nv; ++v)
      if (esc(v)) escaped_prims_.push_back(static_cast<std::uint32_t>(v));
    for (Eigen::Index f = 0; f < topo_.faces.rows(); ++f)
      if (esc(topo_.faces(f, 0)) | esc(topo_.faces(f, 1)) | esc(topo_.faces(f, 2)))
        escaped_prims_.push_back(static_cast<std::uint32_t>(nvs + static_cast<std::size_t>(f)));
    for (Eigen::Index e = 0; e < topo_.edges.rows(); ++e)
      if (esc(topo_.edges(e, 0)) | esc(topo_.edges(e, 1)))
        escaped_prims_.push_back(static_cast<std::uint32_t>(nvs + nf + static_cast<std::size_t>(e)));
  }
  const double far_gap = far_gap_threshold_for_magnitude(max_abs, inflation, options_.delta);
  const bool task_ok = finish_task();
  if (!task_ok || !spec_ok_ || too_many || other_x0) return fail();

  // The grid's pairs of two primitives inside their predicted boxes whose actual boxes overlap
  // are exactly find_candidates' pairs of such primitives (containment keeps every overlap).
  // Pairs with a vertex outside are left out here and found by the queries below.
  const std::size_t n_spec = pairs_.size();
  const std::size_t nvf_spec = candidates_.vertex_face.size();
  role_.resize(n_spec);
  stale_.resize(n_spec);
  free_.resize(n_spec);
  const std::size_t blocks = (n_spec + PAIR_GRAIN - 1) / PAIR_GRAIN;
  block_kept_.assign(blocks, 0);
  block_live_.assign(blocks, 0);
  block_tests_.assign(blocks, 0);
  if (live_.size() < n_spec) live_.resize(n_spec);
  if (live_v_.size() < n_spec) live_v_.resize(n_spec);
  if (tests_.size() < n_spec) tests_.resize(n_spec);
  auto overlap = [](const detail::GridVertexBox& a, const detail::GridVertexBox& b) {
    return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] &&
           b.lo[1] <= a.hi[1] && a.lo[2] <= b.hi[2] && b.lo[2] <= a.hi[2];
  };
  auto far = [&](const detail::GridVertexBox& a, const detail::GridVertexBox& b) {
    return b.lo[0] - a.hi[0] > far_gap || a.lo[0] - b.hi[0] > far_gap ||
           b.lo[1] - a.hi[1] > far_gap || a.lo[1] - b.hi[1] > far_gap ||
           b.lo[2] - a.hi[2] > far_gap || a.lo[2] - b.hi[2] > far_gap;
  };
  // Raw pointers copied into each task: with the byte stores of the flags the compiler would
  // otherwise reload every vector's data pointer per pair (measured 2x slower).
  const PairRecord* const rec_data = pairs_.data();
  const detail::GridVertexBox* const box_data = exact_boxes_.data();
  const std::uint8_t* const esc_data = escaped_.data();
  const std::uint8_t* const base_data = base_role_.data();
  std::uint8_t* const role_data = role_.data();
  std::uint8_t* const stale_data = stale_.data();
  std::uint8_t* const free_data = free_.data();
  std::size_t* const kept_data = block_kept_.data();
  std::size_t* const live_counts = block_live_.data();
  std::size_t* const test_counts = block_tests_.data();
  std::uint32_t* const live_data = live_.data();
  std::array<int, 4>* const live_v_data = live_v_.data();
  std::uint32_t* const tests_data = tests_.data();
  workers_->arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, blocks, [=](std::size_t blk) {
      const PairRecord* __restrict rec = rec_data;
      const detail::GridVertexBox* __restrict eb = box_data;
      const std::uint8_t* __restrict esc = esc_data;
      const std::uint8_t* __restrict base = base_data;
      std::uint8_t* __restrict role = role_data;
      std::uint8_t* __restrict stale = stale_data;
      std::uint8_t* __restrict fr = free_data;
      const double gap = far_gap;
      std::size_t kept = 0;
      // The same pass compacts the block's live pairs (collect_live) and round 0's tests (the
      // live pairs that are stale and NORMAL, as mark_moved_and_collect) to the front of the
      // block's own slices of live_ and tests_ (branch-free stores), closed up after the loop:
      // two fewer passes over the pairs.
      std::uint32_t* __restrict live_out = live_data + blk * PAIR_GRAIN;
      std::array<int, 4>* __restrict live_v_out = live_v_data + blk * PAIR_GRAIN;
      std::uint32_t* __restrict test_out = tests_data + blk * PAIR_GRAIN;
      std::size_t nlive = 0, ntests = 0;
      // VF pairs come first (the grid's lists, VF then EE): one loop per kind, so the kind is no
      // per-pair branch, and the tests are branch-free (measured on bear: 35-40% faster).
      // The boxes of the pair PF ahead are prefetched: the four box reads per pair are the
      // loop's cost (perf, bear at P = 4: its share against the solve's membrane kernel 0.61 ->
      // 0.57; 16 and 32 ahead the same).
      constexpr std::size_t PF = 16;
      auto classify_range = [&](auto vf_tag, std::size_t begin, std::size_t stop) {
        constexpr bool vf = decltype(vf_tag)::value;
        for (std::size_t i = begin; i < stop; ++i) {
          if (i + PF < stop) {
            const PairRecord& q = rec[i + PF];
            for (int k = 0; k < 4; ++k) __builtin_prefetch(&eb[static_cast<std::size_t>(q.v[k])]);
          }
          const PairRecord& p = rec[i];
          const std::size_t v0 = static_cast<std::size_t>(p.v[0]);
          const std::size_t v1 = static_cast<std::size_t>(p.v[1]);
          const std::size_t v2 = static_cast<std::size_t>(p.v[2]);
          const std::size_t v3 = static_cast<std::size_t>(p.v[3]);
          const bool out = (esc[v0] | esc[v1] | esc[v2] | esc[v3]) != 0;
          // The two primitives' actual boxes: VF vertex | face, EE edge | edge (the unions of
          // vertex boxes that find_candidates forms; min and max are exact).
          const detail::GridVertexBox &b0 = eb[v0], &b1 = eb[v1], &b2 = eb[v2], &b3 = eb[v3];
          bool meet = !out, far = false;
          for (std::size_t d = 0; d < 3; ++d) {
            const double alo = vf ? b0.lo[d] : std::min(b0.lo[d], b1.lo[d]);
            const double ahi = vf ? b0.hi[d] : std::max(b0.hi[d], b1.hi[d]);
            double blo = std::min(b2.lo[d], b3.lo[d]), bhi = std::max(b2.hi[d], b3.hi[d]);
            if (vf) {
              blo = std::min(blo, b1.lo[d]);
              bhi = std::max(bhi, b1.hi[d]);
            }
            meet = meet & (alo <= bhi) & (blo <= ahi);
            far = far | (blo - ahi > gap) | (alo - bhi > gap);
          }
          // A pair with a vertex outside its predicted box is left to the queries below.
          const std::uint8_t r = meet ? base[i] : std::uint8_t{NOT_CANDIDATE};
          const bool st = meet & (r != EXCLUDED) & !far;
          role[i] = r;
          stale[i] = st;
          fr[i] = !st;
          kept += meet;
          live_out[nlive] = static_cast<std::uint32_t>(i);
          live_v_out[nlive] = p.v;
          nlive += r < EXCLUDED;
          test_out[ntests] = static_cast<std::uint32_t>(i);
          ntests += st & (r == NORMAL);
        }
      };
      const std::size_t begin = blk * PAIR_GRAIN, end = std::min(n_spec, begin + PAIR_GRAIN);
      const std::size_t split = std::clamp(nvf_spec, begin, end);
      classify_range(std::true_type{}, begin, split);
      classify_range(std::false_type{}, split, end);
      kept_data[blk] = kept;
      live_counts[blk] = nlive;
      test_counts[blk] = ntests;
    });
  });
  std::size_t kept = 0;
  for (const std::size_t k : block_kept_) kept += k;
  // The live pairs stay in the blocks' slices (the passes over them visit the slices, so they
  // are not moved together: 2.7 MB a step on bear at P = 4).
  live_units_.resize(blocks);
  live_count_ = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    live_units_[b] = LiveUnit{b * PAIR_GRAIN, block_live_[b]};
    live_count_ += block_live_[b];
  }
  test_count_ = close_up(tests_, PAIR_GRAIN, block_tests_);

  // The primitives with a vertex outside its predicted box: each against the grid's primitives
  // without one (whose actual boxes are inside their predicted ones, so the query sees every
  // actual overlap), then against each other by a sweep along x. A few hundred queries per step
  // (bear at P = 4), in parallel blocks: 1.4 -> 0.9 ms per step, measured.
  auto ids = [&](std::uint32_t gid) { return detail::primitive_vertices(topo_, gid); };
  auto outside = [&](std::uint32_t gid) {
    const std::array<int, 3> v = ids(gid);
    for (int k = 0; k < detail::primitive_corners(v); ++k)
      if (escaped_[static_cast<std::size_t>(v[static_cast<std::size_t>(k)])]) return true;
    return false;
  };
  auto prim_box = [&](std::uint32_t gid) { return detail::primitive_box(exact_boxes_, ids(gid)); };
  // If primitives a, b (any order) are a VF or EE pair sharing no vertex whose actual boxes
  // overlap: true, and the pair.
  auto pair_of = [&](std::uint32_t a, std::uint32_t b, CcdPrimitive& kind,
                     std::array<int, 2>& pair) {
    const bool a_vertex = a < nvs, b_vertex = b < nvs;
    const bool a_face = !a_vertex && a < nvs + nf, b_face = !b_vertex && b < nvs + nf;
    const bool a_edge = a >= nvs + nf, b_edge = b >= nvs + nf;
    if (a_vertex && b_face) {
      kind = CcdPrimitive::VertexFace;
      pair = {static_cast<int>(a), static_cast<int>(b - nvs)};
    } else if (a_face && b_vertex) {
      kind = CcdPrimitive::VertexFace;
      pair = {static_cast<int>(b), static_cast<int>(a - nvs)};
    } else if (a_edge && b_edge) {
      kind = CcdPrimitive::EdgeEdge;
      const int ea = static_cast<int>(a - nvs - nf), eb = static_cast<int>(b - nvs - nf);
      pair = {std::min(ea, eb), std::max(ea, eb)};
    } else {
      return false;
    }
    const std::array<int, 3> va = ids(a), vb = ids(b);
    for (int i = 0; i < detail::primitive_corners(va); ++i)
      for (int j = 0; j < detail::primitive_corners(vb); ++j)
        if (va[static_cast<std::size_t>(i)] == vb[static_cast<std::size_t>(j)]) return false;
    return overlap(prim_box(a), prim_box(b));
  };
  // The record and flags of the pair (kind, pair) of primitives a, b, as the classification
  // pass sets them: its rest-state role; stale (to test) unless excluded or flagged far.
  auto make_hit = [&](std::uint32_t a, std::uint32_t b, CcdPrimitive kind,
                      const std::array<int, 2>& pair) {
    QueryHit h;
    h.record.kind = kind;
    h.record.pair = pair;
    h.record.v = stencil(kind, pair, topo_);
    h.role = rest_role(kind, pair);
    h.stale = h.role != EXCLUDED && !far(prim_box(a), prim_box(b));
    return h;
  };
  // Appends hits to the pairs, sizing the arrays once (push_back per pair cost 0.24 ms per step
  // on bear at P = 4).
  auto append = [&](const std::vector<QueryHit>& hits) {
    std::size_t at = pairs_.size();
    pairs_.resize(at + hits.size());
    role_.resize(at + hits.size());
    stale_.resize(at + hits.size());
    free_.resize(at + hits.size());
    kept += hits.size();
    for (const QueryHit& h : hits) {
      pairs_[at] = h.record;
      role_[at] = h.role;
      stale_[at] = h.stale;
      free_[at] = !h.stale;
      ++at;
    }
  };
  // The grid queries in parallel (fixed blocks, each its own buffers, which also hold the new
  // pairs' records and flags), the appends in order.
  const std::size_t query_blocks = (escaped_prims_.size() + QUERY_BLOCK - 1) / QUERY_BLOCK;
  const std::uint32_t nv32 = static_cast<std::uint32_t>(nvs);
  const std::uint32_t nvs_nf32 = static_cast<std::uint32_t>(nvs + nf);
  const std::uint32_t all32 = static_cast<std::uint32_t>(nvs + nf + topo_.edges.rows());
  if (query_blocks_.size() < query_blocks) query_blocks_.resize(query_blocks);
  workers_->arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, query_blocks, [&](std::size_t blk) {
      QueryBlock& out = query_blocks_[blk];
      out.pairs.clear();
      const std::size_t stop = std::min(escaped_prims_.size(), (blk + 1) * QUERY_BLOCK);
      for (std::size_t k = blk * QUERY_BLOCK; k < stop; ++k) {
        const std::uint32_t a = escaped_prims_[k];
        out.hits.clear();
        // Only the kind a pairs with: a vertex the faces, a face the vertices, an edge the edges.
        const std::uint32_t first = a < nvs ? nv32 : a < nvs + nf ? 0 : nvs_nf32;
        const std::uint32_t end = a < nvs ? nvs_nf32 : a < nvs + nf ? nv32 : all32;
        query_kept_grid(candidates_, topo_, prim_box(a), out.hits, first, end);
        CcdPrimitive kind;
        std::array<int, 2> pair;
        for (const std::uint32_t b : out.hits)
          if (!outside(b) && pair_of(a, b, kind, pair))
            out.pairs.push_back(make_hit(a, b, kind, pair));
      }
    });
  });
  for (std::size_t blk = 0; blk < query_blocks; ++blk) append(query_blocks_[blk].pairs);
  // Sweep and prune along x over the escaped primitives (sorted by lower x bound, then id).
  std::vector<std::pair<double, std::uint32_t>>& order = sweep_order_;
  order.clear();
  for (const std::uint32_t a : escaped_prims_) order.emplace_back(prim_box(a).lo[0], a);
  std::sort(order.begin(), order.end());
  sweep_hits_.clear();
  for (std::size_t i = 0; i < order.size(); ++i) {
    const double hi = prim_box(order[i].second).hi[0];
    for (std::size_t j = i + 1; j < order.size() && order[j].first <= hi; ++j) {
      const std::uint32_t a = order[i].second, b = order[j].second;
      CcdPrimitive kind;
      std::array<int, 2> pair;
      if (pair_of(a, b, kind, pair)) sweep_hits_.push_back(make_hit(a, b, kind, pair));
    }
  }
  append(sweep_hits_);

  // The appended pairs' live and round-0 test entries, after the grid's (increasing index):
  // their live entries in one more unit after the blocks' slices.
  const std::size_t appended = pairs_.size() - n_spec;
  const std::size_t tail = blocks * PAIR_GRAIN;
  if (live_.size() < tail + appended) live_.resize(tail + appended);
  if (live_v_.size() < tail + appended) live_v_.resize(tail + appended);
  if (tests_.size() < pairs_.size()) tests_.resize(pairs_.size());
  std::size_t tail_count = 0;
  for (std::size_t i = n_spec; i < pairs_.size(); ++i) {
    if (role_[i] < EXCLUDED) {
      live_v_[tail + tail_count] = pairs_[i].v;
      live_[tail + tail_count++] = static_cast<std::uint32_t>(i);
    }
    if (stale_[i] && role_[i] == NORMAL) tests_[test_count_++] = static_cast<std::uint32_t>(i);
  }
  if (tail_count > 0) live_units_.push_back(LiveUnit{tail, tail_count});
  live_count_ += tail_count;
  round0_tests_ready_ = true;
  stats.speculative = 1;
  stats.escaped_vertices = static_cast<std::int64_t>(escaped);
  stats.broad_seconds += since(t0);
  ++stats.broad_phase_calls;
  stats.pairs_no_culling = topo_.all_vertex_face_pairs + topo_.all_edge_edge_pairs;
  stats.pairs_broad = static_cast<std::int64_t>(kept);
  return true;
}

void SelfCollision::set_regions(const Positions& x0, const Positions& x1) {
  const double margin = options_.region_margin * options_.delta;
  region_lo_ = x0.cwiseMin(x1).array() - 0.5 * margin;
  region_hi_ = x0.cwiseMax(x1).array() + 0.5 * margin;
}

void SelfCollision::broad_phase(const Positions& x0, const Positions& x1,
                                CollisionStepStats& stats) {
  BroadPhaseStats bs;
  workers_->arena.execute([&] {
    find_candidates(x0, x1, topo_, broad_phase_inflation(options_), candidates_, &bs,
                    options_.method, options_.delta);
  });
  const auto t0 = Clock::now();
  // One record per candidate, filled in parallel (each writes its own slot). Excluded pairs keep
  // their slot but are never tested. The excluded and near lists are short (pairs within delta
  // at rest) and sorted.
  const std::size_t nvf = candidates_.vertex_face.size();
  const std::size_t n = nvf + candidates_.edge_edge.size();
  pairs_.resize(n);
  role_.resize(n);
  stale_.resize(n);
  free_.resize(n);
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
                      });
  });
  collect_live();
  set_regions(x0, x1);
  stats.broad_seconds += bs.seconds + since(t0);
  ++stats.broad_phase_calls;
  stats.pairs_no_culling = bs.no_culling_vertex_face + bs.no_culling_edge_edge;
  stats.pairs_broad = bs.vertex_face + bs.edge_edge;
}

void SelfCollision::detect(const Positions& x0, const Positions& x1, double tol,
                           CollisionStepStats& stats, bool count_stage) {
  contacts_.clear();
  const std::size_t n = test_count_;
  if (n == 0) return;
  // One parallel region per call: each task takes a fixed block of tests (never cut by the
  // thread count), runs the filter on it, then the narrow phase on the block's survivors, and
  // keeps its hits in test order. With a region per stage and compaction (five per call), bear's
  // rounds after the first took 0.68 ms each for a few thousand tests, mostly hand-offs between
  // the threads; with one, 0.44 ms. Each test is a different pair, so the tasks write different
  // bytes of free_ and stale_.
  const std::size_t blocks = (n + DETECT_BLOCK - 1) / DETECT_BLOCK;
  if (blocks_.size() < blocks) blocks_.resize(blocks);
  CcdOptions ccd;
  ccd.tolerance = tol;
  ccd.tighten_toi = false;  // the response uses the contact data, not the time of impact
  const auto start = Clock::now();
  workers_->arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      DetectBlock& out = blocks_[b];
      out.hits.clear();
      out.axis_culls = 0;
      const std::size_t begin = b * DETECT_BLOCK, end = std::min(n, begin + DETECT_BLOCK);
      const auto t0 = Clock::now();
      // Stage 1: the box cull and the certain non-penetration filter (math-spec 10.4), four
      // tests at a time (cull_batch: the same answers as swept_boxes_apart and
      // nonpenetration_filter_culls one by one); a group of four is cut where the kind changes.
      // A culled pair is free at its current positions.
      out.kept.clear();
      std::array<int, 4> v[CULL_LANES];
      std::uint8_t culled[CULL_LANES];
      for (std::size_t i = begin; i < end;) {
        const CcdPrimitive kind = pairs_[tests_[i]].kind;
        const std::size_t group_end = std::min(end, i + CULL_LANES);
        int count = 0;
        for (std::size_t j = i; j < group_end && pairs_[tests_[j]].kind == kind; ++j)
          v[count++] = pairs_[tests_[j]].v;
        cull_batch(kind, x0.data(), x1.data(), v, count, tol, culled);
        for (int k = 0; k < count; ++k, ++i) {
          if (!culled[k]) {
            out.kept.push_back(tests_[i]);
            continue;
          }
          stale_[tests_[i]] = 0;
          free_[tests_[i]] = 1;
        }
      }
      const auto t1 = Clock::now();
      // Stage 2: the narrow phase on the survivors, in test order.
      CcdStencil s0, s1;
      for (const std::uint32_t pair : out.kept) {
        const PairRecord& p = pairs_[pair];
        gather(x0, x1, p.v, s0, s1);
        stale_[pair] = 0;
        // Most survivors of the filter are neighbours apart within a common plane: the
        // separating-axis test settles them for less than a third of the interval search's
        // cost, with the same answer (ccd.hpp).
        if (separating_axis_culls(p.kind, s0, s1, tol)) {
          free_[pair] = 1;
          ++out.axis_culls;
          continue;
        }
        const CcdResult res = primitive_ccd(p.kind, s0, s1, ccd);
        free_[pair] = !res.hit;
        if (!res.hit) continue;
        Contact& c = out.hits.emplace_back();
        c.kind = p.kind;
        c.pair = p.pair;
        c.v = p.v;
        c.weights = res.weights;
        c.normal = res.normal;
        c.side = res.side;
      }
      out.filter_seconds = std::chrono::duration<double>(t1 - t0).count();
      out.narrow_seconds = since(t1);
    });
  });
  // The hits in the order of tests_: block after block.
  double filter_cpu = 0.0, narrow_cpu = 0.0;
  std::size_t m = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    const DetectBlock& block = blocks_[b];
    contacts_.insert(contacts_.end(), block.hits.begin(), block.hits.end());
    m += block.kept.size();
    stats.axis_culls += block.axis_culls;
    filter_cpu += block.filter_seconds;
    narrow_cpu += block.narrow_seconds;
  }
  // The stages share one region: its wall time is split in proportion to their CPU time.
  const double wall = since(start), cpu = filter_cpu + narrow_cpu;
  const double filter_share = cpu > 0.0 ? filter_cpu / cpu : 0.5;
  stats.filter_seconds += wall * filter_share;
  stats.narrow_seconds += wall * (1.0 - filter_share);
  stats.narrow_tests += static_cast<std::int64_t>(m);
  stats.filter_tests += static_cast<std::int64_t>(n);
  if (count_stage) stats.pairs_filtered = static_cast<std::int64_t>(m);
}

template <class Keep>
std::size_t SelfCollision::compact(std::size_t n, Keep keep, std::vector<std::uint32_t>& out) {
  // Fixed blocks (never cut by the thread count): block b compacts its kept indices, in order,
  // to the front of its own slice out[b B, (b + 1) B); the slices are then closed up in order.
  constexpr std::size_t B = COMPACT_BLOCK;
  const std::size_t blocks = (n + B - 1) / B;
  if (out.size() < n) out.resize(n);
  block_count_.resize(blocks);
  workers_->arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      std::uint32_t* dst = out.data() + b * B;
      const std::size_t end = std::min(n, (b + 1) * B);
      std::size_t k = 0;
      for (std::size_t i = b * B; i < end; ++i) {
        dst[k] = static_cast<std::uint32_t>(i);  // branch-free: keep() is hard to predict
        k += keep(i) ? 1 : 0;
      }
      block_count_[b] = k;
    });
  });
  return close_up(out, B, block_count_);
}

std::size_t SelfCollision::close_up(std::vector<std::uint32_t>& out,
                                    const std::vector<LiveUnit>& units,
                                    const std::vector<std::size_t>& counts) {
  std::size_t total = 0;
  for (std::size_t u = 0; u < units.size(); ++u) {
    if (total != units[u].begin)
      std::memmove(out.data() + total, out.data() + units[u].begin,
                   counts[u] * sizeof(std::uint32_t));
    total += counts[u];
  }
  return total;
}

template <class T>
std::size_t SelfCollision::close_up(std::vector<T>& out, std::size_t block,
                                    const std::vector<std::size_t>& counts) {
  std::size_t total = 0;
  for (std::size_t b = 0; b < counts.size(); ++b) {
    if (total != b * block)
      std::memmove(out.data() + total, out.data() + b * block, counts[b] * sizeof(T));
    total += counts[b];
  }
  return total;
}

void SelfCollision::collect_live() {
  live_count_ = compact(pairs_.size(), [&](std::size_t i) { return role_[i] < EXCLUDED; }, live_);
  if (live_v_.size() < live_count_) live_v_.resize(live_count_);
  workers_->arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, live_count_, PAIR_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t j = r.begin(); j < r.end(); ++j)
                          live_v_[j] = pairs_[live_[j]].v;
                      });
  });
  live_units_.clear();
  for (std::size_t b = 0; b < live_count_; b += COMPACT_BLOCK)
    live_units_.push_back(LiveUnit{b, std::min(COMPACT_BLOCK, live_count_ - b)});
}

template <bool FAILSAFE>
void SelfCollision::mark_moved_and_collect(CollisionStepStats& stats) {
  // One pass (one parallel region) over the live pairs marks the pairs of the moved vertices
  // stale and collects the next tests, one task per live unit. Raw pointers copied into
  // each task: through the byte stores to stale_ the compiler would otherwise reload every
  // vector's data pointer per pair.
  //
  // The zone (CollisionOptions::narrow_rescans): a full pass that marks also lists, per unit,
  // the live pairs that touch a zone vertex (one that a push or a revert has moved since the
  // step began, this pass's included) or are stale or not free after it. Until a vertex outside
  // the zone moves, every later pass visits only those: a pair outside touches no vertex that
  // has moved since, so its flags stay as the full pass left them (not stale, free) and no pass
  // would mark or collect it; the tested pairs, the only ones detect changes, are collected
  // ones. The zone pass collects the same pairs in the same order. Bear at P = 4 (timers and
  // counts in a build not committed): each pass over its 133k live pairs took 0.18 ms, while
  // rounds 2-4 collect 3,000, 700 and 200 tests per step and the fail-safe's hardly any; the
  // zone holds 38% of the live pairs, and 1.8 of the 4.4 passes per step stay in it.
  //
  // Work unit u is live_units_[u]: its live pairs, and the slots from its begin in tests_ and
  // in the zone's lists.
  const std::size_t n = live_count_;
  const std::size_t units = live_units_.size();
  const std::size_t slots = units > 0 ? live_units_.back().begin + live_units_.back().count : 0;
  if (tests_.size() < slots) tests_.resize(slots);
  block_count_.resize(units);
  const bool mark = !moved_list_.empty();
  bool in_zone = zone_state_ == ZoneState::Ready;
  for (std::size_t k = 0; in_zone && k < moved_list_.size(); ++k)
    in_zone = (moved_[static_cast<std::size_t>(moved_list_[k])] & ZONE) != 0;
  // A full pass that marks rebuilds the zone, grown by the vertices it marks (the zone only
  // grows: once too large, it stays so for the step).
  const bool build =
      !in_zone && mark && options_.narrow_rescans && zone_state_ != ZoneState::TooLarge;
  if (build) {
    if (zone_pair_.size() < slots) zone_pair_.resize(slots);
    if (zone_v_.size() < slots) zone_v_.resize(slots);
    zone_count_.resize(units);
    for (int v : moved_list_) {
      std::uint8_t& f = moved_[static_cast<std::size_t>(v)];
      if (!(f & ZONE)) zone_vertices_.push_back(v);
      f |= ZONE;
    }
  }
  ++(in_zone ? stats.rescans_in_zone : stats.rescans_full);
  const std::uint32_t* const live_data = in_zone ? zone_pair_.data() : live_.data();
  const std::array<int, 4>* const live_v_data = in_zone ? zone_v_.data() : live_v_.data();
  const std::size_t* const zone_counts = zone_count_.data();
  std::uint32_t* const zone_data = zone_pair_.data();
  std::array<int, 4>* const zone_v_data = zone_v_.data();
  std::size_t* const zone_count_data = zone_count_.data();
  const LiveUnit* const unit_data = live_units_.data();
  const std::uint8_t* const moved_data = moved_.data();
  std::uint8_t* const stale_data = stale_.data();
  const std::uint8_t* const role_data = role_.data();
  const std::uint8_t* const free_data = free_.data();
  std::uint32_t* const out_data = tests_.data();
  std::size_t* const count_data = block_count_.data();
  auto pass = [=](auto build_tag, std::size_t b) {
    constexpr bool BUILD = decltype(build_tag)::value;
    // A zone pass visits unit b's zone entries, a full pass its live pairs.
    const std::size_t at = unit_data[b].begin;
    const std::uint32_t* __restrict live = live_data + at;
    const std::array<int, 4>* __restrict live_v = live_v_data + at;
    const std::size_t count = in_zone ? zone_counts[b] : unit_data[b].count;
    const std::uint8_t* __restrict moved = moved_data;
    std::uint8_t* __restrict stale = stale_data;
    const std::uint8_t* __restrict role = role_data;
    const std::uint8_t* __restrict fr = free_data;
    std::uint32_t* __restrict dst = out_data + at;
    std::uint32_t* __restrict zone = zone_data + at;
    std::array<int, 4>* __restrict zone_v = zone_v_data + at;
    std::size_t k = 0, z = 0;
    for (std::size_t j = 0; j < count; ++j) {
      const std::uint32_t i = live[j];
      std::uint8_t st = stale[i], touch = 0;
      if (mark) {
        const std::array<int, 4>& v = live_v[j];
        touch = moved[static_cast<std::size_t>(v[0])] | moved[static_cast<std::size_t>(v[1])] |
                moved[static_cast<std::size_t>(v[2])] | moved[static_cast<std::size_t>(v[3])];
        st |= touch & MOVED;
        stale[i] = st;
      }
      const std::uint8_t unfree = fr[i] ^ 1;
      // Rounds: stale NORMAL pairs (no push for pairs near at rest). Fail-safe: every live
      // pair not known to be free at its current positions (stale, hit, or near at rest).
      const bool keep = FAILSAFE ? ((st | unfree) & (role[i] < EXCLUDED)) != 0
                                 : (st & (role[i] == NORMAL)) != 0;
      dst[k] = i;  // branch-free: keep is hard to predict
      k += keep ? 1 : 0;
      if (BUILD) {
        zone[z] = i;
        zone_v[z] = live_v[j];
        z += ((touch & ZONE) | st | unfree) != 0 ? 1 : 0;
      }
    }
    count_data[b] = k;
    if (BUILD) zone_count_data[b] = z;
  };
  workers_->arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, units, [&](std::size_t b) {
      if (build)
        pass(std::true_type{}, b);
      else
        pass(std::false_type{}, b);
    });
  });
  test_count_ = close_up(tests_, live_units_, block_count_);
  for (int v : moved_list_) moved_[static_cast<std::size_t>(v)] &= ~MOVED;
  moved_list_.clear();
  if (build) {
    // A zone of most of the pairs saves little: its passes would be nearly full ones.
    std::size_t total = 0;
    for (std::size_t b = 0; b < units; ++b) total += zone_count_[b];
    zone_state_ = total <= n / 2 ? ZoneState::Ready : ZoneState::TooLarge;
  }
}

void SelfCollision::warm_start(Positions& x1, const Eigen::VectorXd& w,
                               std::vector<Contact>* pressed) const {
  const double separation = RESPONSE_FACTOR * options_.delta;
  for (const Contact& c : previous_contacts_) {
    // Trust the frozen contact frame only while the two contact points have not slid apart
    // along the surface by more than twice the push distance.
    Vec3 gap = Vec3::Zero();
    for (int k = 0; k < 4; ++k) gap += c.weights(k) * row(x1, c.v[static_cast<std::size_t>(k)]);
    if ((gap - gap.dot(c.normal) * c.normal).norm() > WARM_START_SLIDE * separation) continue;
    if (project_contact(c, separation, x1.data(), w.data()) && pressed != nullptr)
      pressed->push_back(c);
  }
}

void SelfCollision::update_contact_cache() {
  // A contact's pair as one key: kind, then the two ids (each < 2^31).
  auto key = [](const Contact& c) {
    return (c.kind == CcdPrimitive::EdgeEdge ? std::uint64_t{1} << 62 : std::uint64_t{0}) |
           static_cast<std::uint64_t>(c.pair[0]) << 31 | static_cast<std::uint64_t>(c.pair[1]);
  };
  // The step's detections, the last one of each pair (its frame is the newest), by key.
  cache_keys_.clear();
  for (std::size_t i = 0; i < previous_contacts_.size(); ++i)
    cache_keys_.emplace_back(key(previous_contacts_[i]), static_cast<std::uint32_t>(i));
  std::sort(cache_keys_.begin(), cache_keys_.end());
  cache_next_.clear();
  for (std::size_t i = 0; i < cache_keys_.size(); ++i)
    if (i + 1 == cache_keys_.size() || cache_keys_[i + 1].first != cache_keys_[i].first)
      cache_next_.push_back(previous_contacts_[cache_keys_[i].second]);
  // Then the warm start's pressed contacts whose pair was not detected again (they are unique:
  // a subset of the last cache). The detections are looked up through chains per vertex (VF)
  // and per first edge (EE), usually one entry long: a binary search over the sorted keys per
  // pressed contact cost 0.25-0.3 ms per step on bear at P = 4 (5.3k pressed, 1.7k detected).
  const std::size_t detected = cache_next_.size();
  cache_head_vf_.resize(static_cast<std::size_t>(topo_.num_vertices), NO_ENTRY);
  cache_head_ee_.resize(static_cast<std::size_t>(topo_.edges.rows()), NO_ENTRY);
  cache_chain_.resize(detected);
  auto head = [&](const Contact& c) -> std::uint32_t& {
    std::vector<std::uint32_t>& heads =
        c.kind == CcdPrimitive::VertexFace ? cache_head_vf_ : cache_head_ee_;
    return heads[static_cast<std::size_t>(c.pair[0])];
  };
  for (std::size_t i = 0; i < detected; ++i) {
    std::uint32_t& first = head(cache_next_[i]);
    cache_chain_[i] = first;
    first = static_cast<std::uint32_t>(i);
  }
  for (const Contact& c : pressed_contacts_) {
    bool found = false;
    for (std::uint32_t i = head(c); i != NO_ENTRY && !found; i = cache_chain_[i])
      found = cache_next_[i].kind == c.kind && cache_next_[i].pair == c.pair;
    if (!found) cache_next_.push_back(c);
  }
  for (std::size_t i = 0; i < detected; ++i) head(cache_next_[i]) = NO_ENTRY;
  previous_contacts_.swap(cache_next_);
}

void SelfCollision::resolve(const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
                            CollisionStepStats& stats) {
  stats = CollisionStepStats{};
  const auto start = Clock::now();
  resolve_impl(x0, x1, w, stats);
  // predict's share on the calling thread (the prediction, its boxes, the hand-off) is
  // collision work of this step too.
  stats.broad_seconds += predict_seconds_;
  stats.predict_seconds = predict_seconds_;
  stats.seconds = since(start) + predict_seconds_;
  predict_seconds_ = 0.0;
}

void SelfCollision::resolve_impl(const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
                                 CollisionStepStats& stats) {
  const double delta = options_.delta;
  // The solve's correction of the guess, for the next step's prediction.
  if (guess_set_ && x1.rows() == spec_guess_.rows()) correction_ = x1 - spec_guess_;
  guess_set_ = false;
  pressed_contacts_.clear();
  if (options_.warm_start) {
    const auto t0 = Clock::now();
    warm_start(x1, w, &pressed_contacts_);
    stats.response_seconds += since(t0);
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
    const auto t0 = Clock::now();
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
    stats.response_seconds += since(t0);
    if (round + 1 < options_.rounds) mark_moved_and_collect<false>(stats);
  }
  if (options_.warm_start) {
    const auto t0 = Clock::now();
    update_contact_cache();
    stats.response_seconds += since(t0);
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
