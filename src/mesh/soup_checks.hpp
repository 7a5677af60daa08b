// The connectivity checks of an input polygon soup (private to src/mesh): each refuses a soup that
// is not a closed, manifold, consistently oriented triangle mesh with an InputError that names the
// problem and where the file shows it (Namer). read_input_mesh runs them before CGAL builds the
// mesh (io.cpp's header comment says why ours and not PMP::is_polygon_soup_a_polygon_mesh alone),
// and mesh_from_arrays runs the same checks (soup::accept_triangles) with a Namer that has no
// file lines.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iomanip>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/classic_locale.hpp"
#include "mesh/normalization.hpp"
#include "mesh/off_scan.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/face_error.hpp"
#include "shellcontract/mesh.hpp"

namespace shellcontract::soup {

using Polygon = std::vector<std::size_t>;

/// How many indices a warning or an error message lists before "...".
constexpr std::size_t MAX_LISTED = 10;

/// Thrown messages all read "<file>: <problem>: <where and details>", so that a user (and a
/// test) finds the problem name and its place in a fixed spot.
[[noreturn]] inline void fail(const std::string& path, const std::string& problem, const std::string& details) {
  throw InputError(path + ": " + problem + ": " + details);
}

/// fail, for a problem of particular faces: a FaceListError that carries their triangle indices
/// (all of them, where the message lists only the first MAX_LISTED).
[[noreturn]] inline void fail_faces(const std::string& path, const std::string& problem, const std::string& details,
                                    std::vector<std::size_t> faces) {
  throw FaceListError(path + ": " + problem + ": " + details, std::move(faces));
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
  /// Per vertex of the checked soup, its number in the file (and in `points`, `lines`,
  /// `first_use`); none: the same. A soup welded at its seams is checked on its welded vertices
  /// and names each by its first copy (seam_weld.cpp), so that its refusal is in the file's terms.
  const std::vector<std::size_t>* vertex_number = nullptr;

  std::size_t number(std::size_t v) const { return vertex_number ? (*vertex_number)[v] : v; }
  std::string point(std::size_t v) const {
    const Point3& p = (*points)[number(v)];
    ClassicOStringStream s;
    s << std::setprecision(9) << '(' << p.x() << ", " << p.y() << ", " << p.z() << ')';
    return s.str();
  }
  std::string vertex(std::size_t v) const {
    const std::size_t n = number(v);
    if (stl) {
      std::string s = "the point " + point(v);
      if (n < first_use.size())
        s += " (corner " + std::to_string(first_use[n].second) + " of facet " +
             std::to_string(first_use[n].first) + ")";
      return s;
    }
    std::string s = "vertex " + std::to_string(n);
    if (n < lines->vertex_line.size()) s += " (line " + std::to_string(lines->vertex_line[n]) + ")";
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
    return "edge (" + std::to_string(number(a)) + ", " + std::to_string(number(b)) + ")";
  }
};

/// Points closer than this fraction of the bounding-box diagonal are near-duplicates: one vertex
/// written twice with float noise (CAD and STL exporters), far below any edge a simulation could
/// resolve. The open-boundary refusal names them and `repair` merges them (docs/design/repair.md).
constexpr double NEAR_DUPLICATE_RELATIVE = 1e-10;

/// For an open-boundary refusal of the edge (a, b): "; vertex A has a near-duplicate, vertex C, D
/// away ...; 'shellcontract repair' merges them", when a point of the file other than a or b lies
/// within NEAR_DUPLICATE_RELATIVE of the diagonal of a or b, and not at the same position (the
/// crack such copies leave is what the refusal met); else empty. Linear in the points: only on the
/// refusal's path.
inline std::string near_duplicate_hint(const Namer& name, std::size_t a, std::size_t b) {
  if (!name.points || name.points->empty()) return "";
  const std::vector<Point3>& p = *name.points;
  Vec3 lo(p[0].x(), p[0].y(), p[0].z()), hi = lo;
  for (const Point3& q : p) {
    lo = lo.cwiseMin(Vec3(q.x(), q.y(), q.z()));
    hi = hi.cwiseMax(Vec3(q.x(), q.y(), q.z()));
  }
  const double diagonal = bounding_diagonal(lo, hi);  // compute_normalization's
  if (!(diagonal > 0.0) || !std::isfinite(diagonal)) return "";
  const std::size_t na = name.number(a), nb = name.number(b);
  for (const std::size_t v : {na, nb}) {
    if (v >= p.size()) continue;
    for (std::size_t j = 0; j < p.size(); ++j) {
      if (j == na || j == nb) continue;
      const double d =
          std::hypot(std::hypot(p[j].x() - p[v].x(), p[j].y() - p[v].y()), p[j].z() - p[v].z());
      // An exact copy is a seam's, which the reader welds (seam_weld.hpp): not the crack.
      if (!(d > 0.0 && d <= NEAR_DUPLICATE_RELATIVE * diagonal)) continue;
      ClassicOStringStream s;
      s << std::setprecision(3) << "; "
        << (name.stl ? "the point " + name.point(v == na ? a : b) : "vertex " + std::to_string(v))
        << " has a near-duplicate"
        << (name.stl ? std::string() : ", vertex " + std::to_string(j) + ",") << " " << d
        << " away (" << d / diagonal
        << " of the bounding-box diagonal): the crack between such copies is the opening; "
           "'shellcontract repair' merges points closer than "
        << NEAR_DUPLICATE_RELATIVE << " of the diagonal";
      return s.str();
    }
  }
  return "";
}

/// Duplicate faces (same three vertices in any order) would make a zero-volume double sheet.
void check_no_duplicate_face(const std::string& path, const std::vector<Polygon>& tris, const Namer& name);
/// Isolated vertices have no mass and no forces; they would be free degrees of freedom. Checked
/// after the edges: an open boundary is the more fundamental problem of a mesh with both.
void check_no_isolated_vertex(const std::string& path, const std::vector<Polygon>& tris, std::size_t nv,
                              const Namer& name);

// The two checks below are templates over the triangle list (a vector of Polygon or of
// std::array<std::size_t, 3>).

/// Edges: each undirected edge must have exactly two faces that traverse it in opposite
/// directions (closed, manifold, consistently oriented).
template <class Tris>
void check_edges(const std::string& path, const Tris& tris, std::size_t nv, const Namer& name) {
  const std::size_t nf = tris.size();
  // One record per half-edge, sorted by undirected edge: the uses of an edge are one run
  // (a hash map of vectors costs an allocation per edge; lab/history.md).
  struct EdgeUse {
    std::uint64_t key;  // undirected edge
    std::size_t face;
    bool forward;  // traversed from the smaller to the larger vertex index
    bool operator<(const EdgeUse& o) const { return key != o.key ? key < o.key : face < o.face; }
  };
  auto key = [nv](std::size_t a, std::size_t b) { return static_cast<std::uint64_t>(std::min(a, b)) * nv + std::max(a, b); };
  // Sorted by counting on the smaller vertex, then each vertex's few uses by (key, face): the
  // order one std::sort of all uses gives, in linear time (the sort was most of this check).
  std::vector<std::size_t> start(nv + 1, 0);
  bool in_range = true;
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const std::size_t low = std::min<std::size_t>(tris[f][k], tris[f][(k + 1) % 3]);
      in_range = in_range && low < nv;
      if (in_range) ++start[low + 1];
    }
  std::vector<EdgeUse> uses_sorted(3 * nf);
  if (in_range) {
    for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const std::size_t a = tris[f][k], b = tris[f][(k + 1) % 3];
        uses_sorted[fill[std::min(a, b)]++] = {key(a, b), f, a < b};
      }
    for (std::size_t v = 0; v < nv; ++v)
      std::sort(uses_sorted.begin() + static_cast<std::ptrdiff_t>(start[v]), uses_sorted.begin() + static_cast<std::ptrdiff_t>(start[v + 1]));
  } else {  // an index past the vertices (callers check first): the plain sort
    for (std::size_t f = 0, i = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k, ++i) {
        const std::size_t a = tris[f][k], b = tris[f][(k + 1) % 3];
        uses_sorted[i] = {key(a, b), f, a < b};
      }
    std::sort(uses_sorted.begin(), uses_sorted.end());
  }
  // One pass over the runs: a valid mesh (the common case) has only runs of two opposite uses
  // and needs no per-edge search. Only when some run is bad is the first problem looked up in
  // face order (below), so that the message does not depend on the sort.
  bool all_fine = uses_sorted.size() % 2 == 0;
  for (std::size_t i = 0; all_fine && i < uses_sorted.size(); i += 2)
    all_fine = i + 1 < uses_sorted.size() && uses_sorted[i].key == uses_sorted[i + 1].key &&
               uses_sorted[i].forward != uses_sorted[i + 1].forward &&
               (i + 2 == uses_sorted.size() || uses_sorted[i + 2].key != uses_sorted[i].key);
  if (all_fine) return;
  // Every face on an edge of one kind of problem (MeshError's `faces` lists them all; the
  // message names the first, in face order).
  const auto faces_on_runs = [&](auto bad_run) {
    std::vector<std::size_t> faces;
    for (std::size_t i = 0; i < uses_sorted.size();) {
      std::size_t j = i + 1;
      while (j < uses_sorted.size() && uses_sorted[j].key == uses_sorted[i].key) ++j;
      if (bad_run(i, j))
        for (std::size_t u = i; u < j; ++u) faces.push_back(uses_sorted[u].face);
      i = j;
    }
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    return faces;
  };
  const auto more = [](std::size_t n) {
    return n > 1 ? " (" + std::to_string(n) + " faces in all have such edges)" : std::string();
  };
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const std::size_t a = tris[f][k], b = tris[f][(k + 1) % 3];
      const auto first = std::lower_bound(uses_sorted.begin(), uses_sorted.end(), EdgeUse{key(a, b), 0, false});
      std::size_t count = 0;
      while (first + static_cast<std::ptrdiff_t>(count) != uses_sorted.end() && first[static_cast<std::ptrdiff_t>(count)].key == key(a, b)) ++count;
      if (count == 2 && first[0].forward != first[1].forward) continue;
      const std::string edge = name.edge(a, b);
      if (count == 1) {
        std::vector<std::size_t> open = faces_on_runs([](std::size_t i, std::size_t j) { return j - i == 1; });
        const std::string all = more(open.size());
        fail_faces(path, "open boundary",
                   edge + " of " + name.face(f) +
                       " has no neighbouring face (boundary edge between " +
                       (name.stl ? name.vertex(a) + " and " + name.vertex(b)
                                 : "vertex " + std::to_string(name.number(a)) + " and vertex " +
                                       std::to_string(name.number(b))) +
                       "); the mesh must be closed" + all + near_duplicate_hint(name, a, b),
                   std::move(open));
      }
      if (count > 2) {
        std::vector<std::size_t> sharing(count);
        for (std::size_t u = 0; u < count; ++u) sharing[u] = first[static_cast<std::ptrdiff_t>(u)].face;
        std::string fs_list;
        for (std::size_t u = 0; u < count && u < MAX_LISTED; ++u) fs_list += (u ? ", " : "") + std::to_string(sharing[u]);
        std::vector<std::size_t> crowded = faces_on_runs([](std::size_t i, std::size_t j) { return j - i > 2; });
        fail_faces(path, "non-manifold edge", name.edge(std::min(a, b), std::max(a, b)) + " is shared by " + std::to_string(count) + " faces (" + fs_list + "), at most 2 allowed" + more(crowded.size()), std::move(crowded));
      }
      std::vector<std::size_t> flipped = faces_on_runs([&](std::size_t i, std::size_t j) {
        return j - i == 2 && uses_sorted[i].forward == uses_sorted[i + 1].forward;
      });
      const std::string all = more(flipped.size());
      fail_faces(path, "inconsistent orientation", name.face(first[0].face) + " and " + name.face(first[1].face) + " traverse " + edge + " in the same direction (the surface is not consistently oriented there)" + all, std::move(flipped));
    }
}

