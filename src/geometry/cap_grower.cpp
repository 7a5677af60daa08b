// Growing a geodesic disc from a seed while a sphere fits it (cap_grower.hpp).
#include "geometry/cap_grower.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "geometry/sphere_moments.hpp"

namespace shellcontract::detail {
namespace {

/// Growth step of the discs, in units of the mesh's size (finer than the smallest part looked for).
constexpr double GROWTH_STEP = 0.004;
/// Vertices a disc needs before its fit is judged (fewer cannot tell a cap from noise), and
/// after which a disc that never fitted is given up.
constexpr std::size_t MIN_FIT_POINTS = 10, GIVE_UP_POINTS = 40;
constexpr double INF = std::numeric_limits<double>::infinity();

}  // namespace

std::vector<GrowthVertex> growth_vertices(const MeshArrays& m, const Positions& x, const Eigen::VectorXd& concave_field) {
  std::vector<GrowthVertex> out(m.nv);
  for (std::size_t v = 0; v < m.nv; ++v) {
    const auto i = static_cast<Eigen::Index>(v);
    out[v].point = Vec3(x.row(i));
    out[v].area = m.vertex_area[v];
    out[v].concave_area = concave_field(i) < 0.0 ? m.vertex_area[v] : 0.0;
  }
  return out;
}

CapGrower::CapGrower(const MeshArrays& m, const std::vector<GrowthVertex>& vertices, const CurvatureField& c,
                     const RegionOptions& o)
    : m_(m), v_(vertices), c_(c), o_(o), state_(m.nv, State{INF, false}), in_(m.nf, 0), keep_(m.nf, 0) {}

void CapGrower::reset() {
  for (int v : touched_) state_[static_cast<std::size_t>(v)] = State{INF, false};
  touched_.clear();
  heap_.clear();
}

std::optional<Cap> CapGrower::grow(int seed, const std::vector<char>* blocked,
                                   const std::function<bool(const Cap&)>* want_faces) {
  reset();
  const double h = GROWTH_STEP * m_.size;
  const auto s = static_cast<std::size_t>(seed);
  SphereMoments moments(v_[s].point, m_.size);
  const Vec3 n_seed(c_.normal.row(seed));
  // A min-heap on (distance, vertex), as std::priority_queue with std::greater keeps it.
  const std::greater<> later;
  state_[s].dist = 0.0;
  touched_.push_back(seed);
  heap_.emplace_back(0.0, seed);
  double boundary = h, area = 0.0, concave = 0.0, last = 0.0;
  std::size_t popped = 0;
  std::optional<Cap> best;
  bool stop = false, unbounded = false;
  const auto judge = [&]() {
    if (popped < MIN_FIT_POINTS) return;
    const std::optional<SphereFit> f = moments.fit();
    const bool pass = f && f->residual <= o_.fit_tolerance && n_seed.dot(v_[s].point - f->centre) > 0.0 &&
                      concave <= o_.max_concave_fraction * area;
    if (pass) {
      if (!best) best = Cap{};
      best->seed = seed;
      best->rho = last;
      best->sphere = *f;
    } else if (best || popped >= GIVE_UP_POINTS) {
      stop = true;
    }
  };
  while (!heap_.empty() && !stop) {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    const auto [d, v] = heap_.back();
    heap_.pop_back();
    const auto vi = static_cast<std::size_t>(v);
    if (state_[vi].popped) continue;
    if (d > boundary) {
      judge();
      if (stop) break;
      if (area > o_.max_area_fraction * m_.total_area) {
        unbounded = true;  // still fitting at the size limit: no part ends here
        break;
      }
      boundary = (std::floor(d / h) + 1.0) * h;
    }
    state_[vi].popped = true;
    ++popped;
    last = d;
    const GrowthVertex& gv = v_[vi];
    moments.add(gv.point, gv.area);
    area += gv.area;
    concave += gv.concave_area;
    for (int k = m_.nbr_start[vi]; k < m_.nbr_start[vi + 1]; ++k) {
      const auto wi = static_cast<std::size_t>(m_.nbr_to[static_cast<std::size_t>(k)]);
      State& sw = state_[wi];
      const double dw = d + m_.nbr_len[static_cast<std::size_t>(k)];
      if (sw.popped || !(dw < sw.dist) || (blocked && (*blocked)[wi])) continue;
      if (sw.dist == INF) touched_.push_back(static_cast<int>(wi));
      sw.dist = dw;
      heap_.emplace_back(dw, static_cast<int>(wi));
      std::push_heap(heap_.begin(), heap_.end(), later);
    }
  }
  if (heap_.empty() && !stop) judge();  // the whole (blocked-off) component is the disc
  if (!best) return std::nullopt;
  best->unbounded = unbounded;
  best->angle = best->sphere.radius > 0.0 ? best->rho / best->sphere.radius : 0.0;
  if (!want_faces || (*want_faces)(*best)) best->faces = disc_faces(seed, best->rho, blocked);
  return best;
}

/// The faces of the disc of radius rho: every corner reached and the mean corner distance
/// within rho; the edge-connected part touching the seed; notches (a face outside with two
/// neighbours inside) filled in synchronous passes, so the result does not depend on the
/// order of the faces.
std::vector<int> CapGrower::disc_faces(int seed, double rho, const std::vector<char>* blocked) {
  const auto is_blocked = [&](int w) { return blocked && (*blocked)[static_cast<std::size_t>(w)] != 0; };
  std::vector<int> cand;
  for (int v : touched_)
    for (int f : m_.vertex_faces[static_cast<std::size_t>(v)]) {
      if (in_[static_cast<std::size_t>(f)]) continue;
      const auto& t = m_.tri[static_cast<std::size_t>(f)];
      double sum = 0.0;
      bool reached = true;
      for (int w : t) {
        const double dw = state_[static_cast<std::size_t>(w)].dist;
        reached = reached && !is_blocked(w) && dw < INF;
        sum += dw;
      }
      if (reached && sum / 3.0 <= rho) in_[static_cast<std::size_t>(f)] = 1, cand.push_back(f);
    }
  std::vector<int> stack, faces;
  for (int f : m_.vertex_faces[static_cast<std::size_t>(seed)])
    if (in_[static_cast<std::size_t>(f)] && !keep_[static_cast<std::size_t>(f)])
      keep_[static_cast<std::size_t>(f)] = 1, stack.push_back(f);
  while (!stack.empty()) {
    const int f = stack.back();
    stack.pop_back();
    faces.push_back(f);
    for (int g : m_.face_nbr[static_cast<std::size_t>(f)])
      if (g >= 0 && in_[static_cast<std::size_t>(g)] && !keep_[static_cast<std::size_t>(g)])
        keep_[static_cast<std::size_t>(g)] = 1, stack.push_back(g);
  }
  for (int pass = 0; pass < 3; ++pass) {
    std::vector<int> add;
    for (int f : faces)
      for (int g : m_.face_nbr[static_cast<std::size_t>(f)]) {
        if (g < 0 || keep_[static_cast<std::size_t>(g)]) continue;
        const auto& t = m_.tri[static_cast<std::size_t>(g)];
        if (std::any_of(t.begin(), t.end(), is_blocked)) continue;
        int inside = 0;
        for (int k : m_.face_nbr[static_cast<std::size_t>(g)]) inside += (k >= 0 && keep_[static_cast<std::size_t>(k)]) ? 1 : 0;
        if (inside >= 2) add.push_back(g);
      }
    if (add.empty()) break;
    for (int g : add)
      if (!keep_[static_cast<std::size_t>(g)]) keep_[static_cast<std::size_t>(g)] = 1, faces.push_back(g);
  }
  for (int f : cand) in_[static_cast<std::size_t>(f)] = 0;
  for (int f : faces) keep_[static_cast<std::size_t>(f)] = 0;
  std::sort(faces.begin(), faces.end());
  return faces;
}

}  // namespace shellcontract::detail
