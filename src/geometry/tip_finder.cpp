// The tip finder (RegionMethod::Tips; docs/math/tip-finder.md, lab/regions/tips.md): the ends of
// protrusions as a person would circle them (an arm's end, an ear, a fingertip).
//   1. protrusion p(v): the mean edge-graph distance from v to PROTRUSION_SOURCES sources placed
//      by farthest-point sampling (the average geodesic distance of Zhang et al., sampled);
//   2. tips: strict maxima of p within a geodesic radius of TIP_RADIUS;
//   3. a disc per tip: faces by their corners' mean distance from the tip, until the disc has
//      wrapped round its end (mean unit normal short) or met a concave crease;
//   4. ends: tips by decreasing p; a tip inside a kept disc joins it, a disc wider than
//      max_area_fraction is dropped;
//   5. each end grown again from the centre of its top (the tip can sit off-centre on a flat end);
//   6. every face to the nearest disc, the outlines smoothed, one piece each, the filters.
// Every length is relative to size = sqrt(total area), and every tie is broken by positions or
// by an order that is itself position-based, so rotation, scaling and vertex order do not change
// the result.
#include "geometry/tip_finder.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "core/cancellation.hpp"
#include "core/constants.hpp"
#include "geometry/cap_internal.hpp"
#include "geometry/curvature.hpp"
#include "geometry/edge_dijkstra.hpp"

namespace shellcontract::detail {
namespace {

/// Sources of the protrusion field: enough that p is smooth on the paper's meshes, few enough
/// that 24 Dijkstra passes stay cheap (lab/regions/tips.md).
constexpr int PROTRUSION_SOURCES = 24;
/// A tip is the strict maximum of p within this geodesic radius (times size): one tip per
/// fingertip, not one per bump of a scan.
constexpr double TIP_RADIUS = 0.06;
/// A disc is judged only from this many faces on (the first faces around a tip say nothing).
constexpr std::size_t MIN_DISC_FACES = 5;
/// The disc stops when the length of its area-weighted mean unit normal falls to this: a
/// spherical cap of half-angle theta has (1 + cos theta) / 2, a hemisphere 1/2, so 0.4 is a
/// disc that has passed round its end and runs down the limb (docs/math/tip-finder.md).
constexpr double WRAPPED = 0.4;
/// Heat scales (times size) of the smoothed mean curvature: the concave test, and the
/// reference curvature (as the cap finder's largest scale).
constexpr double CONCAVE_SCALE = 0.02, REFERENCE_SCALE = 0.1;
/// A face is concave when its smoothed H is below -this * h_ref (a flat spot, H = 0 up to
/// rounding, is not).
constexpr double CONCAVE_EPS = 1e-9;
/// The top of an end: the disc's vertices connected to the tip with p >= this * p(tip).
constexpr double TOP_LEVEL = 0.95;
/// Passes of the majority rule that smooths the outlines (as the cap finder's shape_cap).
constexpr int SMOOTHING_PASSES = 3;

/// Lexicographic order of positions (x, y, z), the tie-break wherever two vertices compare
/// equal, so that the vertex order never decides; the index only for equal positions.
bool before(const Positions& x, int a, int b) {
  const auto pa = std::make_tuple(x(a, 0), x(a, 1), x(a, 2)),
             pb = std::make_tuple(x(b, 0), x(b, 1), x(b, 2));
  return pa != pb ? pa < pb : a < b;
}

/// Step 1. Vertices that no source reaches (another connected component) average over the
/// sources that do; farthest-point sampling places a source in every component it can.
std::vector<double> protrusion(const MeshArrays& m, const Positions& x, EdgeDijkstra& dijkstra) {
  Vec3 c = Vec3::Zero();
  for (std::size_t v = 0; v < m.nv; ++v)
    c += m.vertex_area[v] * Vec3(x.row(static_cast<Eigen::Index>(v)));
  c /= m.total_area;
  const auto farthest = [&](const std::vector<double>& key) {
    int best = 0;
    for (int v = 1; v < static_cast<int>(m.nv); ++v) {
      const double kv = key[static_cast<std::size_t>(v)], kb = key[static_cast<std::size_t>(best)];
      if (kv > kb || (kv == kb && before(x, v, best))) best = v;
    }
    return best;
  };
  std::vector<double> from_centroid(m.nv);
  for (std::size_t v = 0; v < m.nv; ++v)
    from_centroid[v] = (Vec3(x.row(static_cast<Eigen::Index>(v))) - c).norm();
  std::vector<double> sum(m.nv, 0.0), nearest(m.nv, EdgeDijkstra::NONE);
  std::vector<int> count(m.nv, 0);
  int source = farthest(from_centroid);
  for (int k = 0; k < PROTRUSION_SOURCES; ++k) {
    for (int v : dijkstra.run({source})) {
      const auto i = static_cast<std::size_t>(v);
      sum[i] += dijkstra.dist(v), ++count[i];
      nearest[i] = std::min(nearest[i], dijkstra.dist(v));
    }
    source = farthest(nearest);
  }
  std::vector<double> p(m.nv, 0.0);
  for (std::size_t v = 0; v < m.nv; ++v) p[v] = count[v] > 0 ? sum[v] / count[v] : 0.0;
  return p;
}

/// A grown disc: its centre vertex and its faces with their corners' mean distance from it.
struct Disc {
  int centre = -1;
  std::vector<std::pair<int, double>> faces;
};

/// Grows discs (step 3) from a centre vertex.
class DiscGrower {
 public:
  DiscGrower(const MeshArrays& m, const Positions& x, const std::vector<char>& concave,
             const RegionOptions& o)
      : m_(m), x_(x), concave_(concave), o_(o), dijkstra_(m) {}

