// The region finder's mesh arrays (cap_internal.hpp).
#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "core/cancellation.hpp"
#include "geometry/cap_internal.hpp"

namespace shellcontract::detail {

FinderStart start_finder(const Mesh& mesh, const Positions& x) {
  FinderStart start;
  start.curvature = compute_curvature(mesh, x);  // first: it checks the mesh
  cancellation_point();
  start.arrays = mesh_arrays(mesh, x);
  return start;
}

std::vector<int> no_regions(FinderStart& start, RegionReport* report, CurvatureField* curvature) {
  if (report) {
    *report = RegionReport{};
    report->total_area = start.arrays.total_area;
  }
  if (curvature) *curvature = std::move(start.curvature);
  return std::vector<int>(start.arrays.nf, -1);
}

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
    // A run's cancel (cancellation.hpp), per chunk of a large mesh's faces.
    if (f.idx() % CANCELLATION_CHUNK == 0) cancellation_point();
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
  cancellation_point();
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

}  // namespace shellcontract::detail
