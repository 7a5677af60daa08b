#include "sim/region_mirror.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

namespace shellcontract {
namespace {

/// Relative size below which a singular value counts as zero: the points are then collinear (the
/// second) or a single point (the first), far above rounding for meshes of any scale.
constexpr double RANK_TOLERANCE = 1e-9;

/// RegionMirror::max_step over the shortest rest edge at the vertex. A blocked vertex then moves
/// back and forth by at most half an edge, too little to show in a shaded frame, and a dimple
/// still keeps up with the regions' ramp in a run of the default length; a fifth of an edge (the
/// constraints' STEP_CLAMP_FACTOR per projection) made large dimples lag in short runs, a whole
/// edge left blocked vertices flickering (lab/regions/mirror_step.md).
constexpr double MIRROR_STEP_FACTOR = 0.5;

Vec3 centroid(const std::vector<Vec3>& p) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& q : p) c += q;
  return p.empty() ? c : Vec3(c / static_cast<double>(p.size()));
}

/// Whether the points span at least a plane (the centred scatter has two nonzero singular values).
bool spans_plane(const std::vector<Vec3>& p) {
  const Vec3 c = centroid(p);
  Mat3 scatter = Mat3::Zero();
  for (const Vec3& q : p) scatter += (q - c) * (q - c).transpose();
  const Eigen::JacobiSVD<Mat3> svd(scatter);
  const Vec3 s = svd.singularValues();  // descending
  return s(0) > 0.0 && std::isfinite(s(0)) && s(1) > RANK_TOLERANCE * s(0);
}

}  // namespace

Vec3 reflect(const Vec3& p, const MirrorPlane& plane) {
  return p - 2.0 * (p - plane.point).dot(plane.normal) * plane.normal;
}

std::optional<Similarity> fit_similarity(const std::vector<Vec3>& from,
                                         const std::vector<Vec3>& to) {
  if (from.size() != to.size() || from.size() < 3) return std::nullopt;
  if (!spans_plane(from) || !spans_plane(to)) return std::nullopt;
  const Vec3 cp = centroid(from), cq = centroid(to);
  Mat3 h = Mat3::Zero();
  double spread = 0.0;
  for (std::size_t i = 0; i < from.size(); ++i) {
    const Vec3 p = from[i] - cp;
    h += p * (to[i] - cq).transpose();
    spread += p.squaredNorm();
  }
  const Eigen::JacobiSVD<Mat3> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  // The best orthogonal map is V U^T; if it is a reflection, the smallest singular direction
  // (zero for a flat rim, where either sign fits equally) is flipped to make it a rotation.
  Mat3 d = Mat3::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0) d(2, 2) = -1.0;
  Similarity s;
  s.rotation = svd.matrixV() * d * svd.matrixU().transpose();
  s.scale = (svd.singularValues().asDiagonal() * d).trace() / spread;
  if (!(s.scale > 0.0) || !std::isfinite(s.scale)) return std::nullopt;
  s.translation = cq - s.scale * (s.rotation * cp);
  return s;
}

const char* mirror_fallback_name(MirrorFallback f) {
  switch (f) {
    case MirrorFallback::None:
      return "mirrorable";
    case MirrorFallback::NoRim:
      return "fewer than 3 rim vertices";
    case MirrorFallback::CollinearRim:
      return "collinear rim";
    case MirrorFallback::NoArea:
      return "zero area vector";
    case MirrorFallback::NoInteriorVertex:
      return "no interior vertex";
  }
  return "unknown";
}

