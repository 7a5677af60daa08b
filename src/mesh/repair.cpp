// Repair of meshes that read_input_mesh refuses (docs/design/repair.md). Every geometric step is
// CGAL Polygon Mesh Processing's; this file orders the steps, counts what each changed and hands
// the result to the one usability check (check_input_soup, the function behind read_input_mesh).
#include "shellcontract/repair.hpp"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/manifoldness.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <algorithm>
#include <array>
#include <boost/iterator/function_output_iterator.hpp>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include "core/plural.hpp"
#include "core/progress_stage.hpp"
#include "mesh/formats.hpp"
#include "mesh/read_polygon_soup.hpp"
#include "mesh/soup_checks.hpp"
#include "mesh/soup_geometry.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Polygon = std::vector<std::size_t>;

/// A closed component whose |volume| at a unit bounding-box diagonal is below this encloses
/// nothing: a flat patch closed by filling its border (two coincident sheets), or a single
/// triangle. Real thin parts of the corpus are orders of magnitude above it.
constexpr double MIN_COMPONENT_VOLUME = 1e-9;

[[noreturn]] void cannot_repair(const std::string& path, const std::string& why) {
  throw InputError(path + ": cannot repair: " + why);
}

/// Faces the report names when it says that faces naming a missing vertex were dropped.
constexpr std::size_t MISSING_VERTEX_FACES_NAMED = 3;

/// Moves each point within soup::NEAR_DUPLICATE_RELATIVE (of a unit diagonal: the points are
/// normalized) of an earlier kept point onto that point, so that CGAL's exact merge below merges
/// it: float noise between two copies of one vertex (1e-12 apart) otherwise leaves a crack that
/// hole filling closes with zero-area faces. Earlier points keep their coordinates, so every kept
/// vertex is still an input vertex. Cells of the tolerance's size: a neighbour is in one of 27.
void snap_near_duplicates(std::vector<Point3>& points) {
  constexpr double tol = soup::NEAR_DUPLICATE_RELATIVE;
  std::map<std::array<std::int64_t, 3>, std::vector<std::size_t>> cells;
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::array<std::int64_t, 3> c;
    for (int k = 0; k < 3; ++k) c[k] = static_cast<std::int64_t>(std::floor(points[i][k] / tol));
    std::size_t found = points.size();
    for (int dx = -1; dx <= 1 && found == points.size(); ++dx)
      for (int dy = -1; dy <= 1 && found == points.size(); ++dy)
        for (int dz = -1; dz <= 1 && found == points.size(); ++dz) {
          const auto cell = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (cell == cells.end()) continue;
          for (const std::size_t j : cell->second)
            if (CGAL::squared_distance(points[i], points[j]) <= tol * tol) {
              found = j;
              break;
            }
        }
    if (found < points.size())
      points[i] = points[found];
    else
      cells[c].push_back(i);
  }
}

/// Polygon soup steps: faces naming a missing vertex, duplicate points and polygons, degenerate
/// polygons (repair_polygon_soup), then a consistent orientation (orient_polygon_soup).
void repair_soup(std::vector<Point3>& points, std::vector<Polygon>& polygons,
                 const SourceLines& lines, RepairReport& r) {
  // CGAL's soup functions index without checking; a face naming a vertex the file lacks (read so
  // by read_polygon_soup's MissingVertices::Keep) is dropped, and said with its line.
  std::vector<Polygon> kept;
  kept.reserve(polygons.size());
  for (std::size_t j = 0; j < polygons.size(); ++j) {
    if (std::none_of(polygons[j].begin(), polygons[j].end(),
                     [&](std::size_t v) { return v >= points.size(); })) {
      kept.push_back(std::move(polygons[j]));
      continue;
    }
    if (++r.missing_vertex_faces_dropped <= MISSING_VERTEX_FACES_NAMED)
      r.missing_vertex_faces.push_back(
          "face " + std::to_string(j) +
          (j < lines.face_line.size() ? ", line " + std::to_string(lines.face_line[j]) : ""));
  }
  polygons = std::move(kept);
  const std::size_t n_polygons = polygons.size();
  snap_near_duplicates(points);
  r.duplicate_points_merged = PMP::merge_duplicate_points_in_polygon_soup(points, polygons);
  PMP::repair_polygon_soup(points, polygons);
  r.soup_polygons_removed = n_polygons > polygons.size() ? n_polygons - polygons.size() : 0;
  const std::size_t n_points = points.size();
  PMP::orient_polygon_soup(points, polygons);
  r.points_duplicated_to_orient = points.size() - n_points;
}

