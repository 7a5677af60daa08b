// Reading and checking meshes (design.md, data flow: read -> check input); writing is in
// write_mesh.cpp.
//
// Reading goes through a polygon soup, which we check ourselves before
// PMP::polygon_soup_to_polygon_mesh: that function only *asserts* that the soup is a valid
// polygon mesh, and a failed Euler::add_face in a release build silently yields a null face.
// PMP::is_polygon_soup_a_polygon_mesh would say only yes or no; our checks let every message
// name the problem, the face, the vertex and (for OFF and ascii PLY) the line, and they cover
// every condition it tests (see check_soup). CGAL does what needs no message: the mesh, its
// connected components, the volume. PMP::merge_duplicate_polygons_in_polygon_soup and orient_polygon_soup would change a
// file the user must hear about (`repair` uses them, on request). The soup keeps the input
// vertex and face order, which users rely on (textures, per-vertex data); read_input_mesh
// verifies that it was kept.
//
// The soup comes from CGAL::IO::read_OBJ/STL, or from our own PLY and OFF readers (ply_reader.cpp:
// CGAL 5.5's crashes; off_scan.cpp: CGAL's trusts declared counts, misreads binary OFF and parses
// slowly). Every geometric test (triangulation, orientation, volume, zero area)
// runs on coordinates normalized to the bounding-box centre and a unit diagonal, so that meshes
// from 1e-150 to 1e150 get the same answers as at unit scale (no overflow or underflow in
// products of three coordinates).
#include "shellcontract/mesh_io.hpp"

#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <map>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "mesh/eigen_point_map.hpp"
#include "mesh/normalization.hpp"
#include "mesh/read_polygon_soup.hpp"
#include "shellcontract/error.hpp"

#include "mesh/soup_checks.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
namespace PMP = CGAL::Polygon_mesh_processing;
using soup::check_edges;
using soup::check_no_duplicate_face;
using soup::check_no_isolated_vertex;
using soup::check_vertex_fans;
using soup::fail;
using soup::list_indices;
using soup::Namer;
using soup::Polygon;

/// Faces with 2A below this fraction of the squared mean edge length count as zero-area
/// (relative, so that the test does not depend on the mesh's units).
constexpr double ZERO_AREA_RELATIVE = 1e-10;

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// ------------------------------------------- triangulation and orientation (soup_checks.hpp: connectivity)

Vec3 to_vec(const Point3& p) { return Vec3(p.x(), p.y(), p.z()); }

/// Fan-triangulates polygon `p` from the first corner whose fan triangles all face along the
/// polygon's Newell normal (any convex polygon, and star-shaped ones seen from that corner).
/// @return the triangles, or an empty vector when no corner works (non-convex polygon)
std::vector<Polygon> fan_triangulate(const Polygon& p, const std::vector<Point3>& pts) {
  const std::size_t n = p.size();
  Vec3 normal = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) normal += to_vec(pts[p[i]]).cross(to_vec(pts[p[(i + 1) % n]]));
  for (std::size_t k = 0; k < n; ++k) {
    std::vector<Polygon> tris;
    bool ok = true;
    for (std::size_t j = 1; j + 1 < n && ok; ++j) {
      Polygon t{p[k], p[(k + j) % n], p[(k + j + 1) % n]};
      const Vec3 a = to_vec(pts[t[0]]), b = to_vec(pts[t[1]]), c = to_vec(pts[t[2]]);
      ok = (b - a).cross(c - a).dot(normal) > 0.0;
      tris.push_back(std::move(t));
    }
    // A flat (zero-normal) polygon has no good corner; corner 0 gives zero-area triangles,
    // which are then reported like any other zero-area face.
    if (ok || normal.squaredNorm() == 0.0) return tris;
  }
  return {};
}

/// Sets each face's halfedge so that vertices_around_face starts at the soup's first corner:
/// then a written face lists its corners exactly as the input did (per-corner data such as UVs
/// stay aligned). Also verifies that the conversion kept vertex and face order.
void align_to_soup(Mesh& mesh, const std::vector<Polygon>& tris) {
  if (mesh.number_of_faces() != tris.size())
    throw std::logic_error("read_input_mesh: polygon_soup_to_polygon_mesh dropped faces of a checked soup");
  for (const FaceIndex f : mesh.faces()) {
    const Polygon& t = tris[f.idx()];
    HalfedgeIndex h = mesh.halfedge(f);
    for (int k = 0; k < 3 && mesh.target(h).idx() != t[0]; ++k) h = mesh.next(h);
    if (mesh.target(h).idx() != t[0] || mesh.target(mesh.next(h)).idx() != t[1] ||
        mesh.target(mesh.next(mesh.next(h))).idx() != t[2])
      throw std::logic_error("read_input_mesh: face " + std::to_string(f.idx()) + " lost its input vertex order");
    mesh.set_halfedge(f, h);
  }
}

