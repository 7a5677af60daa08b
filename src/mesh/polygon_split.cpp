// Splitting a polygon into triangles for the simulation (polygon_split.hpp).
#include "mesh/polygon_split.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>

#include "mesh/soup_geometry.hpp"

namespace shellcontract::soup {
namespace {

Vec3 newell_normal(const Polygon& p, const std::vector<Point3>& pts) {
  const std::size_t n = p.size();
  Vec3 normal = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) normal += to_vec(pts[p[i]]).cross(to_vec(pts[p[(i + 1) % n]]));
  return normal;
}

/// Twice the triangle's vector area.
Vec3 area_vector(const Polygon& t, const std::vector<Point3>& pts) {
  const Vec3 a = to_vec(pts[t[0]]);
  return (to_vec(pts[t[1]]) - a).cross(to_vec(pts[t[2]]) - a);
}

/// Twice the vector area of triangle j (1 <= j < n - 1) of polygon `p`'s fan from corner k: that
/// of area_vector({p[k], p[k + j], p[k + j + 1]}) (indices mod n), without making the triangle,
/// so that trying a fan costs no allocation and stops at its first bad triangle (a polygon of
/// n corners tries up to n fans: making each whole had cost n^2 allocations).
Vec3 fan_area_vector(const Polygon& p, const std::vector<Point3>& pts, std::size_t k,
                     std::size_t j) {
  const std::size_t n = p.size();
  const Vec3 a = to_vec(pts[p[k]]);
  return (to_vec(pts[p[(k + j) % n]]) - a).cross(to_vec(pts[p[(k + j + 1) % n]]) - a);
}

/// Polygon `p`'s fan from corner k.
std::vector<Polygon> fan(const Polygon& p, std::size_t k) {
  const std::size_t n = p.size();
  std::vector<Polygon> tris;
  for (std::size_t j = 1; j + 1 < n; ++j) tris.push_back({p[k], p[(k + j) % n], p[(k + j + 1) % n]});
  return tris;
}

/// Below this, 2A counts as zero: ZERO_AREA_RELATIVE times the squared mean edge length of the
/// polygon (the threshold zero_area_faces applies with the mesh's mean edge).
double zero_area_threshold(const Polygon& p, const std::vector<Point3>& pts) {
  double sum = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) sum += (to_vec(pts[p[i]]) - to_vec(pts[p[(i + 1) % p.size()]])).norm();
  const double mean = sum / static_cast<double>(p.size());
  return ZERO_AREA_RELATIVE * mean * mean;
}

/// Rule 2: the quad's least folded diagonal.
std::vector<Polygon> least_folded_diagonal(const Polygon& p, const std::vector<Point3>& pts) {
  const double zero = zero_area_threshold(p, pts);
  double best = -std::numeric_limits<double>::infinity();
  std::size_t best_k = 0;
  for (std::size_t k = 0; k < 2; ++k) {
    const std::vector<Polygon> t = fan(p, k);
    const Vec3 a = area_vector(t[0], pts), b = area_vector(t[1], pts);
    // A zero-area triangle ranks below every folded pair (cosines lie in [-1, 1]).
    const double score = (a.norm() < zero || b.norm() < zero) ? -2.0 : a.normalized().dot(b.normalized());
    if (score > best) {
      best = score;
      best_k = k;
    }
  }
  return fan(p, best_k);
}

