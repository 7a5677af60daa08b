// A checked Mesh from a triangle soup in memory. The checks, their order and their messages follow
// read_input_mesh (src/mesh/io.cpp) for a triangle soup, so that an array and a file with the
// same content are accepted or refused alike; a file's extras (lines, polygon triangulation) do
// not apply. What is here reads the arrays (coordinates, indices in range, distinct corners) and
// names faces and vertices by their index; the rest of the rule is the reader's own code
// (soup::accept_triangles, soup_geometry.hpp): connectivity, seams, orientation, volume.
#include <array>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/classic_locale.hpp"
#include "core/plural.hpp"
#include "mesh/soup_checks.hpp"
#include "mesh/soup_geometry.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
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
  // The reader's acceptance rule from here on (soup_geometry.hpp), with faces and vertices named
  // by their index (no lines).
  soup::UnitPoints normalized = soup::unit_points(points);
  const SourceLines no_lines;
  std::vector<std::size_t> identity(tris.size());
  std::iota(identity.begin(), identity.end(), std::size_t{0});
  soup::Namer by_index;
  by_index.lines = &no_lines;
  by_index.points = &points;
  by_index.origin = &identity;
  soup::AcceptOptions options;
  options.who = "mesh_from_arrays";
  options.reorient = reorient;
  return soup::accept_triangles(name, points, polygons, normalized, by_index, options, report);
}

}  // namespace shellcontract