/// Vertices: the faces around a vertex must form one fan (their link edges one cycle). With
/// manifold, consistently oriented edges, each link vertex has exactly one successor. A vertex
/// that fails is refused with all its faces (a FaceListError, in face order).
template <class Tris>
void check_vertex_fans(const std::string& path, const Tris& tris, std::size_t nv, const Namer& name) {
  // Each vertex's link edges in one flat array (offsets by vertex, faces in file order within a
  // vertex): one allocation instead of one per vertex.
  std::vector<std::size_t> start(nv + 1, 0);
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) ++start[t[k] + 1];
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::pair<std::size_t, std::size_t>> links(start[nv]);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) links[fill[t[k]]++] = {t[(k + 1) % 3], t[(k + 2) % 3]};
  for (std::size_t v = 0; v < nv; ++v) {
    const auto b = links.begin() + static_cast<std::ptrdiff_t>(start[v]);
    const auto e = links.begin() + static_cast<std::ptrdiff_t>(start[v + 1]);
    const auto size = static_cast<std::size_t>(e - b);
    if (size == 0) continue;  // isolated vertices are reported by their own check
    std::size_t steps = 0, cur = b->second;
    while (cur != b->first && steps <= size) {
      const auto it = std::find_if(b, e, [cur](const auto& l) { return l.first == cur; });
      if (it == e) break;  // cannot happen after the edge checks; never dereference end
      cur = it->second;
      ++steps;
    }
    if (steps + 1 == size) continue;
    // The faces around the vertex, as the refusal's faces: a front end (the Blender add-on) shows
    // the pinch by them. Found by a scan of all faces, once, for the refusal only.
    std::vector<std::size_t> around;
    for (std::size_t f = 0; f < tris.size(); ++f)
      if (tris[f][0] == v || tris[f][1] == v || tris[f][2] == v) around.push_back(f);
    fail_faces(path, "non-manifold vertex", name.vertex(v) + ": its " + std::to_string(size) + " faces form several fans (the fan through its first face has " + std::to_string(steps + 1) + "); the surface pinches there", std::move(around));
  }
}

}  // namespace shellcontract::soup