/// Components (PMP::connected_components, numbered in order of their first face) and their
/// orientation: a component with negative signed volume is inside-out and gets flipped
/// (swapping corners 1 and 2 keeps corner 0 first). Each component is taken as its own shell;
/// a nested inner wall of a hollow solid would also be flipped outward (which
/// PMP::orient_to_bound_a_volume would not do: it orients nested shells inward).
/// @param mesh   built from tris (components are found on it)
/// @param unit   the points at a unit bounding-box diagonal; scale = that diagonal (for the message)
/// @return the number of components; inside-out ones are flipped in tris and named in warnings
std::size_t orient_components(const Mesh& mesh, std::vector<Polygon>& tris, const std::vector<Point3>& unit,
                              double scale, std::vector<std::string>& warnings) {
  const std::size_t nf = tris.size();
  std::vector<std::size_t> component_face(nf);
  const std::size_t n_components = PMP::connected_components(mesh, CGAL::make_property_map(component_face));
  std::vector<double> six_volume(n_components, 0.0);
  std::vector<Vec3> origin_point(n_components);
  std::vector<char> has_origin(n_components, 0);
  for (std::size_t f = 0; f < nf; ++f) {
    const std::size_t c = component_face[f];
    // Measured from a point of the component: the closed-surface sum does not depend on the
    // origin, and a nearby one avoids cancellation for components far from the centre.
    if (!has_origin[c]) {
      origin_point[c] = to_vec(unit[tris[f][0]]);
      has_origin[c] = 1;
    }
    const Vec3 a = to_vec(unit[tris[f][0]]) - origin_point[c];
    const Vec3 b = to_vec(unit[tris[f][1]]) - origin_point[c];
    const Vec3 d = to_vec(unit[tris[f][2]]) - origin_point[c];
    six_volume[c] += a.dot(b.cross(d));
  }
  for (std::size_t c = 0; c < n_components; ++c) {
    if (six_volume[c] >= 0.0) continue;
    std::size_t first = nf, count = 0;
    for (std::size_t f = 0; f < nf; ++f)
      if (component_face[f] == c) {
        std::swap(tris[f][1], tris[f][2]);
        first = std::min(first, f);
        ++count;
      }
    std::ostringstream w;
    w << "component " << c << " (" << count << " faces, starting at face " << first
      << ") was inside-out (signed volume " << six_volume[c] / 6.0 * scale * scale * scale
      << "); its faces were flipped";
    warnings.push_back(w.str());
  }
  return n_components;
}

/// Faces with (nearly) zero area on the normalized coordinates `unit`, ascending: 2A below
/// ZERO_AREA_RELATIVE times the squared mean edge length. Reported, not refused (the rest state
/// gives them no membrane energy).
std::vector<std::size_t> zero_area_faces(const std::vector<Polygon>& tris, const std::vector<Point3>& unit) {
  const std::size_t nf = tris.size();
  std::vector<std::size_t> zero_area;
  double edge_sum = 0.0;
  for (const Polygon& t : tris)
    for (int k = 0; k < 3; ++k) edge_sum += (to_vec(unit[t[k]]) - to_vec(unit[t[(k + 1) % 3]])).norm();
  const double mean_edge = edge_sum / (3.0 * static_cast<double>(nf));
  const double threshold = ZERO_AREA_RELATIVE * mean_edge * mean_edge;
  for (std::size_t f = 0; f < nf; ++f) {
    const Vec3 a = to_vec(unit[tris[f][0]]);
    const double twice_area = (to_vec(unit[tris[f][1]]) - a).cross(to_vec(unit[tris[f][2]]) - a).norm();
    if (twice_area < threshold) zero_area.push_back(f);
  }
  return zero_area;
}