/// Mesh steps before hole filling: triangulation, stitching, degenerate and isolated removal.
void clean_mesh(Mesh& mesh, RepairReport& r) {
  for (const FaceIndex f : mesh.faces())
    if (mesh.degree(f) > 3) ++r.polygons_triangulated;
  PMP::triangulate_faces(mesh);
  r.border_edges_stitched = PMP::stitch_borders(mesh);
  PMP::duplicate_non_manifold_vertices(mesh);
  const std::size_t triangles = mesh.number_of_faces();
  // Both return false when some degeneracy could not be removed; what is left is judged by the
  // usability check at the end, so the flag is not needed here.
  PMP::remove_degenerate_edges(mesh);
  PMP::remove_degenerate_faces(mesh);
  r.degenerate_faces_removed = triangles > mesh.number_of_faces() ? triangles - mesh.number_of_faces() : 0;
  r.isolated_vertices_removed = PMP::remove_isolated_vertices(mesh);
}

std::size_t border_length(const Mesh& mesh, HalfedgeIndex h) {
  std::size_t n = 0;
  for (HalfedgeIndex c = h;;) {
    ++n;
    c = mesh.next(c);
    if (c == h || n > mesh.number_of_halfedges()) break;
  }
  return n;
}

/// Fills every hole (up to max_edges boundary edges, 0 = all) with triangulate_refine_and_fair_hole.
void fill_holes(Mesh& mesh, std::size_t max_edges, RepairReport& r) {
  std::vector<HalfedgeIndex> borders;
  PMP::extract_boundary_cycles(mesh, std::back_inserter(borders));
  progress_stage("filling " + counted(borders.size(), "hole", "holes"));
  std::set<FaceIndex> filled;
  for (const HalfedgeIndex h : borders) {
    if (!mesh.is_border(h)) continue;  // an earlier fill closed it (cannot happen; be safe)
    const std::size_t edges = border_length(mesh, h);
    if (max_edges > 0 && edges > max_edges) {
      ++r.holes_unfilled;
      continue;
    }
    std::vector<FaceIndex> faces;
    std::vector<VertexIndex> vertices;
    const bool faired = std::get<0>(PMP::triangulate_refine_and_fair_hole(
        mesh, h, std::back_inserter(faces), std::back_inserter(vertices)));
    if (faces.empty()) {
      ++r.holes_unfilled;
      continue;
    }
    ++r.holes_filled;
    r.hole_faces_added += faces.size();
    r.hole_vertices_added += vertices.size();
    r.largest_hole_edges = std::max(r.largest_hole_edges, edges);
    if (!faired) ++r.holes_not_faired;
    filled.insert(faces.begin(), faces.end());
  }
  // A fill can cut through the surface (a faired cap bulging into a nearby part): counted so the
  // user knows; the usability check does not refuse self-intersections, and neither does this.
  if (filled.empty()) return;
  progress_stage("checking the fills for self-intersections");
  // Counted as found, not held: a mesh whose parts pass through each other has pairs in the
  // square of its faces (validation.hpp, for_each_self_intersection).
  const auto count = [&](const std::pair<FaceIndex, FaceIndex>& p) {
    if (filled.count(p.first) || filled.count(p.second)) ++r.hole_self_intersections;
  };
  PMP::self_intersections(mesh, boost::make_function_output_iterator(count));
}

/// Removes the components that are still open or enclose (almost) no volume (the component
/// policy of docs/design/repair.md), then orients each remaining component outward.
void keep_closed_components(Mesh& mesh, RepairReport& r) {
  auto component = mesh.add_property_map<FaceIndex, std::size_t>("f:repair_component", 0).first;
  const std::size_t n = PMP::connected_components(mesh, component);
  std::vector<char> open(n, 0);
  std::vector<double> six_volume(n, 0.0);
  std::vector<std::size_t> faces(n, 0);
  for (const HalfedgeIndex h : mesh.halfedges())
    if (mesh.is_border(h)) open[component[mesh.face(mesh.opposite(h))]] = 1;
  for (const FaceIndex f : mesh.faces()) {
    const HalfedgeIndex h = mesh.halfedge(f);
    const Point3& a = mesh.point(mesh.source(h));
    const Point3& b = mesh.point(mesh.target(h));
    const Point3& c = mesh.point(mesh.target(mesh.next(h)));
    six_volume[component[f]] += CGAL::scalar_product(a - CGAL::ORIGIN, CGAL::cross_product(b - CGAL::ORIGIN, c - CGAL::ORIGIN));
    ++faces[component[f]];
  }
  std::vector<std::size_t> drop;
  for (std::size_t c = 0; c < n; ++c)
    if (open[c] || !(std::abs(six_volume[c]) / 6.0 >= MIN_COMPONENT_VOLUME)) {
      drop.push_back(c);
      ++r.components_dropped;
      r.faces_dropped += faces[c];
    }
  if (!drop.empty()) PMP::remove_connected_components(mesh, drop, component);
  mesh.remove_property_map(component);
  mesh.collect_garbage();
  if (mesh.number_of_faces() > 0) PMP::orient(mesh);
}

}  // namespace