RegionMirror make_region_mirror(const Positions& rest, const RegionCap& cap) {
  RegionMirror m;
  auto at = [&](int local) {
    return Vec3(rest.row(cap.vertices[static_cast<std::size_t>(local)]));
  };
  if (cap.rim.size() < 3) return m;  // NoRim
  for (int r : cap.rim) m.rest_rim.push_back(at(r));
  if (!spans_plane(m.rest_rim)) {
    m.fallback = MirrorFallback::CollinearRim;
    return m;
  }
  const Vec3 c = centroid(m.rest_rim);
  m.rest_centre = c;
  for (Vec3& p : m.rest_rim) p -= c;
  // The area vector, with the corners taken from the rim's centroid so that its size is the
  // region's, not the distance to the origin.
  Vec3 area = Vec3::Zero();
  double total = 0.0;
  for (Eigen::Index j = 0; j < cap.faces.rows(); ++j) {
    const Vec3 e = (at(cap.faces(j, 1)) - at(cap.faces(j, 0)))
                       .cross(at(cap.faces(j, 2)) - at(cap.faces(j, 0)));
    area += e;
    total += e.norm();
  }
  if (!(area.norm() > RANK_TOLERANCE * total)) {
    m.fallback = MirrorFallback::NoArea;
    return m;
  }
  m.plane.point = Vec3::Zero();  // relative to the rim's centroid
  m.plane.normal = area.normalized();
  std::vector<char> on_rim(cap.vertices.size(), 0);
  for (int r : cap.rim) on_rim[static_cast<std::size_t>(r)] = 1;
  for (std::size_t k = 0; k < cap.vertices.size(); ++k)
    if (!on_rim[k]) {
      m.moved.push_back(static_cast<int>(k));
      m.image.push_back(reflect(at(static_cast<int>(k)) - c, m.plane));
    }
  m.fallback = m.moved.empty() ? MirrorFallback::NoInteriorVertex : MirrorFallback::None;
  std::vector<char> by_rim(cap.vertices.size(), 0);
  for (Eigen::Index j = 0; j < cap.faces.rows(); ++j)
    if (on_rim[static_cast<std::size_t>(cap.faces(j, 0))] ||
        on_rim[static_cast<std::size_t>(cap.faces(j, 1))] ||
        on_rim[static_cast<std::size_t>(cap.faces(j, 2))])
      for (int k = 0; k < 3; ++k) by_rim[static_cast<std::size_t>(cap.faces(j, k))] = 1;
  m.crease.assign(m.moved.size(), 0);
  bool beyond = false;
  for (std::size_t i = 0; i < m.moved.size(); ++i) {
    m.crease[i] = by_rim[static_cast<std::size_t>(m.moved[i])];
    beyond = beyond || !m.crease[i];
  }
  if (!beyond) m.crease.assign(m.moved.size(), 0);
  // The step bound of each interior vertex: the shortest rest edge of the cap's faces at it.
  std::vector<double> shortest(cap.vertices.size(), std::numeric_limits<double>::infinity());
  for (Eigen::Index j = 0; j < cap.faces.rows(); ++j)
    for (int k = 0; k < 3; ++k) {
      const int a = cap.faces(j, k), b = cap.faces(j, (k + 1) % 3);
      const double len = (at(a) - at(b)).norm();
      if (!(len > 0.0)) continue;  // a collapsed edge bounds nothing
      for (int u : {a, b}) {
        double& s = shortest[static_cast<std::size_t>(u)];
        s = std::min(s, len);
      }
    }
  m.max_step.reserve(m.moved.size());
  for (int k : m.moved)
    m.max_step.push_back(MIRROR_STEP_FACTOR * shortest[static_cast<std::size_t>(k)]);
  return m;
}

bool apply_region_mirror(Positions& x, const RegionCap& cap, const RegionMirror& mirror,
                         const Eigen::VectorXd& w, const std::vector<char>& held, double beta) {
  return apply_region_mirror(x, cap, mirror, w, held, MirrorStep{beta, false, false, false});
}

bool apply_region_mirror(Positions& x, const RegionCap& cap, const RegionMirror& mirror,
                         const Eigen::VectorXd& w, const std::vector<char>& held,
                         const MirrorStep& step) {
  if (mirror.fallback != MirrorFallback::None || !(step.beta > 0.0)) return false;
  std::vector<Vec3> rim_rest, rim_now;
  rim_now.reserve(cap.rim.size());
  for (int r : cap.rim) rim_now.push_back(Vec3(x.row(cap.vertices[static_cast<std::size_t>(r)])));
  for (const Vec3& p : mirror.rest_rim) rim_rest.push_back(p + mirror.rest_centre);
  const std::optional<Similarity> frame = fit_similarity(rim_rest, rim_now);
  if (!frame) return false;
  return apply_region_mirror_in(x, cap, mirror, *frame, w, held, step);
}

std::optional<Similarity> shell_frame(const Positions& rest, const Positions& x,
                                      const std::vector<int>& vertices) {
  std::vector<Vec3> from, to;
  from.reserve(vertices.size());
  to.reserve(vertices.size());
  for (int v : vertices) {
    from.push_back(Vec3(rest.row(v)));
    to.push_back(Vec3(x.row(v)));
  }
  return fit_similarity(from, to);
}

bool apply_region_mirror_in(Positions& x, const RegionCap& cap, const RegionMirror& mirror,
                            const Similarity& frame, const Eigen::VectorXd& w,
                            const std::vector<char>& held, const MirrorStep& step) {
  if (mirror.fallback != MirrorFallback::None || !(step.beta > 0.0)) return false;
  const double share = std::min(step.beta, 1.0);
  // The rest plane's outward normal carried by the frame: the side the cap stood out to.
  const Vec3 outward = frame.rotation * mirror.plane.normal;
  for (std::size_t i = 0; i < mirror.moved.size(); ++i) {
    if (step.free_crease && i < mirror.crease.size() && mirror.crease[i]) continue;
    const int v = cap.vertices[static_cast<std::size_t>(mirror.moved[i])];
    if (!(w(v) > 0.0) ||
        (static_cast<std::size_t>(v) < held.size() && held[static_cast<std::size_t>(v)]))
      continue;
    const Vec3 target = frame(mirror.image[i] + mirror.rest_centre);
    // A mould: a vertex already deeper than its image (a load pushed it there) stays.
    if (step.one_sided && (Vec3(x.row(v)) - target).dot(outward) <= 0.0) continue;
    Vec3 move = share * (target - Vec3(x.row(v)));
    if (step.clamp && i < mirror.max_step.size()) {
      const double length = move.norm();
      if (length > mirror.max_step[i]) move *= mirror.max_step[i] / length;
    }
    x.row(v) += move.transpose();
  }
  return true;
}

}  // namespace shellcontract
