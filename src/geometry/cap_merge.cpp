// The region finder's mesh arrays and the merge of caps that belong to one part (cap_internal.hpp).
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "geometry/cap_internal.hpp"
#include "geometry/region_metrics.hpp"

namespace shellcontract::detail {
namespace {
/// Two fitted spheres are one when their centres and radii differ by at most this fraction of
/// the larger radius.
constexpr double SAME_SPHERE = 0.4;
/// A face joins the band between two caps of one sphere when its corners are within this
/// fraction of the radius from that sphere.
constexpr double BAND_TOLERANCE = 0.05;
}  // namespace

MeshArrays mesh_arrays(const Mesh& mesh, const Positions& x) {
  MeshArrays m;
  m.nv = mesh.number_of_vertices();
  m.nf = mesh.number_of_faces();
  m.tri.resize(m.nf);
  m.face_area.assign(m.nf, 0.0);
  m.vertex_area.assign(m.nv, 0.0);
  m.face_nbr.assign(m.nf, {-1, -1, -1});
  m.vertex_faces.resize(m.nv);
  for (FaceIndex f : mesh.faces()) {
    HalfedgeIndex h = mesh.halfedge(f);
    for (int k = 0; k < 3; ++k, h = mesh.next(h)) {
      m.tri[f.idx()][static_cast<std::size_t>(k)] = static_cast<int>(mesh.source(h).idx());
      const FaceIndex g = mesh.face(mesh.opposite(h));
      m.face_nbr[f.idx()][static_cast<std::size_t>(k)] = g == Mesh::null_face() ? -1 : static_cast<int>(g.idx());
    }
    const auto& t = m.tri[f.idx()];
    const Vec3 p0(x.row(t[0])), p1(x.row(t[1])), p2(x.row(t[2]));
    const double a = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    m.face_area[f.idx()] = a;
    m.total_area += a;
    for (int v : t) {
      m.vertex_area[static_cast<std::size_t>(v)] += a / 3.0;
      m.vertex_faces[static_cast<std::size_t>(v)].push_back(static_cast<int>(f.idx()));
    }
  }
  // Each vertex lists its neighbours in the order of the mesh's edges.
  m.nbr_start.assign(m.nv + 1, 0);
  for (EdgeIndex e : mesh.edges())
    for (int k = 0; k < 2; ++k) ++m.nbr_start[mesh.vertex(e, k).idx() + 1];
  for (std::size_t v = 0; v < m.nv; ++v) m.nbr_start[v + 1] += m.nbr_start[v];
  m.nbr_to.resize(static_cast<std::size_t>(m.nbr_start[m.nv]));
  m.nbr_len.resize(m.nbr_to.size());
  std::vector<int> fill(m.nbr_start.begin(), m.nbr_start.end() - 1);
  for (EdgeIndex e : mesh.edges()) {
    const int a = static_cast<int>(mesh.vertex(e, 0).idx()), b = static_cast<int>(mesh.vertex(e, 1).idx());
    const double len = (Vec3(x.row(a)) - Vec3(x.row(b))).norm();
    for (const auto& [from, to] : {std::pair<int, int>{a, b}, std::pair<int, int>{b, a}}) {
      const auto k = static_cast<std::size_t>(fill[static_cast<std::size_t>(from)]++);
      m.nbr_to[k] = to;
      m.nbr_len[k] = len;
    }
  }
  m.size = std::sqrt(m.total_area);
  return m;
}

std::vector<Cap> merge_adjacent_caps(const Mesh& mesh, const MeshArrays& m, const Positions& x,
                                     const Eigen::VectorXd& concave_field, std::vector<Cap> caps,
                                     const RegionOptions& options) {
  std::vector<int> owner_face(m.nf, -1);
  const auto assign = [&](std::size_t id) {
    for (int f : caps[id].faces) owner_face[static_cast<std::size_t>(f)] = static_cast<int>(id);
  };
  for (std::size_t id = 0; id < caps.size(); ++id) assign(id);
  std::vector<char> alive(caps.size(), 1);
  const auto refit = [&](Cap& cap) {
    std::set<int> verts;
    for (int f : cap.faces)
      for (int v : m.tri[static_cast<std::size_t>(f)]) verts.insert(v);
    SphereMoments moments(Vec3(x.row(cap.seed)), m.size);
    for (int v : verts) moments.add(Vec3(x.row(v)), m.vertex_area[static_cast<std::size_t>(v)]);
    if (const auto fit = moments.fit()) cap.sphere = *fit;
  };
  bool merged = true;
  while (merged) {
    merged = false;
    // Vertex owners (a vertex of a cap's face belongs to that cap; caps share no vertex).
    std::vector<int> owner(m.nv, -1);
    for (std::size_t f = 0; f < m.nf; ++f)
      if (owner_face[f] >= 0)
        for (int v : m.tri[f]) owner[static_cast<std::size_t>(v)] = owner_face[f];
    // Gap faces: outside every cap, corners on exactly two caps (and possibly on none).
    std::map<std::pair<int, int>, std::vector<int>> gaps;
    for (std::size_t f = 0; f < m.nf; ++f) {
      if (owner_face[f] >= 0) continue;
      std::set<int> ids;
      for (int v : m.tri[f])
        if (owner[static_cast<std::size_t>(v)] >= 0) ids.insert(owner[static_cast<std::size_t>(v)]);
      if (ids.size() == 2) gaps[{*ids.begin(), *ids.rbegin()}].push_back(static_cast<int>(f));
    }
    for (const auto& [pair, gap] : gaps) {  // ordered by the caps' rank
      const auto [a, b] = pair;
      double area = 0.0, concave = 0.0;
      std::set<int> corners;
      for (int f : gap)
        for (int v : m.tri[static_cast<std::size_t>(f)]) corners.insert(v);
      for (int v : corners) {
        area += m.vertex_area[static_cast<std::size_t>(v)];
        if (concave_field(v) < 0.0) concave += m.vertex_area[static_cast<std::size_t>(v)];
      }
      if (concave > options.max_concave_fraction * area) continue;  // a crease: two parts
      std::vector<char> flag(m.nf, 0);
      for (int f : caps[static_cast<std::size_t>(a)].faces) flag[static_cast<std::size_t>(f)] = 1;
      for (int f : caps[static_cast<std::size_t>(b)].faces) flag[static_cast<std::size_t>(f)] = 1;
      for (int f : gap) flag[static_cast<std::size_t>(f)] = 1;
      const RegionShape shape = region_shape(mesh, x, flag);
      if (!(shape.compactness <= options.max_compactness) || shape.area > options.max_area_fraction * m.total_area)
        continue;
      Cap& into = caps[static_cast<std::size_t>(a)];
      const Cap& from = caps[static_cast<std::size_t>(b)];
      into.faces.insert(into.faces.end(), from.faces.begin(), from.faces.end());
      into.faces.insert(into.faces.end(), gap.begin(), gap.end());
      std::sort(into.faces.begin(), into.faces.end());
      into.angle = std::max(into.angle, from.angle);
      into.rho = std::max(into.rho, from.rho);
      refit(into);
      alive[static_cast<std::size_t>(b)] = 0;
      caps[static_cast<std::size_t>(b)].faces.clear();
      assign(static_cast<std::size_t>(a));
      merged = true;
      break;  // owners changed: recompute the gaps
    }
  }
  // Two caps of one sphere (the front and back of a head, split by the caps taken before
  // them) with a band of unassigned faces between them on that sphere: the band is flooded
  // from both and they become one region.
  for (std::size_t a = 0; a < caps.size(); ++a)
    for (std::size_t b = a + 1; b < caps.size() && alive[a]; ++b) {
      if (!alive[b]) continue;
      const SphereFit& sa = caps[a].sphere;
      const SphereFit& sb = caps[b].sphere;
      const double r = std::max(sa.radius, sb.radius);
      if (!((sa.centre - sb.centre).norm() <= SAME_SPHERE * r && std::abs(sa.radius - sb.radius) <= SAME_SPHERE * r))
        continue;
      std::vector<char> flag(m.nf, 0);
      std::vector<int> stack;
      for (std::size_t id : {a, b})
        for (int f : caps[id].faces) flag[static_cast<std::size_t>(f)] = 1, stack.push_back(f);
      const auto on_sphere = [&](int f) {
        for (int v : m.tri[static_cast<std::size_t>(f)]) {
          const double d = (Vec3(x.row(v)) - sa.centre).norm();
          if (!(std::abs(d - sa.radius) <= BAND_TOLERANCE * sa.radius)) return false;
        }
        return true;
      };
      std::vector<int> band;
      while (!stack.empty()) {
        const int f = stack.back();
        stack.pop_back();
        for (int g : m.face_nbr[static_cast<std::size_t>(f)])
          if (g >= 0 && !flag[static_cast<std::size_t>(g)] && owner_face[static_cast<std::size_t>(g)] < 0 && on_sphere(g))
            flag[static_cast<std::size_t>(g)] = 1, stack.push_back(g), band.push_back(g);
      }
      // Joined only when the flood reached from one to the other: one edge-connected set.
      std::vector<char> seen(m.nf, 0);
      std::vector<int> walk{caps[a].faces.front()};
      seen[static_cast<std::size_t>(walk.front())] = 1;
      bool reached = false;
      const std::set<int> faces_b(caps[b].faces.begin(), caps[b].faces.end());
      while (!walk.empty() && !reached) {
        const int f = walk.back();
        walk.pop_back();
        reached = faces_b.count(f) > 0;
        for (int g : m.face_nbr[static_cast<std::size_t>(f)])
          if (g >= 0 && flag[static_cast<std::size_t>(g)] && !seen[static_cast<std::size_t>(g)])
            seen[static_cast<std::size_t>(g)] = 1, walk.push_back(g);
      }
      if (!reached) continue;
      // Notches of the flooded band (a face outside with two neighbours inside), filled in
      // synchronous passes as the caps' own (cap_finder.cpp, disc_faces).
      for (int pass = 0; pass < 3; ++pass) {
        std::vector<int> add;
        for (std::size_t g = 0; g < m.nf; ++g) {
          if (flag[g] || owner_face[g] >= 0) continue;
          int inside = 0;
          for (int k : m.face_nbr[g]) inside += (k >= 0 && flag[static_cast<std::size_t>(k)]) ? 1 : 0;
          if (inside >= 2) add.push_back(static_cast<int>(g));
        }
        if (add.empty()) break;
        for (int g : add) flag[static_cast<std::size_t>(g)] = 1, band.push_back(g);
      }
      const RegionShape shape = region_shape(mesh, x, flag);
      if (!(shape.compactness <= options.max_compactness) || shape.area > options.max_area_fraction * m.total_area)
        continue;
      Cap& into = caps[a];
      into.faces.insert(into.faces.end(), caps[b].faces.begin(), caps[b].faces.end());
      into.faces.insert(into.faces.end(), band.begin(), band.end());
      std::sort(into.faces.begin(), into.faces.end());
      into.angle = std::max(into.angle, caps[b].angle);
      refit(into);
      alive[b] = 0;
      caps[b].faces.clear();
      assign(a);
    }
  std::vector<Cap> out;
  for (std::size_t id = 0; id < caps.size(); ++id)
    if (alive[id]) out.push_back(std::move(caps[id]));
  return out;
}

}  // namespace shellcontract::detail