std::vector<std::string> RepairReport::summary_lines() const {
  std::vector<std::string> out;
  if (already_usable) return {"the mesh was usable as read: nothing changed"};
  auto line = [&out](std::size_t n, const char* one, const char* many) {
    if (n > 0) out.push_back(counted(n, one, many));
  };
  if (missing_vertex_faces_dropped > 0) {
    std::string named;
    for (const std::string& f : missing_vertex_faces) named += (named.empty() ? "" : "; ") + f;
    if (missing_vertex_faces_dropped > missing_vertex_faces.size())
      named += "; " + std::to_string(missing_vertex_faces_dropped - missing_vertex_faces.size()) +
               " more";
    out.push_back(counted(missing_vertex_faces_dropped, "face naming a missing vertex dropped",
                          "faces naming a missing vertex dropped") +
                  " (" + named + ")");
  }
  line(duplicate_points_merged, "duplicate point merged", "duplicate points merged");
  line(soup_polygons_removed, "duplicate, degenerate or invalid polygon removed",
       "duplicate, degenerate or invalid polygons removed");
  line(points_duplicated_to_orient, "point split at a non-manifold place to orient the faces",
       "points split at non-manifold places to orient the faces");
  line(polygons_triangulated, "polygon triangulated", "polygons triangulated");
  line(border_edges_stitched, "border edge pair stitched", "border edge pairs stitched");
  line(degenerate_faces_removed, "degenerate face removed", "degenerate faces removed");
  line(isolated_vertices_removed, "isolated vertex removed", "isolated vertices removed");
  if (holes_filled > 0)
    out.push_back(counted(holes_filled, "hole", "holes") + " filled with " + counted(hole_faces_added, "face", "faces") +
                  " and " + counted(hole_vertices_added, "vertex", "vertices") + " (largest: " +
                  counted(largest_hole_edges, "boundary edge", "boundary edges") +
                  (holes_not_faired > 0 ? ", " + std::to_string(holes_not_faired) + " not faired" : "") + ")");
  line(holes_unfilled, "hole left open", "holes left open");
  line(hole_self_intersections, "self-intersecting face pair involves the holes' new faces (kept: not refused)",
       "self-intersecting face pairs involve the holes' new faces (kept: not refused)");
  if (components_dropped > 0)
    out.push_back(counted(components_dropped, "component", "components") + " dropped (" +
                  counted(faces_dropped, "face", "faces") + "): still open, or enclosing no volume");
  return out;
}