  /// The disc around `centre`; nothing when it grows past max_area_fraction before it stops.
  std::optional<Disc> grow(int centre) {
    const double max_area = o_.max_area_fraction * m_.total_area;
    // A flat disc of the largest allowed area first; doubled while the faces within reach run
    // out before the disc stops (a thin limb holds less area within a radius than a plane).
    double reach = 2.0 * std::sqrt(max_area / PI);
    if (!(reach > 0.0)) reach = m_.size;
    for (;;) {
      const std::vector<int>& reached = dijkstra_.run({centre}, reach);
      std::vector<std::pair<int, double>> order;
      for (int v : reached)
        for (int f : m_.vertex_faces[static_cast<std::size_t>(v)]) {
          const auto& t = m_.tri[static_cast<std::size_t>(f)];
          // Each face once, listed from its corner of smallest index (only which corner lists
          // it; the order below is by distance and position).
          double d = 0.0;
          bool all = true, first = true;
          for (int c : t) {
            const double dc = dijkstra_.dist(c);
            all = all && dc != EdgeDijkstra::NONE;
            if (dc != EdgeDijkstra::NONE && c < v) first = false;
            d += dc;
          }
          if (all && first) order.emplace_back(f, d / 3.0);
        }
      // By distance; equal distances (a symmetric mesh) by the centroids' positions.
      std::sort(order.begin(), order.end(), [&](const auto& a, const auto& b) {
        if (a.second != b.second) return a.second < b.second;
        const Vec3 ca = face_centroid(m_, x_, a.first), cb = face_centroid(m_, x_, b.first);
        return std::make_tuple(ca.x(), ca.y(), ca.z()) < std::make_tuple(cb.x(), cb.y(), cb.z());
      });
      double area = 0.0, concave_area = 0.0;
      Vec3 normal = Vec3::Zero();  // sum of area * unit normal
      for (std::size_t i = 0; i < order.size(); ++i) {
        const int f = order[i].first;
        const auto& t = m_.tri[static_cast<std::size_t>(f)];
        const Vec3 p0(x_.row(t[0])), p1(x_.row(t[1])), p2(x_.row(t[2]));
        const double a = m_.face_area[static_cast<std::size_t>(f)];
        area += a;
        normal += 0.5 * (p1 - p0).cross(p2 - p0);
        if (concave_[static_cast<std::size_t>(f)]) concave_area += a;
        if (area > max_area) return std::nullopt;
        const bool stop =
            normal.norm() <= WRAPPED * area || concave_area > o_.max_concave_fraction * area;
        if (i >= MIN_DISC_FACES && stop) {
          order.resize(i);  // the faces before the one that wrapped or met the crease
          return Disc{centre, std::move(order)};
        }
      }
      if (!dijkstra_.cut_off()) return Disc{centre, std::move(order)};  // an open mesh, all taken
      reach *= 2.0;
    }
  }

