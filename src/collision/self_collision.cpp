#include "shellcontract/collision/self_collision.hpp"

#include <algorithm>
#include <chrono>

#include "shellcontract/collision/ccd.hpp"

namespace shellcontract {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

Vec3 row(const Positions& x, int i) { return Vec3(x(i, 0), x(i, 1), x(i, 2)); }

bool contains(const std::vector<std::array<int, 2>>& sorted, const std::array<int, 2>& key) {
  return std::binary_search(sorted.begin(), sorted.end(), key);
}

/// Response target: contacts closer than delta are pushed to RESPONSE_FACTOR * delta, so that a
/// resolved pair is not detected again in the next round (detection thickness < response
/// thickness, as in Bridson et al. 2002).
constexpr double RESPONSE_FACTOR = 2.0;

}  // namespace

SelfCollision::SelfCollision(const Faces& faces, const Positions& rest,
                             const CollisionOptions& options)
    : topo_(make_collision_topology(faces, static_cast<int>(rest.rows()))), options_(options) {
  // Pairs that touch (distance 0) in the rest state cannot be separated by a response that
  // keeps each pair on its starting side: exclude them for the whole run.
  find_candidates(rest, rest, topo_, options_.delta, candidates_, nullptr, options_.method);
  std::vector<Contact> touching;
  detect(rest, rest, 0.0, touching, nullptr, false, NearPairs::Include);
  for (const Contact& c : touching)
    (c.kind == CcdPrimitive::VertexFace ? excluded_vf_ : excluded_ee_).push_back(c.pair);
  std::sort(excluded_vf_.begin(), excluded_vf_.end());
  std::sort(excluded_ee_.begin(), excluded_ee_.end());
  // Pairs closer than delta (but not touching) in the rest state are the input's own thin
  // features: the response leaves them at their rest distance (a shell at rest stays at rest),
  // but the fail-safe still keeps them from crossing.
  std::vector<Contact> near;
  detect(rest, rest, options_.delta, near, nullptr, false, NearPairs::Include);
  for (const Contact& c : near)
    (c.kind == CcdPrimitive::VertexFace ? near_vf_ : near_ee_).push_back(c.pair);
  std::sort(near_vf_.begin(), near_vf_.end());
  std::sort(near_ee_.begin(), near_ee_.end());
}

void SelfCollision::detect(const Positions& x0, const Positions& x1, double tol,
                           std::vector<Contact>& out, CollisionStepStats* stats, bool count_stage,
                           NearPairs near) {
  CcdOptions ccd;
  ccd.tolerance = tol;
  auto wanted = [near](bool is_near) {
    return near == NearPairs::Include || (near == NearPairs::Skip ? !is_near : is_near);
  };
  std::int64_t filtered = 0, tests = 0;
  double filter_s = 0.0, narrow_s = 0.0;
  auto test = [&](CcdPrimitive kind, const std::array<int, 2>& pair, const std::array<int, 4>& v) {
    CcdStencil s0, s1;
    for (int k = 0; k < 4; ++k) {
      s0[k] = row(x0, v[k]);
      s1[k] = row(x1, v[k]);
    }
    auto t0 = Clock::now();
    const bool culled = nonpenetration_filter_culls(kind, s0, s1, tol);
    filter_s += since(t0);
    if (culled) return;
    ++filtered;
    t0 = Clock::now();
    const CcdResult r = primitive_ccd(kind, s0, s1, ccd);
    narrow_s += since(t0);
    ++tests;
    if (!r.hit) return;
    Contact c;
    c.kind = kind;
    c.pair = pair;
    c.v = v;
    c.weights = r.weights;
    c.normal = r.normal;
    c.side = r.side;
    out.push_back(c);
  };
  for (const auto& p : candidates_.vertex_face) {
    if (contains(excluded_vf_, p) || !wanted(contains(near_vf_, p))) continue;
    const int f = p[1];
    test(CcdPrimitive::VertexFace, p,
         {p[0], topo_.faces(f, 0), topo_.faces(f, 1), topo_.faces(f, 2)});
  }
  for (const auto& p : candidates_.edge_edge) {
    if (contains(excluded_ee_, p) || !wanted(contains(near_ee_, p))) continue;
    test(CcdPrimitive::EdgeEdge, p,
         {topo_.edges(p[0], 0), topo_.edges(p[0], 1), topo_.edges(p[1], 0), topo_.edges(p[1], 1)});
  }
  if (stats == nullptr) return;
  if (count_stage) stats->pairs_filtered = filtered;
  stats->narrow_tests += tests;
  stats->filter_seconds += filter_s;
  stats->narrow_seconds += narrow_s;
}

void SelfCollision::resolve(const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
                            CollisionStepStats& stats) {
  stats = CollisionStepStats{};
  const double delta = options_.delta;
  bool moved = true;  // x1 changed since the last broad phase
  for (int round = 0; round < options_.rounds; ++round) {
    BroadPhaseStats bs;
    find_candidates(x0, x1, topo_, delta, candidates_, &bs, options_.method);
    stats.broad_seconds += bs.seconds;
    if (round == 0) {
      stats.pairs_no_culling = bs.no_culling_vertex_face + bs.no_culling_edge_edge;
      stats.pairs_broad = bs.vertex_face + bs.edge_edge;
    }
    contacts_.clear();
    detect(x0, x1, delta, contacts_, &stats, round == 0, NearPairs::Skip);
    ++stats.rounds;
    moved = false;
    if (contacts_.empty()) {
      // No contact within delta among the pairs the response handles. The pairs that were
      // closer than delta at rest get no push, but they must not cross either.
      if (near_vf_.empty() && near_ee_.empty()) return;
      detect(x0, x1, 0.0, contacts_, &stats, false, NearPairs::Only);
      if (contacts_.empty()) return;  // the step is free
      break;                          // a near pair would touch: the fail-safe handles it
    }
    stats.contacts += static_cast<std::int64_t>(contacts_.size());
    const auto t0 = Clock::now();
    for (const Contact& c : contacts_)
      moved |= project_contact(c, RESPONSE_FACTOR * delta, x1.data(), w.data());
    stats.response_seconds += since(t0);
  }
  // Fail-safe (math-spec 10.8): revert the vertices of every pair that still touches (tolerance
  // 0: a real crossing or contact) to x0 until none is left. Reverting shrinks a swept box to a
  // subset of the old one, so one broad phase on the final x1 covers all iterations.
  if (moved) {
    BroadPhaseStats bs;
    find_candidates(x0, x1, topo_, 0.0, candidates_, &bs, options_.method);
    stats.broad_seconds += bs.seconds;
  }
  for (;;) {
    contacts_.clear();
    detect(x0, x1, 0.0, contacts_, &stats, false, NearPairs::Include);
    if (contacts_.empty()) return;
    std::int64_t reverted = 0;
    for (const Contact& c : contacts_)
      for (int v : c.v)
        if (x1.row(v) != x0.row(v)) {
          x1.row(v) = x0.row(v);
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
