// A checked Mesh from a triangle soup in memory. The checks, their order and their messages follow
// read_input_mesh (src/mesh/io.cpp) for a triangle soup, so that an array and a file with the
// same content are accepted or refused alike; a file's extras (lines, polygon triangulation) do
// not apply. io.cpp keeps its checks inside read_input_mesh, hence this second implementation:
// if both ever move to one shared soup check, this file becomes a thin wrapper.
#include "shellcontract/mesh_io.hpp"

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "mesh/eigen_point_map.hpp"
#include "mesh/normalization.hpp"
#include "mesh/soup_checks.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {
namespace {

using Tri = std::array<std::size_t, 3>;

/// read_input_mesh's ZERO_AREA_RELATIVE: 2A below this fraction of the squared mean edge length.
constexpr double ZERO_AREA_RELATIVE = 1e-10;

using soup::fail;

std::string face_name(std::size_t f) { return "face " + std::to_string(f); }
std::string vertex_name(std::size_t v) { return "vertex " + std::to_string(v); }

Vec3 to_vec(const Point3& p) { return Vec3(p.x(), p.y(), p.z()); }

std::size_t find_root(std::vector<std::size_t>& parent, std::size_t a) {
  while (parent[a] != a) a = parent[a] = parent[parent[a]];
  return a;
}

/// Faces as size_t triangles; range and repeated-corner checks on the way.
std::vector<Tri> read_faces(const TriangleSoupView& s, const std::string& name) {
  std::vector<Tri> tris(s.num_faces);
  for (std::size_t f = 0; f < s.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      const std::int64_t v = s.faces32 ? s.faces32[3 * f + k] : s.faces64[3 * f + k];
      if (v < 0)
        fail(name, "vertex index out of range", face_name(f) + " has the negative index " + std::to_string(v));
      if (static_cast<std::uint64_t>(v) >= s.num_vertices)
        fail(name, "vertex index out of range", face_name(f) + " refers to vertex " + std::to_string(v) + ", but the mesh has " + std::to_string(s.num_vertices) + " vertices (0.." + std::to_string(s.num_vertices - 1) + ")");
      tris[f][k] = static_cast<std::size_t>(v);
      for (int l = 0; l < k; ++l)
        if (tris[f][l] == tris[f][k])
          fail(name, "degenerate face", face_name(f) + " uses vertex " + std::to_string(v) + " twice");
    }
  }
  return tris;
}

void check_duplicates_and_isolated(const std::vector<Tri>& tris, std::size_t nv, const std::string& name) {
  std::map<Tri, std::size_t> seen;
  for (std::size_t f = 0; f < tris.size(); ++f) {
    Tri key = tris[f];
    std::sort(key.begin(), key.end());
    const auto [it, inserted] = seen.emplace(key, f);
    if (!inserted)
      fail(name, "duplicate face", face_name(f) + " has the same vertices (" + std::to_string(key[0]) + ", " + std::to_string(key[1]) + ", " + std::to_string(key[2]) + ") as " + face_name(it->second));
  }
  std::vector<char> used(nv, 0);
  for (const Tri& t : tris)
    for (std::size_t v : t) used[v] = 1;
  for (std::size_t v = 0; v < nv; ++v)
    if (!used[v]) fail(name, "isolated vertex", vertex_name(v) + " is not used by any face");
}