 private:
  const MeshArrays& m_;
  const Positions& x_;
  const std::vector<char>& concave_;
  const RegionOptions& o_;
  EdgeDijkstra dijkstra_;
};

std::vector<int> corners_of(const MeshArrays& m, const Disc& d) {
  std::vector<int> v;
  for (const auto& fd : d.faces)
    for (int c : m.tri[static_cast<std::size_t>(fd.first)]) v.push_back(c);
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

/// Step 5: the vertex at the middle of an end's top (see TOP_LEVEL).
int top_centre(const MeshArrays& m, const Positions& x, const std::vector<double>& p, const Disc& d,
               int tip) {
  const std::vector<int> corners = corners_of(m, d);
  std::vector<char> in(m.nv, 0), top(m.nv, 0);
  for (int v : corners) in[static_cast<std::size_t>(v)] = 1;
  const double level = TOP_LEVEL * p[static_cast<std::size_t>(tip)];
  std::vector<int> stack{tip}, members;
  top[static_cast<std::size_t>(tip)] = 1;
  while (!stack.empty()) {
    const auto v = static_cast<std::size_t>(stack.back());
    stack.pop_back();
    members.push_back(static_cast<int>(v));
    for (int k = m.nbr_start[v]; k < m.nbr_start[v + 1]; ++k) {
      const auto w = static_cast<std::size_t>(m.nbr_to[static_cast<std::size_t>(k)]);
      if (in[w] && !top[w] && p[w] >= level) top[w] = 1, stack.push_back(static_cast<int>(w));
    }
  }
  Vec3 c = Vec3::Zero();
  double w = 0.0;
  for (int v : members) {
    c += m.vertex_area[static_cast<std::size_t>(v)] * Vec3(x.row(v));
    w += m.vertex_area[static_cast<std::size_t>(v)];
  }
  if (!(w > 0.0)) return tip;
  c /= w;
  int best = tip;
  double best_d = (Vec3(x.row(tip)) - c).norm();
  for (int v : members) {
    const double dv = (Vec3(x.row(v)) - c).norm();
    if (dv < best_d || (dv == best_d && before(x, v, best))) best = v, best_d = dv;
  }
  return best;
}

}  // namespace

std::vector<int> select_tip_regions(const Mesh& mesh, const Positions& x, const RegionOptions& options,
                                    RegionReport* report, CurvatureField* curvature) {
  cancellation_point();
  FinderStart start = start_finder(mesh, x);
  if (start.empty()) return no_regions(start, report, curvature);
  cancellation_point();
  CurvatureField& c = start.curvature;
  const MeshArrays& m = start.arrays;
  RegionReport r;
  r.total_area = m.total_area;
  const std::vector<Eigen::VectorXd> u =
      smoothed_curvature(m, x, c, {CONCAVE_SCALE, REFERENCE_SCALE});
  const double h_ref = reference_curvature(m, x, u.back());
  r.reference_mean_curvature = h_ref;
  std::vector<char> concave(m.nf, 0);
  for (std::size_t f = 0; f < m.nf; ++f) {
    double h = 0.0;
    for (int v : m.tri[f]) h += u.front()(v) / 3.0;
    concave[f] = h < -CONCAVE_EPS * h_ref ? 1 : 0;
  }

  // Steps 1 and 2.
  cancellation_point();
  EdgeDijkstra dijkstra(m);
  const std::vector<double> p = protrusion(m, x, dijkstra);
  std::vector<int> tips;
  for (std::size_t v = 0; v < m.nv; ++v) {
    if (v % 4096 == 0) cancellation_point();
    bool peak = true;
    for (int k = m.nbr_start[v]; k < m.nbr_start[v + 1] && peak; ++k)
      peak = p[v] > p[static_cast<std::size_t>(m.nbr_to[static_cast<std::size_t>(k)])];
    if (!peak) continue;
    for (int w : dijkstra.run({static_cast<int>(v)}, TIP_RADIUS * m.size))
      peak = peak && (w == static_cast<int>(v) || p[v] > p[static_cast<std::size_t>(w)]);
    if (peak) tips.push_back(static_cast<int>(v));
  }
  std::sort(tips.begin(), tips.end(), [&](int a, int b) {
    const double pa = p[static_cast<std::size_t>(a)], pb = p[static_cast<std::size_t>(b)];
    return pa != pb ? pa > pb : before(x, a, b);
  });
  r.seed_vertices = tips.size();

  // Steps 3 and 4.
  DiscGrower grower(m, x, concave, options);
  std::vector<char> covered(m.nv, 0);
  std::vector<std::pair<int, Disc>> ends;  // (tip, disc)
  for (int tip : tips) {
    cancellation_point();
    if (covered[static_cast<std::size_t>(tip)]) continue;  // joins the end whose disc holds it
    std::optional<Disc> d = grower.grow(tip);
    if (!d) {
      ++r.dropped_large;
      continue;
    }
    for (int v : corners_of(m, *d)) covered[static_cast<std::size_t>(v)] = 1;
    ends.emplace_back(tip, std::move(*d));
  }
  r.candidates = ends.size();
  // Step 5 (a disc that no longer stops within max_area_fraction from the new centre keeps
  // the one from its tip).
  for (auto& [tip, d] : ends) {
    cancellation_point();
    const int centre = top_centre(m, x, p, d, tip);
    if (centre == tip) continue;
    if (std::optional<Disc> again = grower.grow(centre)) d = std::move(*again);
  }

  // Step 6: nearest disc (ties: the earlier end, in the tips' order), then the outlines.
  std::vector<int> owner(m.nf, -1);
  std::vector<double> best(m.nf, EdgeDijkstra::NONE);
  for (std::size_t e = 0; e < ends.size(); ++e)
    for (const auto& [f, d] : ends[e].second.faces)
      if (d < best[static_cast<std::size_t>(f)]) {
        best[static_cast<std::size_t>(f)] = d;
        owner[static_cast<std::size_t>(f)] = static_cast<int>(e);
      }
  // Majority rule, synchronous (the face order cannot matter): a face joins the region that holds
  // at least two of its three edge neighbours; a face with at most one neighbour in its own
  // region leaves it.
  for (int pass = 0; pass < SMOOTHING_PASSES; ++pass) {
    std::vector<int> next = owner;
    for (std::size_t f = 0; f < m.nf; ++f) {
      const auto& nb = m.face_nbr[f];
      const auto label = [&](int k) {
        return nb[static_cast<std::size_t>(k)] >= 0
                   ? owner[static_cast<std::size_t>(nb[static_cast<std::size_t>(k)])]
                   : -1;
      };
      const int a = label(0), b = label(1), cc = label(2);
      const int major = (a >= 0 && (a == b || a == cc)) ? a : (b >= 0 && b == cc) ? b : -1;
      if (major >= 0) {
        next[f] = major;
      } else if (owner[f] >= 0 && (a == owner[f]) + (b == owner[f]) + (cc == owner[f]) <= 1) {
        next[f] = -1;
      }
    }
    if (next == owner) break;
    owner = std::move(next);
  }
  std::vector<std::pair<Cap, RegionSummary>> kept;
  for (std::size_t e = 0; e < ends.size(); ++e) {
    cancellation_point();
    std::vector<char> flag(m.nf, 0);
    for (std::size_t f = 0; f < m.nf; ++f) flag[f] = owner[f] == static_cast<int>(e) ? 1 : 0;
    std::vector<int> faces = largest_piece(m, flag);
    if (faces.empty()) {
      ++r.dropped_small;
      continue;
    }
    Cap cap = region_cap(m, x, ends[e].second.centre, std::move(faces));
    const RegionSummary s = summarise(mesh, x, m, cap, h_ref);
    if (std::size_t* dropped = failed_filter(s, options, r))
      ++*dropped;
    else
      kept.emplace_back(std::move(cap), s);
  }
  std::vector<int> region = number_regions(kept, m.nf, r, false);
  if (report) *report = std::move(r);
  if (curvature) *curvature = std::move(c);
  return region;
}

}  // namespace shellcontract::detail
