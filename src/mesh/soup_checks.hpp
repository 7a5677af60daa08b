// The connectivity checks of an input polygon soup (private to src/mesh): each refuses a soup that
// is not a closed, manifold, consistently oriented triangle mesh with an InputError that names the
// problem and where the file shows it (Namer). read_input_mesh runs them before CGAL builds the
// mesh (io.cpp's header comment says why ours and not PMP::is_polygon_soup_a_polygon_mesh alone).
#pragma once

#include <cstddef>
#include <iomanip>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "shellcontract/core/error.hpp"
#include "shellcontract/mesh/off_scan.hpp"
#include "shellcontract/mesh/surface_mesh.hpp"

namespace shellcontract::soup {

using Polygon = std::vector<std::size_t>;

/// How many indices a warning or an error message lists before "...".
constexpr std::size_t MAX_LISTED = 10;

/// Thrown messages all read "<file>: <problem>: <where and details>", so that a user (and a
/// test) finds the problem name and its place in a fixed spot.
[[noreturn]] inline void fail(const std::string& path, const std::string& problem, const std::string& details) {
  throw InputError(path + ": " + problem + ": " + details);
}

inline std::string list_indices(const std::vector<std::size_t>& ids) {
  std::string s;
  for (std::size_t i = 0; i < ids.size() && i < MAX_LISTED; ++i) s += (i ? ", " : "") + std::to_string(ids[i]);
  if (ids.size() > MAX_LISTED) s += ", ...";
  return s;
}

/// Names vertices, faces and edges in messages, the way the file shows them: with their line
/// when known; for STL, which has no vertex numbers (CGAL merges equal corners into numbered
/// points), by facet number and coordinates.
struct Namer {
  const SourceLines* lines = nullptr;
  const std::vector<Point3>* points = nullptr;
  const std::vector<std::size_t>* origin = nullptr;  ///< input polygon of each output face
  bool stl = false;
  std::vector<std::pair<std::size_t, std::size_t>> first_use;  ///< STL: (facet, corner) where point i first appears

  std::string point(std::size_t v) const {
    std::ostringstream s;
    s << std::setprecision(9) << '(' << (*points)[v].x() << ", " << (*points)[v].y() << ", " << (*points)[v].z() << ')';
    return s.str();
  }
  std::string vertex(std::size_t v) const {
    if (stl) {
      std::string s = "the point " + point(v);
      if (v < first_use.size()) s += " (corner " + std::to_string(first_use[v].second) + " of facet " + std::to_string(first_use[v].first) + ")";
      return s;
    }
    std::string s = "vertex " + std::to_string(v);
    if (v < lines->vertex_line.size()) s += " (line " + std::to_string(lines->vertex_line[v]) + ")";
    return s;
  }
  /// Polygon i of the input (before triangulation).
  std::string polygon(std::size_t i) const {
    std::string s = (stl ? "facet " : "face ") + std::to_string(i);
    if (i < lines->face_line.size()) s += " (line " + std::to_string(lines->face_line[i]) + ")";
    return s;
  }
  /// Face f of the triangulated mesh.
  std::string face(std::size_t f) const {
    const std::size_t p = (*origin)[f];
    if (p == f) return polygon(f);
    std::string s = "face " + std::to_string(f) + " (part of input polygon " + std::to_string(p) + ")";
    if (p < lines->face_line.size()) s += " (line " + std::to_string(lines->face_line[p]) + ")";
    return s;
  }
  std::string edge(std::size_t a, std::size_t b) const {
    if (stl) return "the edge from " + point(a) + " to " + point(b);
    return "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")";
  }
};

/// Duplicate faces (same three vertices in any order) would make a zero-volume double sheet.
void check_no_duplicate_face(const std::string& path, const std::vector<Polygon>& tris, const Namer& name);
/// Edges: each undirected edge must have exactly two faces that traverse it in opposite
/// directions (closed, manifold, consistently oriented).
void check_edges(const std::string& path, const std::vector<Polygon>& tris, std::size_t nv, const Namer& name);
/// Isolated vertices have no mass and no forces; they would be free degrees of freedom. Checked
/// after the edges: an open boundary is the more fundamental problem of a mesh with both.
void check_no_isolated_vertex(const std::string& path, const std::vector<Polygon>& tris, std::size_t nv,
                              const Namer& name);
/// Vertices: the faces around a vertex must form one fan (their link edges one cycle).
void check_vertex_fans(const std::string& path, const std::vector<Polygon>& tris, std::size_t nv, const Namer& name);

}  // namespace shellcontract::soup