Mesh repair_input_mesh(const std::string& path, RepairReport* report, std::size_t max_hole_edges) {
  RepairReport local;
  RepairReport& r = report ? *report : local;
  r = RepairReport{};
  // A file of no format of the table is refused as check refuses it: repair cannot read it
  // either (its message had named the file twice: "F: cannot repair: ... (F: unknown extension").
  try {
    require_mesh_extension(path, lower_extension(path));
  } catch (const InputError& e) {
    r.input_problem = r.failure = e.what();
    throw;
  }
  try {
    Mesh mesh = read_input_mesh(path, &r.input_report);
    r.already_usable = r.usable = true;
    r.input_vertices = r.input_report.vertices;
    return mesh;
  } catch (const InputError& e) {
    r.input_problem = e.what();
  }

  std::vector<Point3> points;
  std::vector<Polygon> polygons;
  SourceLines lines;
  try {
    progress_stage("reading " + path + " as polygons to repair");
    // Faces naming a missing vertex are read, for repair_soup to drop (repair.md, step 4).
    read_polygon_soup(path, lower_extension(path), points, polygons, lines, nullptr,
                      MissingVertices::Keep);
  } catch (const InputError& e) {
    r.failure = std::string("the file cannot be read (") + e.what() + ")";
    cannot_repair(path, r.failure);
  }
  r.input_vertices = points.size();
  // A few stray vertices far from the rest (an exporter's vertex at the origin) make a full shape
  // flat, and repair cannot help; said with the refusal below, in the file's numbering.
  const std::string strays = soup::stray_vertices_note(points);
  r.input_polygons = polygons.size();
  if (polygons.empty()) {
    r.failure = "the file has no faces (" + std::to_string(points.size()) +
                " points): a point set is not a surface ('shellcontract reconstruct' builds one from oriented points)";
    cannot_repair(path, r.failure);
  }
  for (const Point3& p : points)
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z())) {
      r.failure = "it has a non-finite coordinate (the file is corrupt, not a surface with defects)";
      cannot_repair(path, r.failure);
    }

  // Normalize to the bounding-box centre and a unit diagonal (read_input_mesh does the same), so
  // that fairing and the volume threshold see the same numbers at any scale.
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = hi[k] = points[0][k];
  for (const Point3& p : points)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  double centre[3], diagonal = 0.0;
  for (int k = 0; k < 3; ++k) {
    centre[k] = 0.5 * lo[k] + 0.5 * hi[k];
    diagonal = std::hypot(diagonal, hi[k] - lo[k]);
  }
  if (!(diagonal > 0.0) || !std::isfinite(diagonal)) {
    r.failure = "its bounding box has a zero or non-finite diagonal";
    cannot_repair(path, r.failure);
  }
  // Repair merges, splits and adds vertices but moves none of the input's (fairing moves only a
  // fill's new vertices), and (x - c) / d * d + c is not always x: each input point is found again
  // by its normalized position, so that the vertices the repair kept keep their coordinates.
  std::map<std::array<double, 3>, Point3> input_point;
  for (Point3& p : points) {
    const Point3 unit((p.x() - centre[0]) / diagonal, (p.y() - centre[1]) / diagonal, (p.z() - centre[2]) / diagonal);
    input_point.emplace(std::array<double, 3>{unit.x(), unit.y(), unit.z()}, p);
    p = unit;
  }

  Mesh mesh;
  try {
    progress_stage("repairing the polygons (duplicates, degenerate faces, orientation)");
    repair_soup(points, polygons, lines, r);
    if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
      r.failure = "the faces do not form a polygon mesh even after orienting the soup";
      cannot_repair(path, r.failure);
    }
    PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
    progress_stage("stitching the borders");
    clean_mesh(mesh, r);
    fill_holes(mesh, max_hole_edges, r);
    progress_stage("dropping open components, orienting");
    keep_closed_components(mesh, r);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    r.failure = std::string("a CGAL repair step failed (") + e.what() + ")";
    cannot_repair(path, r.failure);
  }
  if (mesh.number_of_faces() == 0) {
    r.failure = "no component encloses a volume after repair (" +
                counted(r.components_dropped, "component", "components") +
                " dropped: still open, or flat)" + strays;
    cannot_repair(path, r.failure);
  }

  // Back to a soup in input units (the input's own coordinates where the vertex is the input's),
  // then the one usability check.
  progress_stage("checking the repaired mesh");
  std::vector<Point3> out_points;
  std::map<VertexIndex, std::size_t> index;
  for (const VertexIndex v : mesh.vertices()) {
    const Point3& p = mesh.point(v);
    index[v] = out_points.size();
    const auto known = input_point.find({p.x(), p.y(), p.z()});
    if (known != input_point.end())
      out_points.push_back(known->second);
    else
      out_points.emplace_back(p.x() * diagonal + centre[0], p.y() * diagonal + centre[1], p.z() * diagonal + centre[2]);
  }
  std::vector<Polygon> out_faces;
  out_faces.reserve(mesh.number_of_faces());
  for (const FaceIndex f : mesh.faces()) {
    Polygon t;
    for (const VertexIndex v : mesh.vertices_around_face(mesh.halfedge(f))) t.push_back(index.at(v));
    out_faces.push_back(std::move(t));
  }
  try {
    Mesh result = check_input_soup(path + " (after repair)", std::move(out_points), out_faces, &r.input_report);
    r.usable = true;
    return result;
  } catch (const InputError& e) {
    r.failure = std::string("the repaired mesh is still unusable: ") + e.what();
    cannot_repair(path, r.failure);
  }
}

}  // namespace shellcontract
