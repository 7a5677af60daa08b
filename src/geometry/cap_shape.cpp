// The final shape of a region (cap_internal.hpp, shape_cap): at most a hemisphere of its sphere,
// one piece, without holes that no other region fills.
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "geometry/cap_internal.hpp"

namespace shellcontract::detail {
namespace {

/// A face is on a region's sphere when its corners are within twice the fit's residual of it,
/// in units of the radius, kept within these bounds (an exact sphere still gets a band a face
/// wide; a loose fit does not spread over its neighbours).
constexpr double MIN_BAND = 0.005, MAX_BAND = 0.1;
/// Passes that fill notches and cut spikes of a region's outline (shape_cap); a clip leaves
/// teeth one or two faces deep.
constexpr int SMOOTHING_PASSES = 3;

}  // namespace

Vec3 face_centroid(const MeshArrays& m, const Positions& x, int f) {
  const auto& t = m.tri[static_cast<std::size_t>(f)];
  return (Vec3(x.row(t[0])) + Vec3(x.row(t[1])) + Vec3(x.row(t[2]))) / 3.0;
}

std::vector<int> largest_piece(const MeshArrays& m, const std::vector<char>& flag) {
  const Components pieces = components(m, flag);
  const int big = largest(pieces);
  std::vector<int> out;
  for (std::size_t f = 0; f < m.nf; ++f)
    if (big >= 0 && pieces.of[f] == big) out.push_back(static_cast<int>(f));
  return out;
}

Cap region_cap(const MeshArrays& m, const Positions& x, int seed, std::vector<int> faces) {
  Cap cap;
  cap.seed = seed;
  cap.faces = std::move(faces);
  if (const auto fit = fit_faces(m, x, cap.faces, cap.seed)) cap.sphere = *fit;
  const Vec3 axis = cap_axis(m, x, cap.faces, cap.sphere.centre);
  for (int f : cap.faces) {
    const Vec3 dir = face_centroid(m, x, f) - cap.sphere.centre;
    if (dir.norm() > 0.0)
      cap.angle = std::max(cap.angle, std::acos(std::clamp(dir.normalized().dot(axis), -1.0, 1.0)));
  }
  return cap;
}

std::size_t* failed_filter(const RegionSummary& s, const RegionOptions& o, RegionReport& r) {
  if (s.area_fraction < o.min_area_fraction || s.faces < static_cast<std::size_t>(o.min_faces)) return &r.dropped_small;
  if (s.area_fraction > o.max_area_fraction) return &r.dropped_large;
  if (!(s.compactness <= o.max_compactness)) return &r.dropped_shape;
  return nullptr;
}

Components components(const MeshArrays& m, const std::vector<char>& flag) {
  Components c;
  c.of.assign(m.nf, -1);
  std::vector<int> stack;
  for (std::size_t f = 0; f < m.nf; ++f) {
    if (!flag[f] || c.of[f] >= 0) continue;
    const int id = static_cast<int>(c.area.size());
    c.area.push_back(0.0);
    c.first.push_back(static_cast<int>(f));
    c.of[f] = id;
    stack.push_back(static_cast<int>(f));
    while (!stack.empty()) {
      const auto g = static_cast<std::size_t>(stack.back());
      stack.pop_back();
      c.area[static_cast<std::size_t>(id)] += m.face_area[g];
      for (int h : m.face_nbr[g])
        if (h >= 0 && flag[static_cast<std::size_t>(h)] && c.of[static_cast<std::size_t>(h)] < 0)
          c.of[static_cast<std::size_t>(h)] = id, stack.push_back(h);
    }
  }
  return c;
}

int largest(const Components& c) {
  int best = -1;
  for (std::size_t i = 0; i < c.area.size(); ++i)
    if (best < 0 || c.area[i] > c.area[static_cast<std::size_t>(best)]) best = static_cast<int>(i);
  return best;
}

/// The faces' corners, each once, in increasing index (the order a std::set gave, without its
/// node per vertex).
std::vector<int> corners(const MeshArrays& m, const std::vector<int>& faces) {
  std::vector<int> verts;
  verts.reserve(3 * faces.size());
  for (int f : faces)
    for (int v : m.tri[static_cast<std::size_t>(f)]) verts.push_back(v);
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  return verts;
}

std::optional<SphereFit> fit_faces(const MeshArrays& m, const Positions& x, const std::vector<int>& faces, int origin) {
  const std::vector<int> verts = corners(m, faces);
  SphereMoments moments(Vec3(x.row(origin)), m.size);
  for (int v : verts) moments.add(Vec3(x.row(v)), m.vertex_area[static_cast<std::size_t>(v)]);
  return moments.fit();
}

/// Axis: the area-weighted mean direction from the centre to the faces (a property of the face
/// set, not of the seed vertex, so a subdivided mesh gives the same axis); zero when there is
/// none (a closed sphere).
Vec3 cap_axis(const MeshArrays& m, const Positions& x, const std::vector<int>& faces, const Vec3& c) {
  Vec3 axis = Vec3::Zero();
  double area = 0.0;
  for (int f : faces) {
    const Vec3 d = face_centroid(m, x, f) - c;
    const double n = d.norm();
    area += m.face_area[static_cast<std::size_t>(f)];
    if (n > 0.0) axis += m.face_area[static_cast<std::size_t>(f)] * d / n;
  }
  return axis.norm() > 1e-9 * area ? Vec3(axis.normalized()) : Vec3::Zero();
}


bool shape_cap(const MeshArrays& m, const Positions& x, Cap& cap, std::vector<int>& owner_face,
               int id, const std::vector<char>& crease) {
  const double cos_max = std::cos(MAX_CAP_ANGLE);
  if (cap.faces.empty()) return false;
  // The sphere and axis of the part as found (the union of its seeds' caps, so it depends on the
  // part more than on which seed ranked first); the region is the surface on that sphere
  // (corners within a band of twice the fit's residual) within a hemisphere about the axis,
  // flooded from the part. A refit on the clipped region, repeated, drifts along a limb whose
  // end is not a sphere; one pass does not.
  if (const auto fit = fit_faces(m, x, cap.faces, cap.seed)) cap.sphere = *fit;
  const Vec3 c = cap.sphere.centre;
  const double r = cap.sphere.radius;
  const Vec3 axis = cap_axis(m, x, cap.faces, c);
  if (axis.isZero() || !(r > 0.0)) return false;
  const double band = std::clamp(2.0 * cap.sphere.residual, MIN_BAND, MAX_BAND) * r;
  const auto within = [&](std::size_t f) {
    const Vec3 d = face_centroid(m, x, static_cast<int>(f)) - c;
    return d.dot(axis) >= cos_max * d.norm();
  };
  const auto near = [&](std::size_t f) {
    for (int v : m.tri[f])
      if (!(std::abs((Vec3(x.row(v)) - c).norm() - r) <= band)) return false;
    return true;
  };
  std::vector<char> flag(m.nf, 0);
  std::vector<int> stack;
  for (int f : cap.faces)
    if (within(static_cast<std::size_t>(f))) flag[static_cast<std::size_t>(f)] = 1, stack.push_back(f);
  while (!stack.empty()) {
    const auto f = static_cast<std::size_t>(stack.back());
    stack.pop_back();
    for (int g : m.face_nbr[f]) {
      const auto gi = static_cast<std::size_t>(g);
      if (g < 0 || flag[gi] || (owner_face[gi] >= 0 && owner_face[gi] != id) || !within(gi) || !near(gi)) continue;
      flag[gi] = 1;
      stack.push_back(g);
    }
  }
  // A smooth outline: notches (a face outside with two neighbours inside) filled and spikes (a
  // face inside with at most one neighbour inside) cut, in synchronous passes (so the result
  // does not depend on the face order). A clip through a triangulation leaves a staircase whose
  // teeth would add perimeter at every resolution.
  // A notch on a concave crease is not a tooth: it is the groove between two parts side by side
  // (two finger ends whose caps the part's union holds), one or two faces wide, and filling it
  // joins them into one region across the crease. So no face with a concave corner is added;
  // creases inside a part are filled below, as holes.
  const auto on_crease = [&](std::size_t f) {
    for (int v : m.tri[f])
      if (crease[static_cast<std::size_t>(v)]) return true;
    return false;
  };
  // A face can change only when it or a neighbour is in the region (the first pass) or changed
  // in the pass before: only those faces are examined, each once (add and cut are disjoint, so
  // their order cannot matter), instead of every face of the mesh in every pass.
  std::vector<std::size_t> look;
  std::vector<char> listed(m.nf, 0);
  const auto list = [&](std::size_t f) {
    if (!listed[f]) listed[f] = 1, look.push_back(f);
    for (int g : m.face_nbr[f])
      if (g >= 0 && !listed[static_cast<std::size_t>(g)]) listed[static_cast<std::size_t>(g)] = 1, look.push_back(static_cast<std::size_t>(g));
  };
  for (std::size_t f = 0; f < m.nf; ++f)
    if (flag[f]) list(f);
  for (int pass = 0; pass < SMOOTHING_PASSES; ++pass) {
    std::vector<std::size_t> add, cut;
    for (std::size_t f : look) {
      int inside = 0;
      for (int g : m.face_nbr[f]) inside += (g >= 0 && flag[static_cast<std::size_t>(g)]) ? 1 : 0;
      if (!flag[f] && inside >= 2 && within(f) && !(owner_face[f] >= 0 && owner_face[f] != id) &&
          !on_crease(f))
        add.push_back(f);
      if (flag[f] && inside <= 1) cut.push_back(f);
    }
    if (add.empty() && cut.empty()) break;
    for (std::size_t f : add) flag[f] = 1;
    for (std::size_t f : cut) flag[f] = 0;
    for (std::size_t f : look) listed[f] = 0;
    look.clear();
    for (std::size_t f : add) list(f);
    for (std::size_t f : cut) list(f);
  }
  // One piece: the clip can cut off a sliver on the far side of the rim.
  const Components pieces = components(m, flag);
  const int keep = largest(pieces);
  if (keep < 0) return false;
  for (std::size_t f = 0; f < m.nf; ++f) flag[f] = pieces.of[f] == keep ? 1 : 0;
  // Holes: components of the other faces that lie inside the region. A hole within the
  // hemisphere that holds no face of another region (a crease, a snout's base, scan noise)
  // belongs to the part a person would circle; one that holds another region (an ear) stays
  // out, and so does everything reaching beyond the hemisphere (the rest of the mesh, or the far
  // side of a nearly closed ball). Each component is explored from the region's border and the
  // search stops at the first face that disqualifies it, so the cost is the holes', not the
  // mesh's.
  enum : char { UNSEEN, OPEN, NOT_HOLE };
  std::vector<char> seen(m.nf, UNSEEN);
  std::vector<int> walk, members;
  for (std::size_t f0 = 0; f0 < m.nf; ++f0) {
    if (!flag[f0]) continue;
    for (int start : m.face_nbr[f0]) {
      if (start < 0 || flag[static_cast<std::size_t>(start)] || seen[static_cast<std::size_t>(start)] != UNSEEN) continue;
      bool hole = true;
      walk.assign(1, start);
      members.clear();
      seen[static_cast<std::size_t>(start)] = OPEN;
      while (!walk.empty() && hole) {
        const auto g = static_cast<std::size_t>(walk.back());
        walk.pop_back();
        members.push_back(static_cast<int>(g));
        if ((owner_face[g] >= 0 && owner_face[g] != id) || !within(g)) {
          hole = false;
          break;
        }
        for (int h : m.face_nbr[g]) {
          if (h < 0 || flag[static_cast<std::size_t>(h)]) continue;
          const char st = seen[static_cast<std::size_t>(h)];
          if (st == NOT_HOLE) hole = false;
          if (st != UNSEEN) continue;
          seen[static_cast<std::size_t>(h)] = OPEN;
          walk.push_back(h);
        }
      }
      for (int g : walk) members.push_back(g);
      for (int g : members) seen[static_cast<std::size_t>(g)] = hole ? OPEN : NOT_HOLE;
      if (hole)
        for (int g : members) flag[static_cast<std::size_t>(g)] = 1;
    }
  }
  // The hemisphere about the region's own axis: the flood and the holes move the mean direction
  // a little off the part's, so faces beyond 90 degrees of the final axis are cut until none is
  // (cuts only, so it ends).
  Vec3 final_axis = axis;
  for (int round = 0; round < 20; ++round) {
    std::vector<int> faces;
    for (std::size_t f = 0; f < m.nf; ++f)
      if (flag[f]) faces.push_back(static_cast<int>(f));
    final_axis = cap_axis(m, x, faces, c);
    if (final_axis.isZero()) return false;
    bool cut = false;
    for (int f : faces) {
      const Vec3 d = face_centroid(m, x, f) - c;
      if (!(d.dot(final_axis) >= cos_max * d.norm())) flag[static_cast<std::size_t>(f)] = 0, cut = true;
    }
    if (!cut) break;
    const Components rest_pieces = components(m, flag);
    const int biggest = largest(rest_pieces);
    if (biggest < 0) return false;
    for (std::size_t f = 0; f < m.nf; ++f) flag[f] = rest_pieces.of[f] == biggest ? 1 : 0;
  }
  cap.faces.clear();
  for (std::size_t f = 0; f < m.nf; ++f) {
    if (owner_face[f] == id && !flag[f]) owner_face[f] = -1;
    if (flag[f]) owner_face[f] = id, cap.faces.push_back(static_cast<int>(f));
  }
  // Reported: the sphere that shaped the region, the RMS distance of the region's vertices to
  // it (area weights) / its radius, and the widest face centroid from the region's axis.
  const std::vector<int> verts = corners(m, cap.faces);
  double w = 0.0, sq = 0.0;
  for (int v : verts) {
    const double e = (Vec3(x.row(v)) - c).norm() - r, a = m.vertex_area[static_cast<std::size_t>(v)];
    w += a, sq += a * e * e;
  }
  cap.sphere.residual = w > 0.0 ? std::sqrt(sq / w) / r : 0.0;
  double angle = 0.0;
  for (int f : cap.faces) {
    const Vec3 d = face_centroid(m, x, f) - c;
    const double n = d.norm();
    if (n > 0.0) angle = std::max(angle, std::acos(std::clamp(d.dot(final_axis) / n, -1.0, 1.0)));
  }
  cap.angle = angle;
  return !cap.faces.empty();
}

}  // namespace shellcontract::detail
