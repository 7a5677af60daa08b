// Growing a geodesic disc from a seed while a sphere fits it (cap_grower.hpp).
#include "geometry/cap_grower.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <utility>

#include "geometry/sphere_moments.hpp"

namespace shellcontract::detail {
namespace {

/// Growth step of the discs, in units of the mesh's size (finer than the smallest part looked for).
constexpr double GROWTH_STEP = 0.004;
/// Vertices a disc needs before its fit is judged (fewer cannot tell a cap from noise), and
/// after which a disc that never fitted is given up.
constexpr std::size_t MIN_FIT_POINTS = 10, GIVE_UP_POINTS = 40;
constexpr double INF = std::numeric_limits<double>::infinity();

/// Sorts non-negative ints in increasing order: the same result as std::sort (ints have no
/// ties to order), by 11-bit counting passes from the lowest digit when there are enough of them
/// for the passes to pay (a disc of a large mesh lists tens of thousands of vertices and faces;
/// lab/regions/speed.md).
void sort_indices(std::vector<int>& v) {
  constexpr std::size_t SMALL = 256;
  constexpr int BITS = 11;
  constexpr std::size_t BUCKETS = std::size_t{1} << BITS;
  if (v.size() < SMALL) {
    std::sort(v.begin(), v.end());
    return;
  }
  unsigned top = 0;
  for (int x : v) top |= static_cast<unsigned>(x);
  std::vector<int> tmp(v.size());
  std::vector<std::size_t> count(BUCKETS);
  for (int shift = 0; shift < 32 && (top >> shift) != 0; shift += BITS) {
    std::fill(count.begin(), count.end(), 0);
    for (int x : v) ++count[(static_cast<unsigned>(x) >> shift) & (BUCKETS - 1)];
    std::size_t sum = 0;
    for (std::size_t& c : count) sum += std::exchange(c, sum);
    for (int x : v) tmp[count[(static_cast<unsigned>(x) >> shift) & (BUCKETS - 1)]++] = x;
    v.swap(tmp);
  }
}

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

namespace {

/// The bits of a 21-bit integer spread to every third bit (Morton order).
std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffffULL;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

}  // namespace

GrowthGraph::GrowthGraph(const MeshArrays& m, const std::vector<GrowthVertex>& vertices) {
  const std::size_t n = vertices.size();
  // Morton order of the positions on a 2^21 grid over the bounding box (ties: mesh index).
  Vec3 lo = Vec3::Constant(INF), hi = Vec3::Constant(-INF);
  for (const GrowthVertex& v : vertices) lo = lo.cwiseMin(v.point), hi = hi.cwiseMax(v.point);
  const double extent = n > 0 ? (hi - lo).maxCoeff() : 0.0;
  // A point cloud of zero extent (or a non-finite one) keeps the mesh's order.
  const double cells = std::isfinite(extent) && extent > 0.0 ? 2097151.0 / extent : 0.0;
  std::vector<std::pair<std::uint64_t, int>> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const double q = std::clamp((vertices[i].point(a) - lo(a)) * cells, 0.0, 2097151.0);
      code |= spread_bits(std::isfinite(q) ? static_cast<std::uint64_t>(q) : 0) << a;
    }
    key[i] = {code, static_cast<int>(i)};
  }
  std::sort(key.begin(), key.end());
  slot_.resize(n);
  id_.resize(n);
  vertex_.resize(n);
  for (std::size_t s = 0; s < n; ++s) {
    id_[s] = key[s].second;
    slot_[static_cast<std::size_t>(key[s].second)] = static_cast<int>(s);
    vertex_[s] = vertices[static_cast<std::size_t>(key[s].second)];
  }
  // Neighbours and faces of each slot, in the mesh's order for that vertex.
  nbr_start_.assign(n + 1, 0);
  face_start_.assign(n + 1, 0);
  for (std::size_t s = 0; s < n; ++s) {
    const auto v = static_cast<std::size_t>(id_[s]);
    nbr_start_[s + 1] = nbr_start_[s] + (m.nbr_start[v + 1] - m.nbr_start[v]);
    face_start_[s + 1] = face_start_[s] + static_cast<int>(m.vertex_faces[v].size());
  }
  nbr_.resize(static_cast<std::size_t>(nbr_start_[n]));
  face_.resize(static_cast<std::size_t>(face_start_[n]));
  for (std::size_t s = 0; s < n; ++s) {
    const auto v = static_cast<std::size_t>(id_[s]);
    auto out = nbr_.begin() + nbr_start_[s];
    for (int k = m.nbr_start[v]; k < m.nbr_start[v + 1]; ++k, ++out) {
      const int w = m.nbr_to[static_cast<std::size_t>(k)];
      *out = Neighbour{m.nbr_len[static_cast<std::size_t>(k)], slot_[static_cast<std::size_t>(w)], w};
    }
    std::copy(m.vertex_faces[v].begin(), m.vertex_faces[v].end(), face_.begin() + face_start_[s]);
  }
  // Faces in the order of their smallest corner slot (ties: mesh index), so a disc's faces
  // also lie close together.
  std::vector<std::pair<int, int>> fkey(m.nf);
  for (std::size_t f = 0; f < m.nf; ++f) {
    const auto& t = m.tri[f];
    fkey[f] = {std::min({slot(t[0]), slot(t[1]), slot(t[2])}), static_cast<int>(f)};
  }
  std::sort(fkey.begin(), fkey.end());
  face_id_.resize(m.nf);
  std::vector<int> face_slot(m.nf);
  for (std::size_t s = 0; s < m.nf; ++s) {
    face_id_[s] = fkey[s].second;
    face_slot[static_cast<std::size_t>(fkey[s].second)] = static_cast<int>(s);
  }
  face_rec_.resize(m.nf);
  for (std::size_t s = 0; s < m.nf; ++s) {
    const auto f = static_cast<std::size_t>(face_id_[s]);
    for (std::size_t k = 0; k < 3; ++k) {
      face_rec_[s].corner[k] = slot(m.tri[f][k]);
      const int g = m.face_nbr[f][k];
      face_rec_[s].nbr[k] = g >= 0 ? face_slot[static_cast<std::size_t>(g)] : -1;
    }
  }
  for (int& f : face_) f = face_slot[static_cast<std::size_t>(f)];
}

