// A checked Mesh from a triangle soup in memory. The checks, their order and their messages follow
// read_input_mesh (src/mesh/io.cpp) for a triangle soup, so that an array and a file with the
// same content are accepted or refused alike; a file's extras (lines, polygon triangulation) do
// not apply. The edge and fan checks (soup_checks.hpp) and the mesh, orientation and zero areas
// (soup_geometry.hpp) are the reader's own code; what is here reads the arrays and names faces
// and vertices by their index.
#include "shellcontract/mesh_io.hpp"

#include <CGAL/Polygon_mesh_processing/measure.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/classic_locale.hpp"
#include "core/plural.hpp"
#include "mesh/eigen_point_map.hpp"
#include "mesh/normalization.hpp"
#include "mesh/seam_weld.hpp"
#include "mesh/soup_checks.hpp"
#include "mesh/soup_geometry.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {
namespace {

using Tri = std::array<std::size_t, 3>;

using soup::fail;
using soup::fail_faces;

std::string face_name(std::size_t f) { return "face " + std::to_string(f); }
std::string vertex_name(std::size_t v) { return "vertex " + std::to_string(v); }

/// Faces as size_t triangles; range and repeated-corner checks on the way.
std::vector<Tri> read_faces(const TriangleSoupView& s, const std::string& name) {
  std::vector<Tri> tris(s.num_faces);
  for (std::size_t f = 0; f < s.num_faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      const std::int64_t v = s.faces32 ? s.faces32[3 * f + k] : s.faces64[3 * f + k];
      if (v < 0)
        fail_faces(name, "vertex index out of range", face_name(f) + " has the negative index " + std::to_string(v), {f});
      if (static_cast<std::uint64_t>(v) >= s.num_vertices)
        fail_faces(name, "vertex index out of range", face_name(f) + " refers to vertex " + std::to_string(v) + ", but the mesh has " + counted(s.num_vertices, "vertex", "vertices") + " (0.." + std::to_string(s.num_vertices - 1) + ")", {f});
      tris[f][k] = static_cast<std::size_t>(v);
      for (int l = 0; l < k; ++l)
        if (tris[f][l] == tris[f][k])
          fail_faces(name, "degenerate face", face_name(f) + " uses vertex " + std::to_string(v) + " twice", {f});
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
      fail_faces(name, "duplicate face", face_name(f) + " has the same vertices (" + std::to_string(key[0]) + ", " + std::to_string(key[1]) + ", " + std::to_string(key[2]) + ") as " + face_name(it->second), {f, it->second});
  }
  std::vector<char> used(nv, 0);
  for (const Tri& t : tris)
    for (std::size_t v : t) used[v] = 1;
  for (std::size_t v = 0; v < nv; ++v)
    if (!used[v]) fail(name, "isolated vertex", vertex_name(v) + " is not used by any face");
}


}  // namespace

