#include "sim/region_dimple.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <utility>

#include "core/constants.hpp"

namespace shellcontract {

namespace {

/// A unit vector normal to n (n unit), from the coordinate axis least aligned with it.
Vec3 any_normal(const Vec3& n) {
  Eigen::Index axis = 0;
  n.cwiseAbs().minCoeff(&axis);
  return n.cross(Vec3::Unit(axis)).normalized();
}

/// For each face of `order` and each of its edges (k: corner k to corner k + 1), the index in
/// `order` of the face across it, or -1 when that face is not in the region.
std::vector<int> faces_across(const Faces& faces, const std::vector<int>& order) {
  std::map<std::pair<int, int>, int> by_edge;
  for (std::size_t i = 0; i < order.size(); ++i)
    for (int k = 0; k < 3; ++k)
      by_edge[{faces(order[i], k), faces(order[i], (k + 1) % 3)}] = static_cast<int>(i);
  std::vector<int> across(3 * order.size(), -1);
  for (std::size_t i = 0; i < order.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const auto twin = by_edge.find({faces(order[i], (k + 1) % 3), faces(order[i], k)});
      if (twin != by_edge.end()) across[3 * i + static_cast<std::size_t>(k)] = twin->second;
    }
  return across;
}

/// The cut of a region along `axis`: the plane normal to it through the highest rim vertex,
/// lowered by CUT_TOLERANCE mean edge lengths. Returns its height along the axis and sets
/// `volume` to the cap volume (cap_volume: closed by the fan from its rim's centroid) of the
/// faces wholly above it.
double cut_of(const Positions& rest, const Faces& faces, const std::vector<int>& order,
              const std::vector<int>& across, const std::vector<int>& rim_vertices,
              const Vec3& axis, double edge, double& volume) {
  double top = -std::numeric_limits<double>::infinity();
  for (int v : rim_vertices) top = std::max(top, Vec3(rest.row(v)).dot(axis));
  const double h = top - CUT_TOLERANCE * edge;
  std::vector<char> kept(order.size(), 0);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const int f = order[i];
    kept[i] = std::min({Vec3(rest.row(faces(f, 0))).dot(axis), Vec3(rest.row(faces(f, 1))).dot(axis),
                        Vec3(rest.row(faces(f, 2))).dot(axis)}) >= h;
  }
  // Relative to a corner of the region, so the determinants stay of the region's size.
  const Vec3 origin = rest.row(faces(order.front(), 0));
  auto p = [&](int v) { return Vec3(Vec3(rest.row(v)) - origin); };
  double determinants = 0.0;
  Vec3 edge_cross = Vec3::Zero(), rim_sum = Vec3::Zero();
  double rim_weight = 0.0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (!kept[i]) continue;
    const int f = order[i];
    determinants += p(faces(f, 0)).dot(p(faces(f, 1)).cross(p(faces(f, 2))));
    for (int k = 0; k < 3; ++k) {
      const int o = across[3 * i + static_cast<std::size_t>(k)];
      if (o >= 0 && kept[static_cast<std::size_t>(o)]) continue;
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      edge_cross += p(a).cross(p(b));
      // Each rim vertex of a simple rim ends two boundary edges: the mean over edge ends is
      // the rim vertices' centroid.
      rim_sum += p(a) + p(b);
      rim_weight += 2.0;
    }
  }
  const Vec3 centre = rim_weight > 0.0 ? Vec3(rim_sum / rim_weight) : Vec3::Zero();
  volume = (determinants - centre.dot(edge_cross)) / 6.0;
  return h;
}