CapGrower::CapGrower(const MeshArrays& m, const GrowthGraph& graph, const CurvatureField& c, const RegionOptions& o)
    : m_(m), g_(graph), c_(c), o_(o), state_(graph.size(), State{INF, false}), in_(m.nf, 0), keep_(m.nf, 0) {}

CapGrower::CapGrower(const MeshArrays& m, const std::vector<GrowthVertex>& vertices, const CurvatureField& c,
                     const RegionOptions& o)
    : m_(m), own_(std::make_unique<const GrowthGraph>(m, vertices)), g_(*own_), c_(c), o_(o),
      state_(vertices.size(), State{INF, false}), in_(m.nf, 0), keep_(m.nf, 0) {}

void CapGrower::EntryHeap::push(const Entry& e) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &e.dist, sizeof bits);
  const Key key = (Key{bits} << 64) | (Key{static_cast<std::uint32_t>(e.id)} << 32) | Key{static_cast<std::uint32_t>(e.slot)};
  h_.push_back(key);
  std::size_t i = h_.size() - 1;
  while (i > 0) {
    const std::size_t parent = (i - 1) / 4;
    if (!(key < h_[parent])) break;
    h_[i] = h_[parent];
    i = parent;
  }
  h_[i] = key;
}

CapGrower::Entry CapGrower::EntryHeap::pop() {
  const Key top = h_.front();
  const Key last = h_.back();
  h_.pop_back();
  const std::size_t n = h_.size();
  std::size_t i = 0;
  for (;;) {
    const std::size_t first = 4 * i + 1;
    if (first >= n) break;
    const std::size_t end = std::min(first + 4, n);
    std::size_t least = first;
    Key least_key = h_[first];
    for (std::size_t c = first + 1; c < end; ++c) {
      const Key k = h_[c];
      const bool less = k < least_key;
      least = less ? c : least;
      least_key = less ? k : least_key;
    }
    if (!(least_key < last)) break;
    h_[i] = least_key;
    i = least;
  }
  if (n > 0) h_[i] = last;
  Entry e;
  const auto bits = static_cast<std::uint64_t>(top >> 64);
  std::memcpy(&e.dist, &bits, sizeof bits);
  e.id = static_cast<int>(static_cast<std::uint32_t>(top >> 32));
  e.slot = static_cast<int>(static_cast<std::uint32_t>(top));
  return e;
}

void CapGrower::reset() {
  for (int v : touched_) state_[static_cast<std::size_t>(v)] = State{INF, false};
  touched_.clear();
  heap_.clear();
}