/// Flips the inside-out components (negative signed volume of `points`, a unit-diagonal copy of
/// the input scaled by `scale`); returns the components' count.
std::size_t orient_components(std::vector<Tri>& tris, const std::vector<Point3>& points, double scale,
                              bool reorient, std::vector<std::string>& warnings, bool& reoriented) {
  std::vector<std::size_t> parent(points.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (const Tri& t : tris) {
    parent[find_root(parent, t[0])] = find_root(parent, t[1]);
    parent[find_root(parent, t[1])] = find_root(parent, t[2]);
  }
  std::map<std::size_t, std::size_t> component_of_root;
  for (const Tri& t : tris) component_of_root.emplace(find_root(parent, t[0]), component_of_root.size());
  const std::size_t n = component_of_root.size();
  std::vector<double> six_volume(n, 0.0);
  std::vector<Vec3> origin(n);
  std::vector<char> has_origin(n, 0);
  std::vector<std::size_t> component(tris.size());
  for (std::size_t f = 0; f < tris.size(); ++f) {
    const std::size_t c = component_of_root.at(find_root(parent, tris[f][0]));
    component[f] = c;
    // Measured from a point of the component (less cancellation far from the origin).
    if (!has_origin[c]) {
      origin[c] = to_vec(points[tris[f][0]]);
      has_origin[c] = 1;
    }
    const Vec3 a = to_vec(points[tris[f][0]]) - origin[c];
    six_volume[c] += a.dot((to_vec(points[tris[f][1]]) - origin[c]).cross(to_vec(points[tris[f][2]]) - origin[c]));
  }
  reoriented = false;
  for (std::size_t c = 0; reorient && c < n; ++c) {
    if (six_volume[c] >= 0.0) continue;
    reoriented = true;
    std::size_t first = tris.size(), count = 0;
    for (std::size_t f = 0; f < tris.size(); ++f)
      if (component[f] == c) {
        std::swap(tris[f][1], tris[f][2]);  // corner 0 stays first
        first = std::min(first, f);
        ++count;
      }
    std::ostringstream w;
    w << "component " << c << " (" << count << " faces, starting at face " << first
      << ") was inside-out (signed volume " << six_volume[c] / 6.0 * scale * scale * scale
      << "); its faces were flipped";
    warnings.push_back(w.str());
  }
  return n;
}

std::vector<std::size_t> zero_area_faces(const std::vector<Tri>& tris, const std::vector<Point3>& points) {
  double edge_sum = 0.0;
  for (const Tri& t : tris)
    for (int k = 0; k < 3; ++k) edge_sum += (to_vec(points[t[k]]) - to_vec(points[t[(k + 1) % 3]])).norm();
  const double mean_edge = edge_sum / (3.0 * static_cast<double>(tris.size()));
  const double threshold = ZERO_AREA_RELATIVE * mean_edge * mean_edge;
  std::vector<std::size_t> out;
  for (std::size_t f = 0; f < tris.size(); ++f) {
    const Vec3 a = to_vec(points[tris[f][0]]);
    if ((to_vec(points[tris[f][1]]) - a).cross(to_vec(points[tris[f][2]]) - a).norm() < threshold) out.push_back(f);
  }
  return out;
}

}  // namespace

