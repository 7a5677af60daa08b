#include "sim/region_volume.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>

namespace shellcontract {
namespace {

Vec3 rim_centroid(const Positions& x, const RegionCap& cap) {
  Vec3 c = Vec3::Zero();
  if (cap.rim.empty()) return c;  // no rim: the volume does not depend on c
  for (int r : cap.rim) c += Vec3(x.row(cap.vertices[static_cast<std::size_t>(r)]));
  return c / static_cast<double>(cap.rim.size());
}

}  // namespace

std::vector<std::vector<int>> region_pieces(const Faces& faces,
                                            const std::vector<int>& region_faces) {
  std::vector<int> kept;
  for (int f : region_faces)
    if (f >= 0 && f < faces.rows()) kept.push_back(f);
  std::sort(kept.begin(), kept.end());
  kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
  // Union-find over the kept faces (indices into `kept`), joined across each shared edge.
  std::vector<std::size_t> parent(kept.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
  auto root = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::vector<std::tuple<int, int, std::size_t>> edges;  // (low vertex, high vertex, face)
  edges.reserve(3 * kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int a = faces(kept[i], k), b = faces(kept[i], (k + 1) % 3);
      edges.emplace_back(std::min(a, b), std::max(a, b), i);
    }
  std::sort(edges.begin(), edges.end());
  for (std::size_t e = 1; e < edges.size(); ++e)
    if (std::get<0>(edges[e]) == std::get<0>(edges[e - 1]) &&
        std::get<1>(edges[e]) == std::get<1>(edges[e - 1]))
      parent[root(std::get<2>(edges[e]))] = root(std::get<2>(edges[e - 1]));
  // kept is sorted, so a piece's first face is its smallest: the pieces come in that order.
  std::vector<std::vector<int>> pieces;
  std::vector<std::size_t> piece_of_root(kept.size(), kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const std::size_t r = root(i);
    if (piece_of_root[r] == kept.size()) {
      piece_of_root[r] = pieces.size();
      pieces.emplace_back();
    }
    pieces[piece_of_root[r]].push_back(kept[i]);
  }
  return pieces;
}

RegionCap make_region_cap(const Faces& faces, const std::vector<int>& region_faces) {
  RegionCap cap;
  std::vector<int> kept;
  for (int f : region_faces)
    if (f >= 0 && f < faces.rows()) kept.push_back(f);
  std::sort(kept.begin(), kept.end());
  kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
  for (int f : kept)
    for (int k = 0; k < 3; ++k) cap.vertices.push_back(faces(f, k));
  std::sort(cap.vertices.begin(), cap.vertices.end());
  cap.vertices.erase(std::unique(cap.vertices.begin(), cap.vertices.end()), cap.vertices.end());
  auto local = [&](int v) {
    return static_cast<int>(std::lower_bound(cap.vertices.begin(), cap.vertices.end(), v) -
                            cap.vertices.begin());
  };
  cap.faces.resize(static_cast<Eigen::Index>(kept.size()), 3);
  // An undirected edge used by one region face is on the rim. The edges are counted in a sorted
  // vector rather than a map: a dimple is rebuilt at every change of its size during the ramp.
  std::vector<std::pair<int, int>> edges;
  edges.reserve(3 * kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int a = local(faces(kept[i], k)), b = local(faces(kept[i], (k + 1) % 3));
      cap.faces(static_cast<Eigen::Index>(i), k) = a;
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  std::vector<char> on_rim(cap.vertices.size(), 0);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) {
      on_rim[static_cast<std::size_t>(edges[i].first)] = 1;
      on_rim[static_cast<std::size_t>(edges[i].second)] = 1;
    }
    i = j;
  }
  for (std::size_t i = 0; i < on_rim.size(); ++i)
    if (on_rim[i]) cap.rim.push_back(static_cast<int>(i));
  return cap;
}

double cap_volume(const Positions& x, const RegionCap& cap) {
  const Vec3 c = rim_centroid(x, cap);
  auto corner = [&](Eigen::Index j, int k) {
    return Vec3(Vec3(x.row(cap.vertices[static_cast<std::size_t>(cap.faces(j, k))])) - c);
  };
  double v = 0.0;
  for (Eigen::Index j = 0; j < cap.faces.rows(); ++j)
    v += corner(j, 0).dot(corner(j, 1).cross(corner(j, 2)));
  return v / 6.0;
}

void cap_volume_gradient(const Positions& x, const RegionCap& cap, Positions& g) {
  const Vec3 c = rim_centroid(x, cap);
  g.setZero(static_cast<Eigen::Index>(cap.vertices.size()), 3);
  auto corner = [&](Eigen::Index j, int k) {
    return Vec3(Vec3(x.row(cap.vertices[static_cast<std::size_t>(cap.faces(j, k))])) - c);
  };
  for (Eigen::Index j = 0; j < cap.faces.rows(); ++j) {
    const Vec3 a = corner(j, 0), b = corner(j, 1), d = corner(j, 2);
    g.row(cap.faces(j, 0)) += b.cross(d).transpose() / 6.0;
    g.row(cap.faces(j, 1)) += d.cross(a).transpose() / 6.0;
    g.row(cap.faces(j, 2)) += a.cross(b).transpose() / 6.0;
  }
  if (cap.rim.empty()) return;
  // dV/dc = -(sum of the corners' terms) (translation invariance), and dc/dx_r = I / #rim.
  const Eigen::RowVector3d share = -g.colwise().sum() / static_cast<double>(cap.rim.size());
  for (int r : cap.rim) g.row(r) += share;
}

double cap_reach(const Positions& x, const RegionCap& cap) {
  std::vector<int> points = cap.rim;
  if (points.empty())
    for (std::size_t i = 0; i < cap.vertices.size(); ++i) points.push_back(static_cast<int>(i));
  if (points.empty()) return 0.0;
  auto at = [&](int r) { return Vec3(x.row(cap.vertices[static_cast<std::size_t>(r)])); };
  Vec3 c = Vec3::Zero();
  for (int r : points) c += at(r);
  c /= static_cast<double>(points.size());
  double reach = 0.0;
  for (int r : points) reach = std::max(reach, (at(r) - c).norm());
  return reach;
}

int project_cap_volume(Positions& x, const RegionCap& cap, const Eigen::VectorXd& w, double target,
                       double tolerance, int max_steps, double max_move) {
  return project_cap_volume_sharing(x, cap, w, {}, target, tolerance, max_steps, max_move);
}

int project_cap_volume_sharing(Positions& x, const RegionCap& cap, const Eigen::VectorXd& w,
                               const std::vector<char>& held, double target, double tolerance,
                               int max_steps, double max_move) {
  auto is_held = [&](int v) {
    return static_cast<std::size_t>(v) < held.size() && held[static_cast<std::size_t>(v)];
  };
  Positions g;
  int steps = 0;
  double budget = max_move;  // what the farthest-moved vertex may still move in this call
  for (; steps < max_steps; ++steps) {
    const double c = cap_volume(x, cap) - target;
    if (std::abs(c) <= tolerance) break;
    cap_volume_gradient(x, cap, g);
    double denominator = 0.0, movable = 0.0;
    for (std::size_t i = 0; i < cap.vertices.size(); ++i) {
      const double share = w(cap.vertices[i]) * g.row(static_cast<Eigen::Index>(i)).squaredNorm();
      denominator += share;
      if (!is_held(cap.vertices[i])) movable += share;
    }
    // No movable gradient (every vertex held, or a collapsed region): nothing can move V.
    if (!(movable > 0.0) || !std::isfinite(denominator)) break;
    double lambda = c / denominator;
    // The farthest this step moves a vertex: with a vanishing gradient (a cap collapsing onto its
    // rim's centroid) lambda is unbounded, so the step is cut to the budget (max_move).
    double largest = 0.0;
    for (std::size_t i = 0; i < cap.vertices.size(); ++i)
      if (!is_held(cap.vertices[i]))
        largest = std::max(largest, std::abs(lambda) * w(cap.vertices[i]) *
                                        g.row(static_cast<Eigen::Index>(i)).norm());
    if (!std::isfinite(largest)) break;
    const bool cut = largest > budget;
    if (cut) lambda *= budget / largest;
    for (std::size_t i = 0; i < cap.vertices.size(); ++i)
      if (!is_held(cap.vertices[i]))
        x.row(cap.vertices[i]) -= lambda * w(cap.vertices[i]) * g.row(static_cast<Eigen::Index>(i));
    if (cut) return steps + 1;
    budget -= largest;
  }
  return steps;
}

}  // namespace shellcontract