std::optional<Cap> CapGrower::grow(int seed, const std::vector<char>* blocked,
                                   const std::function<bool(const Cap&)>* want_faces) {
  bool unbounded = false;
  std::optional<Cap> best = grow_disc(seed, blocked, nullptr, &unbounded);
  if (!best) return std::nullopt;
  best->unbounded = unbounded;
  best->angle = best->sphere.radius > 0.0 ? best->rho / best->sphere.radius : 0.0;
  if (!want_faces || (*want_faces)(*best))
    best->faces = disc_faces(g_.slot(seed), best->rho, blocked);
  return best;
}

std::optional<Cap> CapGrower::grow_within(
    int seed, const std::vector<char>* blocked,
    const std::function<double(const std::vector<int>&)>& region_area) {
  std::vector<Cap> passes;
  grow_disc(seed, blocked, &passes, nullptr);
  const double limit = o_.max_area_fraction;
  // The largest disc that fits whose region is within the bound. A disc's faces are listed from
  // the growth's final distances (as grow lists them), which can hold a face that the same
  // radius left out while the growth went on; so each is measured again here.
  for (auto it = passes.rbegin(); it != passes.rend(); ++it) {
    it->faces = disc_faces(g_.slot(seed), it->rho, blocked);
    if (!it->faces.empty() && region_area(it->faces) / m_.total_area <= limit) {
      it->angle = it->sphere.radius > 0.0 ? it->rho / it->sphere.radius : 0.0;
      return std::move(*it);
    }
  }
  return std::nullopt;
}

std::optional<Cap> CapGrower::grow_disc(int seed, const std::vector<char>* blocked,
                                        std::vector<Cap>* passes, bool* unbounded) {
  reset();
  const double h = GROWTH_STEP * m_.size;
  const int s = g_.slot(seed);
  SphereMoments moments(g_.vertex(s).point, m_.size);
  const Vec3 n_seed(c_.normal.row(seed));
  // A min-heap on (distance, mesh index): the order the growth adds its points in, whatever
  // the slots (no two entries tie: a vertex is pushed again only at a strictly smaller distance).
  state_[static_cast<std::size_t>(s)].dist = 0.0;
  touched_.push_back(s);
  heap_.push(Entry{0.0, seed, s});
  double boundary = h, area = 0.0, concave = 0.0, last = 0.0;
  std::size_t popped = 0;
  std::optional<Cap> best;
  bool stop = false, over = false;
  const GrowthVertex& seed_vertex = g_.vertex(s);
  const auto judge = [&]() {
    if (popped < MIN_FIT_POINTS) return;
    const std::optional<SphereFit> f = moments.fit();
    const bool pass = f && f->residual <= o_.fit_tolerance && n_seed.dot(seed_vertex.point - f->centre) > 0.0 &&
                      concave <= o_.max_concave_fraction * area;
    if (pass) {
      if (!best) best = Cap{};
      best->seed = seed;
      best->rho = last;
      best->sphere = *f;
      if (passes) passes->push_back(*best);
    } else if (best || popped >= GIVE_UP_POINTS) {
      stop = true;
    }
  };
  // grow_within's end: the faces of the disc so far exceed the bound. A disc face has a corner
  // popped (its mean corner distance is within the radius), so the faces' area is at most three
  // times the popped vertices' area: below a third of the bound they are not listed. The faces
  // listed now are a subset of those listed at any later point for the same or a larger radius
  // (distances only fall, the reached corners only grow), so every later disc exceeds it too.
  const double bound = o_.max_area_fraction * m_.total_area;
  const auto disc_exceeds = [&]() {
    if (3.0 * area <= bound) return false;
    double faces_area = 0.0;
    for (int f : disc_faces(s, last, blocked))
      faces_area += m_.face_area[static_cast<std::size_t>(f)];
    return faces_area > bound;
  };
  while (!heap_.empty() && !stop) {
    const Entry e = heap_.pop();
    State& sv = state_[static_cast<std::size_t>(e.slot)];
    if (sv.popped) continue;
    if (e.dist > boundary) {
      judge();
      if (stop) break;
      if (passes) {
        if (disc_exceeds()) {
          over = true;
          break;
        }
      } else if (area > o_.max_area_fraction * m_.total_area) {
        *unbounded = true;  // still fitting at the size limit: no part ends here
        break;
      }
      boundary = (std::floor(e.dist / h) + 1.0) * h;
    }
    sv.popped = true;
    ++popped;
    last = e.dist;
    const GrowthVertex& gv = g_.vertex(e.slot);
    moments.add(gv.point, gv.area);
    area += gv.area;
    concave += gv.concave_area;
    for (const GrowthGraph::Neighbour* nb = g_.nbr_begin(e.slot); nb != g_.nbr_end(e.slot); ++nb) {
      State& sw = state_[static_cast<std::size_t>(nb->slot)];
      const double dw = e.dist + nb->len;
      if (sw.popped || !(dw < sw.dist) || (blocked && (*blocked)[static_cast<std::size_t>(nb->id)])) continue;
      if (sw.dist == INF) {
        touched_.push_back(nb->slot);
        // Its record and neighbours are read when it is popped, a frontier's width of pops later:
        // fetched now, they are in the cache by then (the growth otherwise waits on memory).
        __builtin_prefetch(&g_.vertex(nb->slot));
        __builtin_prefetch(g_.nbr_begin(nb->slot));
        __builtin_prefetch(g_.nbr_begin(nb->slot) + 4);
      }
      sw.dist = dw;
      heap_.push(Entry{dw, nb->id, nb->slot});
    }
  }
  if (heap_.empty() && !stop && !over) judge();  // the whole (blocked-off) component is the disc
  return best;
}

