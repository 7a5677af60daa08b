#include "sim/region_volume.hpp"

#include <algorithm>
#include <cmath>
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

int project_cap_volume(Positions& x, const RegionCap& cap, const Eigen::VectorXd& w, double target,
                       double tolerance, int max_steps) {
  return project_cap_volume_sharing(x, cap, w, {}, target, tolerance, max_steps);
}

int project_cap_volume_sharing(Positions& x, const RegionCap& cap, const Eigen::VectorXd& w,
                               const std::vector<char>& held, double target, double tolerance,
                               int max_steps) {
  auto is_held = [&](int v) {
    return static_cast<std::size_t>(v) < held.size() && held[static_cast<std::size_t>(v)];
  };
  Positions g;
  int steps = 0;
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
    const double lambda = c / denominator;
    for (std::size_t i = 0; i < cap.vertices.size(); ++i)
      if (!is_held(cap.vertices[i]))
        x.row(cap.vertices[i]) -= lambda * w(cap.vertices[i]) * g.row(static_cast<Eigen::Index>(i));
  }
  return steps;
}

}  // namespace shellcontract