Mesh mesh_from_arrays(const TriangleSoupView& soup, const std::string& name, InputReport* report, bool reorient) {
  if ((soup.faces32 == nullptr) == (soup.faces64 == nullptr))
    throw std::invalid_argument("mesh_from_arrays: set exactly one of faces32 and faces64");
  if (soup.num_vertices == 0 || soup.num_faces == 0)
    fail(name, "empty mesh", std::to_string(soup.num_vertices) + " vertices and " + std::to_string(soup.num_faces) + " faces");
  const std::size_t nv = soup.num_vertices;
  std::vector<Point3> points;
  points.reserve(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    const double* p = soup.vertices + 3 * i;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      std::ostringstream c;
      c << p[0] << ' ' << p[1] << ' ' << p[2];
      fail(name, "non-finite coordinate", vertex_name(i) + " is (" + c.str() + ")");
    }
    points.emplace_back(p[0], p[1], p[2]);
  }
  std::vector<Tri> tris = read_faces(soup, name);
  check_duplicates_and_isolated(tris, nv, name);
  // The reader's edge and fan checks, with faces and vertices named by their index (no lines).
  const SourceLines no_lines;
  std::vector<std::size_t> identity(tris.size());
  std::iota(identity.begin(), identity.end(), std::size_t{0});
  soup::Namer by_index;
  by_index.lines = &no_lines;
  by_index.points = &points;
  by_index.origin = &identity;
  soup::check_edges(name, tris, nv, by_index);
  soup::check_vertex_fans(name, tris, nv, by_index);
  // Orientation and zero areas on coordinates at a unit diagonal, as read_input_mesh decides
  // them: in input units a mesh at 1e160 overflowed the signed volume (its sign lost) and one at
  // 1e-160 underflowed it. A zero or non-finite diagonal is refused below, after these checks.
  Eigen::Vector3d lo = to_vec(points[0]), hi = lo;
  for (const Point3& p : points) {
    lo = lo.cwiseMin(to_vec(p));
    hi = hi.cwiseMax(to_vec(p));
  }
  const double diagonal = bounding_diagonal(lo, hi);
  const double scale = std::isfinite(diagonal) && diagonal > 0.0 ? diagonal : 1.0;
  const Eigen::Vector3d centre = 0.5 * lo + 0.5 * hi;
  std::vector<Point3> unit;
  unit.reserve(nv);
  for (const Point3& p : points) {
    const Eigen::Vector3d q = (to_vec(p) - centre) / scale;
    unit.emplace_back(q.x(), q.y(), q.z());
  }
  std::vector<std::string> warnings;
  bool reoriented = false;
  const std::size_t components = orient_components(tris, unit, scale, reorient, warnings, reoriented);
  std::vector<std::size_t> zero_area = zero_area_faces(tris, unit);
  if (!zero_area.empty())
    warnings.push_back(std::to_string(zero_area.size()) + " faces have (nearly) zero area: " + soup::list_indices(zero_area));

  // What the simulator needs beyond a closed manifold, decided and measured as read_input_mesh
  // does (a usable bounding box; a positive volume at a unit diagonal, scaled back).
  if (!(std::isfinite(diagonal) && diagonal > 0.0))
    fail(name, "degenerate mesh", diagonal == 0.0 ? "zero bounding-box diagonal"
                                                  : "non-finite bounding-box diagonal: the coordinates span more than a double holds");

  Mesh mesh;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, tris, mesh);
  if (mesh.number_of_faces() != tris.size())
    throw std::logic_error("mesh_from_arrays: polygon_soup_to_polygon_mesh dropped faces of a checked soup");
  // Each face's halfedge starts at the soup's first corner, so that a written face lists its
  // corners as given (read_input_mesh's align_to_soup).
  for (const FaceIndex f : mesh.faces()) {
    const Tri& t = tris[f.idx()];
    HalfedgeIndex h = mesh.halfedge(f);
    for (int k = 0; k < 3 && mesh.target(h).idx() != t[0]; ++k) h = mesh.next(h);
    if (mesh.target(h).idx() != t[0] || mesh.target(mesh.next(h)).idx() != t[1])
      throw std::logic_error("mesh_from_arrays: face " + std::to_string(f.idx()) + " lost its corner order");
    mesh.set_halfedge(f, h);
  }
  const Positions x = positions_from_mesh(mesh);
  // read_input_mesh's measure: the PMP::volume call of validation's enclosed_volume, made here
  // so that mesh/ does not depend on validation/.
  const Positions unit_x = normalize(x, compute_normalization(x));
  const double unit_volume =
      CGAL::Polygon_mesh_processing::volume(mesh, CGAL::parameters::vertex_point_map(EigenPointMap(unit_x)));
  if (reorient && !(unit_volume > 0.0)) {
    std::ostringstream v;
    v << unit_volume;
    fail(name, "no positive volume", "the mesh encloses no positive volume (" + v.str() +
                                         " at a unit bounding-box diagonal): it is flat or degenerate");
  }
  if (report) {
    report->vertices = mesh.number_of_vertices();
    report->faces = mesh.number_of_faces();
    report->triangulated_faces = 0;
    report->zero_area_faces = std::move(zero_area);
    report->reoriented = reoriented;
    report->components = components;
    report->volume = unit_volume * diagonal * diagonal * diagonal;
    report->warnings = std::move(warnings);
  }
  return mesh;
}

}  // namespace shellcontract