Mesh mesh_from_arrays(const TriangleSoupView& soup, const std::string& name, InputReport* report, bool reorient) {
  // An empty soup is an unusable input whatever its pointers (an empty array may have none).
  if (soup.num_vertices == 0 || soup.num_faces == 0)
    fail(name, "empty mesh", counted(soup.num_vertices, "vertex", "vertices") + " and " + counted(soup.num_faces, "face", "faces"));
  if ((soup.faces32 == nullptr) == (soup.faces64 == nullptr))
    throw std::invalid_argument("mesh_from_arrays: set exactly one of faces32 and faces64");
  // A view with a count but no data is the caller's mistake, not a mesh: reading it would crash.
  if (soup.vertices == nullptr)
    throw std::invalid_argument("mesh_from_arrays: vertices is null for " +
                                std::to_string(soup.num_vertices) + " vertices");
  const std::size_t nv = soup.num_vertices;
  std::vector<Point3> points;
  points.reserve(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    const double* p = soup.vertices + 3 * i;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      ClassicOStringStream c;
      c << p[0] << ' ' << p[1] << ' ' << p[2];
      fail(name, "non-finite coordinate", vertex_name(i) + " is (" + c.str() + ")");
    }
    points.emplace_back(p[0], p[1], p[2]);
  }
  std::vector<Tri> tris = read_faces(soup, name);
  std::vector<soup::Polygon> polygons;
  polygons.reserve(tris.size());
  for (const Tri& t : tris) polygons.emplace_back(t.begin(), t.end());
  // The reader's edge and fan checks, with faces and vertices named by their index (no lines).
  // Arrays that are open only along split seams are simulated welded (seam_weld.hpp).
  const SourceLines no_lines;
  std::vector<std::size_t> identity(tris.size());
  std::iota(identity.begin(), identity.end(), std::size_t{0});
  soup::Namer by_index;
  by_index.lines = &no_lines;
  by_index.points = &points;
  by_index.origin = &identity;
  std::optional<soup::SeamWeld> weld;
  try {
    check_duplicates_and_isolated(tris, nv, name);
    soup::check_edges(name, tris, nv, by_index);
    soup::check_vertex_fans(name, tris, nv, by_index);
  } catch (const InputError& refusal) {
    // Or throws the refusal, with what is left after welding.
    weld = soup::weld_seams(name, points, polygons, refusal, by_index);
  }
  std::vector<soup::Polygon> input_polygons;
  if (weld) {
    input_polygons = std::move(polygons);
    polygons = weld->tris;
    points = weld->points;
  }
  // The mesh, its orientation and zero areas as read_input_mesh decides them (soup_geometry.hpp),
  // on coordinates at a unit diagonal: in input units a mesh at 1e160 overflowed the signed
  // volume (its sign lost) and one at 1e-160 underflowed it.
  const soup::UnitPoints normalized = soup::unit_points(points);
  if (!normalized.usable())
    fail(name, "degenerate mesh", normalized.diagonal == 0.0 ? "zero bounding-box diagonal"
                                                             : "non-finite bounding-box diagonal: the coordinates span more than a double holds");
  Mesh mesh = soup::soup_mesh(points, polygons, "mesh_from_arrays");
  std::vector<std::string> warnings;
  // A welded vertex is named by its first copy, as the connectivity refusals name it.
  std::vector<std::size_t> first_copy;
  if (weld) {
    first_copy.resize(weld->points.size());
    for (std::size_t i = weld->welded_of.size(); i-- > 0;) first_copy[weld->welded_of[i]] = i;
  }
  const std::vector<std::size_t>* number = weld ? &first_copy : nullptr;
  const soup::Orientation oriented =
      soup::orient_components(mesh, points, polygons, normalized.unit, normalized.scale, reorient,
                              "mesh_from_arrays", warnings, number);
  if (weld) soup::store_input_corners(mesh, *weld, input_polygons);
  std::vector<std::size_t> zero_area = soup::zero_area_faces(polygons, normalized.unit);
  if (!zero_area.empty())
    warnings.push_back(counted(zero_area.size(), "face", "faces") + one_or_many(zero_area.size(), " has", " have") +
                       " (nearly) zero area: " + soup::list_indices(zero_area));

  // What the simulator needs beyond a closed manifold, decided and measured as read_input_mesh
  // does (a positive volume at a unit diagonal, scaled back).
  const Positions x = positions_from_mesh(mesh);
  // read_input_mesh's measure: the PMP::volume call of validation's enclosed_volume, made here
  // so that mesh/ does not depend on validation/.
  const Positions unit_x = normalize(x, compute_normalization(x));
  const double unit_volume =
      CGAL::Polygon_mesh_processing::volume(mesh, CGAL::parameters::vertex_point_map(EigenPointMap(unit_x)));
  if (reorient && !(unit_volume > 0.0)) {
    ClassicOStringStream v;
    v << unit_volume;
    fail(name, "no positive volume",
         "the mesh encloses no positive volume (" + v.str() +
             " at a unit bounding-box diagonal): it is flat or degenerate" +
             soup::stray_vertices_note(points, number));
  }
  // After the whole's volume, which names a single flat shell as before.
  if (!oriented.flat.empty())
    fail_faces(name, "component with no volume", oriented.flat, oriented.flat_faces);
  if (report) {
    report->vertices = mesh.number_of_vertices();
    report->faces = mesh.number_of_faces();
    report->triangulated_faces = 0;
    report->zero_area_faces = std::move(zero_area);
    report->reoriented = oriented.reoriented;
    report->components = oriented.components;
    report->volume = unit_volume * normalized.diagonal * normalized.diagonal * normalized.diagonal;
    report->warnings = std::move(warnings);
    report->welded_vertices = weld ? weld->copies() : 0;
    report->notes.clear();
    if (weld) report->notes.push_back(soup::weld_note(*weld));
  }
  return mesh;
}

}  // namespace shellcontract
