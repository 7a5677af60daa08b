#include "sim/region_dimple.hpp"

#include <algorithm>
#include <map>
#include <numeric>
#include <utility>

namespace shellcontract {

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
  for (int f : d.order)
    normal += (at(faces(f, 1)) - at(faces(f, 0))).cross(at(faces(f, 2)) - at(faces(f, 0)));
  Vec3 rim_centre = Vec3::Zero();
  for (int r : d.whole.rim) rim_centre += at(d.whole.vertices[static_cast<std::size_t>(r)]);
  if (!d.whole.rim.empty()) rim_centre /= static_cast<double>(d.whole.rim.size());
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
  std::vector<std::size_t> rank(d.order.size());
  std::iota(rank.begin(), rank.end(), std::size_t{0});
  std::stable_sort(rank.begin(), rank.end(),
                   [&](std::size_t a, std::size_t b) { return distance[a] < distance[b]; });
  std::vector<int> sorted(d.order.size());
  for (std::size_t i = 0; i < rank.size(); ++i) sorted[i] = d.order[rank[i]];
  d.order = std::move(sorted);
  d.prefix_rest_volume = prefix_cap_volumes(rest, faces, d.order);
  return d;
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
  for (std::size_t k = 0; k < d.prefix_rest_volume.size(); ++k)
    if (d.prefix_rest_volume[k] >= volume) return static_cast<int>(k) + 1;
  return static_cast<int>(d.order.size());
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