/// Rule 3: ear clipping in the plane of `normal`; empty when no ear is left to cut.
std::vector<Polygon> ear_clip(const Polygon& p, const std::vector<Point3>& pts, const Vec3& normal) {
  const Vec3 w = normal.normalized();
  const Vec3 u = (std::abs(w.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(w).normalized();
  const Vec3 v = w.cross(u);  // (u, v, w) right-handed: the polygon winds counter-clockwise in (u, v)
  struct P2 {
    double x, y;
  };
  std::vector<P2> q;
  for (const std::size_t i : p) q.push_back({to_vec(pts[i]).dot(u), to_vec(pts[i]).dot(v)});
  const auto cross = [&q](std::size_t a, std::size_t b, std::size_t c) {
    return (q[b].x - q[a].x) * (q[c].y - q[a].y) - (q[b].y - q[a].y) * (q[c].x - q[a].x);
  };
  std::vector<std::size_t> left(p.size());
  for (std::size_t i = 0; i < left.size(); ++i) left[i] = i;
  std::vector<Polygon> tris;
  // Walk round the polygon, cutting each ear found; after a cut the walk goes on at the ear's
  // previous corner (whose angle changed), and a full round without a cut gives up.
  std::size_t i = 0, tried = 0;
  while (left.size() > 3) {
    const std::size_t m = left.size();
    if (tried == m) return {};
    i %= m;
    const std::size_t a = left[(i + m - 1) % m], b = left[i], c = left[(i + 1) % m];
    bool ear = cross(a, b, c) > 0.0;  // a reflex or flat corner is no ear
    for (std::size_t j = 0; j < m && ear; ++j) {
      const std::size_t o = left[j];
      if (o == a || o == b || o == c) continue;
      ear = cross(a, b, o) < 0.0 || cross(b, c, o) < 0.0 || cross(c, a, o) < 0.0;  // outside, not on it
    }
    if (!ear) {
      ++i;
      ++tried;
      continue;
    }
    tris.push_back({p[a], p[b], p[c]});
    left.erase(left.begin() + static_cast<std::ptrdiff_t>(i));
    i = (i + m - 2) % (m - 1);
    tried = 0;
  }
  if (!(cross(left[0], left[1], left[2]) > 0.0)) return {};
  tris.push_back({p[left[0]], p[left[1]], p[left[2]]});
  return tris;
}

/// Rule 4: the fan that agrees best with `normal` and has no zero-area triangle; empty if none.
std::vector<Polygon> best_fan(const Polygon& p, const std::vector<Point3>& pts, const Vec3& normal) {
  const double zero = zero_area_threshold(p, pts);
  const Vec3 w = normal.normalized();
  double best = -std::numeric_limits<double>::infinity();
  std::size_t chosen = p.size();  // none
  for (std::size_t k = 0; k < p.size(); ++k) {
    // `worst` only falls (a zero-area triangle makes it -infinity for good): once it is no
    // better than the best fan's, this fan cannot be chosen.
    double worst = 1.0;
    for (std::size_t j = 1; j + 1 < p.size() && worst > best; ++j) {
      const Vec3 a = fan_area_vector(p, pts, k, j);
      worst = a.norm() < zero ? -std::numeric_limits<double>::infinity() : std::min(worst, a.normalized().dot(w));
    }
    if (worst > best) {
      best = worst;
      chosen = k;
    }
  }
  return chosen < p.size() ? fan(p, chosen) : std::vector<Polygon>{};
}

}  // namespace

std::vector<Polygon> split_polygon(const Polygon& p, const std::vector<Point3>& pts, SplitRule* rule) {
  const auto by = [rule](SplitRule r, std::vector<Polygon> tris) {
    if (rule != nullptr && !tris.empty()) *rule = r;
    return tris;
  };
  const Vec3 normal = newell_normal(p, pts);
  // A flat (zero-normal) polygon has no good corner; corner 0 gives zero-area triangles,
  // which are then reported like any other zero-area face.
  if (normal.squaredNorm() == 0.0) return by(SplitRule::flat, fan(p, 0));
  for (std::size_t k = 0; k < p.size(); ++k) {
    bool ok = true;
    for (std::size_t j = 1; j + 1 < p.size() && ok; ++j)
      ok = fan_area_vector(p, pts, k, j).dot(normal) > 0.0;
    if (ok) return by(SplitRule::fan, fan(p, k));
  }
  if (p.size() == 4) return by(SplitRule::diagonal, least_folded_diagonal(p, pts));
  std::vector<Polygon> tris = ear_clip(p, pts, normal);
  if (!tris.empty()) return by(SplitRule::ear_clip, std::move(tris));
  return by(SplitRule::best_fan, best_fan(p, pts, normal));
}

std::vector<Polygon> split_like(const Polygon& p, const Polygon& like,
                                const std::vector<Polygon>& triangles) {
  const std::size_t n = p.size();
  if (like.size() != n || n < 3 || triangles.size() != n - 2) return {};
  const auto start = std::find(like.begin(), like.end(), p[0]);
  if (start == like.end()) return {};
  const std::size_t s = static_cast<std::size_t>(start - like.begin());
  // The same cycle, forwards or backwards from p's first corner.
  bool forwards = true, backwards = true;
  for (std::size_t k = 0; k < n; ++k) {
    forwards = forwards && like[(s + k) % n] == p[k];
    backwards = backwards && like[(s + n - k) % n] == p[k];
  }
  if (!forwards && !backwards) return {};
  // Corner positions in p (sorted by vertex: a polygon may have thousands of corners): a
  // triangle a, b, c is wound like p when b comes before c walking round p from a.
  std::vector<std::pair<std::size_t, std::size_t>> by_vertex;
  for (std::size_t k = 0; k < n; ++k) by_vertex.emplace_back(p[k], k);
  std::sort(by_vertex.begin(), by_vertex.end());
  const auto position = [&](std::size_t v) {
    const auto at =
        std::lower_bound(by_vertex.begin(), by_vertex.end(), std::make_pair(v, std::size_t{0}));
    return at != by_vertex.end() && at->first == v ? at->second : n;
  };
  std::vector<Polygon> out;
  for (const Polygon& t : triangles) {
    if (t.size() != 3) return {};
    const std::size_t a = position(t[0]), b = position(t[1]), c = position(t[2]);
    if (a == n || b == n || c == n || a == b || b == c || a == c) return {};
    const bool wound = (b + n - a) % n < (c + n - a) % n;
    out.push_back(wound ? Polygon{t[0], t[1], t[2]} : Polygon{t[0], t[2], t[1]});
  }
  return out;
}

}  // namespace shellcontract::soup