/// The faces of the disc of radius rho: every corner reached and the mean corner distance
/// within rho; the edge-connected part touching the seed; notches (a face outside with two
/// neighbours inside) filled in synchronous passes, so the result does not depend on the
/// order of the faces.
std::vector<int> CapGrower::disc_faces(int seed_slot, double rho, const std::vector<char>* blocked) {
  // Faces are handled by their slots (GrowthGraph) and named by their mesh indices at the end.
  const auto is_blocked = [&](int slot) { return blocked && (*blocked)[static_cast<std::size_t>(g_.id(slot))] != 0; };
  std::vector<int> cand;
  // A face within rho has a corner within rho, and every vertex within rho was popped (the
  // growth pops in distance order past rho before it stops): only those corners are scanned.
  // In slot order, so that the faces are read in the order they lie in memory.
  std::vector<int> within;
  for (int v : touched_)
    if (const State& sv = state_[static_cast<std::size_t>(v)]; sv.popped && sv.dist <= rho) within.push_back(v);
  sort_indices(within);
  for (int v : within) {
    for (const int* fp = g_.faces_begin(v); fp != g_.faces_end(v); ++fp) {
      const int f = *fp;
      if (in_[static_cast<std::size_t>(f)]) continue;
      const auto& t = g_.face(f).corner;
      double sum = 0.0;
      bool reached = true;
      for (int w : t) {
        const double dw = state_[static_cast<std::size_t>(w)].dist;
        reached = reached && !is_blocked(w) && dw < INF;
        sum += dw;
      }
      if (reached && sum / 3.0 <= rho) in_[static_cast<std::size_t>(f)] = 1, cand.push_back(f);
    }
  }
  std::vector<int> stack, faces;
  for (const int* fp = g_.faces_begin(seed_slot); fp != g_.faces_end(seed_slot); ++fp)
    if (const int f = *fp; in_[static_cast<std::size_t>(f)] && !keep_[static_cast<std::size_t>(f)])
      keep_[static_cast<std::size_t>(f)] = 1, stack.push_back(f);
  while (!stack.empty()) {
    const int f = stack.back();
    stack.pop_back();
    faces.push_back(f);
    for (int g : g_.face(f).nbr)
      if (g >= 0 && in_[static_cast<std::size_t>(g)] && !keep_[static_cast<std::size_t>(g)])
        keep_[static_cast<std::size_t>(g)] = 1, stack.push_back(g);
  }
  for (int pass = 0; pass < 3; ++pass) {
    std::vector<int> add;
    for (int f : faces)
      for (int g : g_.face(f).nbr) {
        if (g < 0 || keep_[static_cast<std::size_t>(g)]) continue;
        const auto& t = g_.face(g).corner;
        if (std::any_of(t.begin(), t.end(), is_blocked)) continue;
        int inside = 0;
        for (int k : g_.face(g).nbr) inside += (k >= 0 && keep_[static_cast<std::size_t>(k)]) ? 1 : 0;
        if (inside >= 2) add.push_back(g);
      }
    if (add.empty()) break;
    for (int g : add)
      if (!keep_[static_cast<std::size_t>(g)]) keep_[static_cast<std::size_t>(g)] = 1, faces.push_back(g);
  }
  for (int f : cand) in_[static_cast<std::size_t>(f)] = 0;
  for (int& f : faces) keep_[static_cast<std::size_t>(f)] = 0, f = g_.face_id(f);
  sort_indices(faces);
  return faces;
}

}  // namespace shellcontract::detail