/// `items` sorted by `key` (ascending; ties keep their order, so the result is deterministic).
std::vector<int> sorted_by(const std::vector<int>& items, const std::vector<double>& key) {
  std::vector<std::size_t> rank(items.size());
  std::iota(rank.begin(), rank.end(), std::size_t{0});
  std::stable_sort(rank.begin(), rank.end(),
                   [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
  std::vector<int> out(items.size());
  for (std::size_t i = 0; i < rank.size(); ++i) out[i] = items[rank[i]];
  return out;
}

RegionDimple finish(RegionDimple& d, const Positions& rest, const Faces& faces) {
  d.prefix_rest_volume = prefix_cap_volumes(rest, faces, d.order);
  return std::move(d);
}

}  // namespace

RegionDimple make_region_dimple(const Positions& rest, const Faces& faces,
                                const std::vector<int>& region_faces) {
  RegionDimple d;
  d.whole = make_region_cap(faces, region_faces);
  d.whole.rest_volume = cap_volume(rest, d.whole);
  for (int f : region_faces)
    if (f >= 0 && f < faces.rows()) d.order.push_back(f);
  std::sort(d.order.begin(), d.order.end());
  d.order.erase(std::unique(d.order.begin(), d.order.end()), d.order.end());
  if (d.order.empty()) return d;

  auto at = [&](int v) { return Vec3(rest.row(v)); };
  Vec3 normal = Vec3::Zero();
  double edge = 0.0;
  for (int f : d.order) {
    normal += (at(faces(f, 1)) - at(faces(f, 0))).cross(at(faces(f, 2)) - at(faces(f, 0)));
    for (int k = 0; k < 3; ++k) edge += (at(faces(f, (k + 1) % 3)) - at(faces(f, k))).norm();
  }
  edge /= 3.0 * static_cast<double>(d.order.size());
  std::vector<int> rim_vertices;
  for (int r : d.whole.rim) rim_vertices.push_back(d.whole.vertices[static_cast<std::size_t>(r)]);
  Vec3 rim_centre = Vec3::Zero();
  for (int v : rim_vertices) rim_centre += at(v);
  if (!rim_vertices.empty()) rim_centre /= static_cast<double>(rim_vertices.size());
  // The apex: highest above the rim along the normal (a zero normal leaves the first vertex).
  int apex = d.whole.vertices.front();
  double height = (at(apex) - rim_centre).dot(normal);
  for (int v : d.whole.vertices) {
    const double h = (at(v) - rim_centre).dot(normal);
    if (h > height) apex = v, height = h;
  }
  std::vector<double> distance(d.order.size());
  for (std::size_t i = 0; i < d.order.size(); ++i) {
    const int f = d.order[i];
    const Vec3 centroid = (at(faces(f, 0)) + at(faces(f, 1)) + at(faces(f, 2))) / 3.0;
    distance[i] = (centroid - at(apex)).squaredNorm();
  }
  d.order = sorted_by(d.order, distance);
  d.limit = static_cast<int>(d.order.size());
  if (!(normal.norm() > 0.0) || rim_vertices.empty()) return finish(d, rest, faces);
  d.axis = normal.normalized();

  // The cut whose cap is largest, among the normal and directions tilted from it: the rim of a
  // region on a surface that is not a sphere is not a plane section, and the plane that leaves
  // the most of it above may lie aslant.
  // The azimuths start from the direction in which the rim rises along the normal (the
  // rim's first moment of height, in the plane normal to n0), so that they turn with the mesh
  // and a rotated mesh gets the rotated cut; a rim with no such direction (level, or rising
  // symmetrically) starts from any normal.
  const Vec3 n0 = d.axis;
  Vec3 rise = Vec3::Zero();
  for (int v : rim_vertices) {
    const Vec3 q = at(v) - rim_centre;
    rise += q.dot(n0) * (q - q.dot(n0) * n0);
  }
  const double rise_scale = edge * edge * static_cast<double>(rim_vertices.size());
  const Vec3 u = rise.norm() > 1e-9 * rise_scale ? Vec3(rise.normalized()) : any_normal(n0);
  const Vec3 w = n0.cross(u);
  const std::vector<int> across = faces_across(faces, d.order);
  double best = -std::numeric_limits<double>::infinity(), cut = 0.0;
  for (int tilt = 0; tilt <= 6; ++tilt)
    for (int az = 0; az < (tilt == 0 ? 1 : 12); ++az) {
      const double t = tilt * 10.0 * PI / 180.0, a = az * 2.0 * PI / 12.0;
      const Vec3 axis =
          (std::cos(t) * n0 + std::sin(t) * (std::cos(a) * u + std::sin(a) * w)).normalized();
      double volume = 0.0;
      const double h = cut_of(rest, faces, d.order, across, rim_vertices, axis, edge, volume);
      if (volume > best) best = volume, d.axis = axis, cut = h;
    }
  std::vector<double> lowest(d.order.size());
  int kept = 0;
  for (std::size_t i = 0; i < d.order.size(); ++i) {
    const int f = d.order[i];
    lowest[i] = -std::min({at(faces(f, 0)).dot(d.axis), at(faces(f, 1)).dot(d.axis),
                           at(faces(f, 2)).dot(d.axis)});
    if (-lowest[i] >= cut) ++kept;
  }
  // A rim within the tolerance of the cut is taken up by the crease ring: the dimple keeps the
  // whole region and grows from the apex as a ball. Otherwise it grows down from the top of
  // the cut's cap and stops at the cut.
  if (kept < static_cast<int>(d.order.size())) {
    d.order = sorted_by(d.order, lowest);
    d.limit = kept;
  } else {
    d.axis = n0;
  }
  return finish(d, rest, faces);
}


std::vector<double> prefix_cap_volumes(const Positions& x, const Faces& faces,
                                       const std::vector<int>& order) {
  std::vector<double> volumes;
  volumes.reserve(order.size());
  if (order.empty()) return volumes;
  // Relative to a corner of the region: the determinants stay of the region's size.
  const Vec3 origin = x.row(faces(order.front(), 0));
  auto p = [&](int v) { return Vec3(Vec3(x.row(v)) - origin); };
  double determinants = 0.0;
  Vec3 edge_cross = Vec3::Zero(), rim_sum = Vec3::Zero();
  int rim_count = 0;
  std::map<std::pair<int, int>, int> directed;  // boundary edges i -> j (a count: non-manifold)
  std::map<int, int> degree;                    // boundary edges at a vertex
  auto touch = [&](int v, int change) {
    int& n = degree[v];
    if (n == 0) rim_sum += p(v), ++rim_count;
    n += change;
    if (n == 0) rim_sum -= p(v), --rim_count;
  };
  for (int f : order) {
    const int a = faces(f, 0), b = faces(f, 1), c = faces(f, 2);
    determinants += p(a).dot(p(b).cross(p(c)));
    for (const auto& [i, j] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
      auto twin = directed.find({j, i});
      if (twin != directed.end() && twin->second > 0) {  // an inner edge now: out of the rim
        --twin->second;
        edge_cross -= p(j).cross(p(i));
        touch(i, -1), touch(j, -1);
      } else {
        ++directed[{i, j}];
        edge_cross += p(i).cross(p(j));
        touch(i, +1), touch(j, +1);
      }
    }
    const Vec3 centre = rim_count > 0 ? Vec3(rim_sum / rim_count) : Vec3::Zero();
    volumes.push_back((determinants - centre.dot(edge_cross)) / 6.0);
  }
  return volumes;
}

int dimple_size_for(const RegionDimple& d, double volume) {
  const std::size_t n = std::min(d.prefix_rest_volume.size(), static_cast<std::size_t>(d.limit));
  for (std::size_t k = 0; k < n; ++k)
    if (d.prefix_rest_volume[k] >= volume) return static_cast<int>(k) + 1;
  return static_cast<int>(n);
}

double dimple_rest_volume(double rest_volume, double shrink, double s, double rho) {
  if (!(rho > 0.0)) return rest_volume;
  return std::min(shrink * std::clamp(s, 0.0, 1.0) / rho, 1.0) * rest_volume;
}

void set_dimple_size(RegionDimple& d, const Faces& faces, int k) {
  k = std::clamp(k, 0, static_cast<int>(d.order.size()));
  if (k == d.size) return;
  d.size = k;
  d.dimple = make_region_cap(faces, std::vector<int>(d.order.begin(), d.order.begin() + k));
  d.dimple.rest_volume = k > 0 ? d.prefix_rest_volume[static_cast<std::size_t>(k) - 1] : 0.0;
}

}  // namespace shellcontract