/// Checks the soup, triangulates and orients it, and builds the mesh (read_input_mesh's work).
Mesh check_soup(const std::string& path, const std::string& ext, std::vector<Point3>& points,
                const std::vector<Polygon>& polygons, const SourceLines& lines, InputReport* report) {
  if (points.empty() || polygons.empty())
    fail(path, "empty mesh", std::to_string(points.size()) + " vertices and " + std::to_string(polygons.size()) + " faces");
  Namer name;
  name.lines = &lines;
  name.points = &points;
  if (ext == "stl") {
    name.stl = true;
    name.first_use.assign(points.size(), {0, 0});
    for (std::size_t f = polygons.size(); f-- > 0;)
      for (std::size_t k = polygons[f].size(); k-- > 0;)
        if (polygons[f][k] < points.size()) name.first_use[polygons[f][k]] = {f, k};
  }

  const std::size_t nv = points.size();
  for (std::size_t i = 0; i < nv; ++i) {
    const Point3& p = points[i];
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z())) {
      std::ostringstream c;
      c << p.x() << ' ' << p.y() << ' ' << p.z();
      fail(path, "non-finite coordinate", name.vertex(i) + " is (" + c.str() + ")");
    }
  }

  // Geometry is tested on normalized coordinates (see the file comment), with the bounding-box
  // centre and diagonal that compute_normalization gives the simulator, so that both see the
  // same numbers. A zero or non-finite diagonal is refused below, after the connectivity checks.
  Vec3 lo = to_vec(points[0]), hi = lo;
  for (const Point3& p : points) {
    lo = lo.cwiseMin(to_vec(p));
    hi = hi.cwiseMax(to_vec(p));
  }
  const Vec3 centre = 0.5 * lo + 0.5 * hi;
  const double diagonal = bounding_diagonal(lo, hi);
  const bool usable_diagonal = std::isfinite(diagonal) && diagonal > 0.0;
  const double scale = usable_diagonal ? diagonal : 1.0;
  std::vector<Point3> unit;
  unit.reserve(nv);
  for (const Point3& p : points) {
    const Vec3 q = (to_vec(p) - centre) / scale;
    unit.emplace_back(q.x(), q.y(), q.z());
  }

  // Per polygon: arity, index range, repeated corners. Then triangulate: polygon i's (first)
  // triangle keeps index i, further triangles of split polygons are appended at the end in
  // polygon order, so a triangle mesh keeps every face index.
  std::vector<Polygon> tris(polygons.size());
  std::vector<std::size_t> origin(polygons.size());
  std::iota(origin.begin(), origin.end(), 0);
  std::vector<Polygon> extra;
  std::vector<std::size_t> extra_origin;
  std::size_t split = 0;

  for (std::size_t i = 0; i < polygons.size(); ++i) {
    const Polygon& p = polygons[i];
    if (p.size() < 3)
      fail(path, "degenerate face", name.polygon(i) + " has " + std::to_string(p.size()) + " vertices");
    for (std::size_t k = 0; k < p.size(); ++k) {
      if (p[k] >= nv)
        fail(path, "vertex index out of range", name.polygon(i) + " refers to vertex " + std::to_string(p[k]) + ", but the file has " + std::to_string(nv) + " vertices (0.." + std::to_string(nv - 1) + ")");
      for (std::size_t l = 0; l < k; ++l)
        if (p[l] == p[k])
          fail(path, "degenerate face", name.polygon(i) + (name.stl ? " uses " + name.vertex(p[k]) + " twice" : " uses vertex " + std::to_string(p[k]) + " twice"));
    }
    if (p.size() == 3) {
      tris[i] = p;
      continue;
    }
    std::vector<Polygon> t = fan_triangulate(p, unit);
    if (t.empty())
      fail(path, "non-convex polygon", name.polygon(i) + " has " + std::to_string(p.size()) + " vertices and no corner from which a fan triangulates it; triangulate it before");
    ++split;
    tris[i] = t[0];
    for (std::size_t k = 1; k < t.size(); ++k) {
      extra.push_back(std::move(t[k]));
      extra_origin.push_back(i);
    }
  }
  tris.insert(tris.end(), extra.begin(), extra.end());
  origin.insert(origin.end(), extra_origin.begin(), extra_origin.end());
  name.origin = &origin;

  // Connectivity, in the order of the problems' importance (each names what it finds).
  check_no_duplicate_face(path, tris, name);
  check_edges(path, tris, nv, name);
  check_no_isolated_vertex(path, tris, nv, name);
  check_vertex_fans(path, tris, nv, name);

  // The soup is now what polygon_soup_to_polygon_mesh requires (in release builds it only
  // asserts that): each condition of PMP::is_polygon_soup_a_polygon_mesh is one of the checks
  // above (tests/mesh/test_soup_checks_vs_cgal.cpp compares them on mutated soups). CGAL's test
  // itself is not run again: its std::set of directed edges is a large share of reading a large
  // mesh (lab/pages/scale.md, lab/history.md). A gap in our checks cannot become undefined
  // behaviour: Euler::add_face returns a null face for a face it cannot add, and align_to_soup
  // refuses a mesh that lost a face or a face's corner order.
  if (!usable_diagonal)
    fail(path, "degenerate mesh", diagonal == 0.0 ? "zero bounding-box diagonal: every vertex is at " + name.point(0)
                                                  : "non-finite bounding-box diagonal: the coordinates span more than a double holds");
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, tris, mesh);
  align_to_soup(mesh, tris);

  std::vector<std::string> warnings;
  const std::size_t n_components = orient_components(mesh, tris, unit, scale, warnings);
  const bool reoriented = !warnings.empty();
  if (reoriented) {
    // Rebuilt from the flipped soup (rare: only inside-out input pays for a second build), so
    // that the mesh is the one a correctly oriented file gives, halfedge for halfedge.
    mesh.clear();
    PMP::polygon_soup_to_polygon_mesh(points, tris, mesh);
    align_to_soup(mesh, tris);
  }
  if (split > 0)
    warnings.push_back(std::to_string(split) + " polygons with more than 3 vertices were fan-triangulated into " +
                       std::to_string(split + extra.size()) + " triangles (the first keeps the polygon's face index, the others are appended after face " + std::to_string(polygons.size() - 1) + ")");

  std::vector<std::size_t> zero_area = zero_area_faces(tris, unit);
  if (!zero_area.empty())
    warnings.push_back(std::to_string(zero_area.size()) + " faces have (nearly) zero area: " + list_indices(zero_area));

  // What the simulator needs beyond a closed manifold (one decision for `check` and `run`): a
  // bounding box to normalize by (checked above, before building the mesh), and a positive
  // volume, measured exactly as the simulator does: validation's enclosed_volume is this same
  // PMP::volume call, made here directly so that mesh/ does not depend on validation/.
  const Positions x = positions_from_mesh(mesh);
  const Positions unit_x = normalize(x, compute_normalization(x));
  const double unit_volume = PMP::volume(mesh, CGAL::parameters::vertex_point_map(EigenPointMap(unit_x)));
  if (!(unit_volume > 0.0)) {
    std::ostringstream v;
    v << unit_volume;
    fail(path, "no positive volume", "the mesh encloses no positive volume (" + v.str() +
                                         " at a unit bounding-box diagonal): it is flat or degenerate");
  }

  if (report) {
    report->vertices = mesh.number_of_vertices();
    report->faces = mesh.number_of_faces();
    report->triangulated_faces = split;
    report->zero_area_faces = std::move(zero_area);
    report->reoriented = reoriented;
    report->components = n_components;
    // In input units; beyond about 1e102 per coordinate the cube of the scale overflows to inf.
    report->volume = unit_volume * scale * scale * scale;
    report->warnings = std::move(warnings);
  }
  return mesh;
}

}  // namespace

Mesh check_input_soup(const std::string& name, std::vector<Point3> points,
                      const std::vector<std::vector<std::size_t>>& polygons, InputReport* report) {
  const SourceLines no_lines;
  return check_soup(name, "", points, polygons, no_lines, report);
}

// ================================================================================== read_input_mesh

Mesh read_input_mesh(const std::string& path, InputReport* report) {
  const std::string ext = lower_extension(path);
  std::vector<Point3> points;
  std::vector<Polygon> polygons;
  SourceLines lines;
  // The readers bound every declared count by the file's size; these handlers are the last line
  // of defence, so that no file can end the process with an uncaught exception.
  try {
    if (ext != "off" && ext != "obj" && ext != "ply" && ext != "stl") {
      std::error_code ec;
      if (!fs::exists(path, ec)) fail(path, "cannot open file", "no such file");
      fail(path, "unknown extension", "'." + ext + "' (expected .off, .obj, .ply or .stl)");
    }
    const auto start = std::chrono::steady_clock::now();
    read_polygon_soup(path, ext, points, polygons, lines);
    const auto read = std::chrono::steady_clock::now();
    Mesh mesh = check_soup(path, ext, points, polygons, lines, report);
    if (report) {
      report->read_seconds = std::chrono::duration<double>(read - start).count();
      report->check_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - read).count();
    }
    return mesh;
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail(path, "out of memory", "reading it needs more memory than there is (" + std::to_string(points.size()) +
                                    " vertices and " + std::to_string(polygons.size()) + " faces read)");
  } catch (const std::length_error& e) {
    fail(path, "too large", std::string("a count in the file is beyond what can be stored (") + e.what() + ")");
  } catch (const std::ios_base::failure& e) {
    fail(path, "cannot read file", e.what());
  } catch (const std::out_of_range& e) {
    fail(path, "parse error", std::string("a value is out of range (") + e.what() + ")");
  } catch (const std::invalid_argument& e) {
    fail(path, "parse error", std::string("a value is not a number (") + e.what() + ")");
  }
}

}  // namespace shellcontract
