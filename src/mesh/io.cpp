// Reading and checking meshes (architecture.md, data flow: read -> check input); writing is in
// write_mesh.cpp.
//
// Reading goes through a polygon soup, which we check ourselves before
// PMP::polygon_soup_to_polygon_mesh: that function only *asserts* that the soup is a valid
// polygon mesh, and a failed Euler::add_face in a release build silently yields a null face.
// PMP::is_polygon_soup_a_polygon_mesh would say only yes or no; our checks let every message
// name the problem, the face, the vertex and (for OFF and ascii PLY) the line, and they cover
// every condition it tests (see check_soup). CGAL does what needs no message: the mesh, its
// connected components, the volume. PMP::merge_duplicate_polygons_in_polygon_soup and
// orient_polygon_soup would change a file the user must hear about (`repair` uses them, on
// request). The soup keeps the input vertex and face order, which users rely on (textures,
// per-vertex data); read_input_mesh verifies that it was kept.
//
// The soup comes from CGAL::IO::read_STL, from tinygltf checked by gltf_reader.cpp, or from our
// own OBJ, PLY and OFF readers (obj_scan.cpp:
// CGAL 5.5's names no line; ply_reader.cpp: CGAL 5.5's crashes; off_scan.cpp: CGAL's trusts
// declared counts, misreads binary OFF and parses slowly). Every geometric test (triangulation,
// orientation, volume, zero area) runs on coordinates normalized to the bounding-box centre and a
// unit diagonal, so that meshes from 1e-150 to 1e150 get the same answers as at unit scale (no
// overflow or underflow in products of three coordinates).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "core/classic_locale.hpp"
#include "core/memory_error.hpp"
#include "core/plural.hpp"
#include "core/progress_stage.hpp"
#include "mesh/followed_split.hpp"
#include "mesh/formats.hpp"
#include "mesh/polygon_split.hpp"
#include "mesh/read_polygon_soup.hpp"
#include "mesh/soup_checks.hpp"
#include "mesh/soup_geometry.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/face_error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

using soup::fail;
using soup::fail_faces;
using soup::Namer;
using soup::Polygon;

// ------------------------------------------- triangulation (polygons: polygon_split.hpp;
// connectivity: soup_checks.hpp; the mesh, orientation and zero areas: soup_geometry.hpp)

/// The warning for the polygons split into triangles: how many each rule of split_polygon split,
/// since a user who sees an odd fold there needs to know whether a fan, a diagonal or ear
/// clipping made the triangles (docs/design/attributes.md); and, reading with another file's
/// splits (read_input_mesh_following), how many were split as that file's polygon of the same
/// index (`followed`) and how many are not that polygon, split by their own shape (`unfollowed`,
/// counted by rule too), so that a user sees which triangles were checked.
std::string split_warning(std::size_t split, std::size_t triangles,
                          const std::array<std::size_t, soup::SPLIT_RULES>& by_rule,
                          std::size_t polygons, const SplitsToFollow* follow, std::size_t followed,
                          std::size_t unfollowed) {
  static const char* const HOW[soup::SPLIT_RULES] = {
      "by a fan from a corner", "by corner 0's fan (a flat polygon, no normal)",
      "along a folded quad's least folded diagonal", "by ear clipping",
      "by the fan that best follows the polygon's normal"};
  std::string how;
  if (followed > 0)
    how =
        std::to_string(followed) + " as " + follow->file + " splits its polygon of the same index";
  for (std::size_t r = 0; r < by_rule.size(); ++r)
    if (by_rule[r] > 0) how += (how.empty() ? "" : ", ") + std::to_string(by_rule[r]) + " " + HOW[r];
  if (unfollowed > 0)
    how += " (" + std::to_string(unfollowed) + (unfollowed == 1 ? " is" : " are") +
           " not the polygon of the same index in " + follow->file + ")";
  const bool one = split == 1;
  return std::to_string(split) + (one ? " polygon" : " polygons") + " with more than 3 vertices " + (one ? "was" : "were") +
         " split into " + std::to_string(triangles) + " triangles (" + how + "; the first triangle of each keeps the polygon's face index, the others are appended after face " +
         std::to_string(polygons - 1) + ")";
}

/// Checks the soup, triangulates and orients it, and builds the mesh (read_input_mesh's work);
/// with `follow`, polygons are split as read_input_mesh_following says.
Mesh check_soup(const std::string& path, const std::string& ext, std::vector<Point3>& points,
                const std::vector<Polygon>& polygons, const SourceLines& lines, InputReport* report,
                const SplitsToFollow* follow = nullptr) {
  if (points.empty() || polygons.empty())
    fail(path, "empty mesh", counted(points.size(), "vertex", "vertices") + " and " + counted(polygons.size(), "face", "faces"));
  Namer name;
  name.lines = &lines;
  name.points = &points;
  if (is_mesh_format(ext, [](const MeshFormat& f) { return !f.indexed_vertices; })) {
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
      ClassicOStringStream c;
      c << p.x() << ' ' << p.y() << ' ' << p.z();
      fail(path, "non-finite coordinate", name.vertex(i) + " is (" + c.str() + ")");
    }
  }

  // Geometry is tested on normalized coordinates (see the file comment). A zero or non-finite
  // diagonal is refused below, after the connectivity checks.
  soup::UnitPoints normalized = soup::unit_points(points);
  const std::vector<Point3>& unit = normalized.unit;

  // Per polygon: arity, index range, repeated corners. Then triangulate: polygon i's (first)
  // triangle keeps index i, further triangles of split polygons are appended at the end in
  // polygon order, so a triangle mesh keeps every face index.
  std::vector<Polygon> tris(polygons.size());
  std::vector<std::size_t> origin(polygons.size());
  std::iota(origin.begin(), origin.end(), 0);
  std::vector<Polygon> extra;
  std::vector<std::size_t> extra_origin;
  std::size_t split = 0, followed = 0, unfollowed = 0;
  std::array<std::size_t, soup::SPLIT_RULES> by_rule{};  // polygons split by each soup::SplitRule, for the warning

  // Polygons above MAX_SPLIT_CORNERS are left to the loop's own message.
  std::size_t split_work = 0;
  std::vector<std::size_t> large;  // polygons of more than SMALL_SPLIT_CORNERS corners
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    const std::size_t n = polygons[i].size();
    if (n <= soup::SMALL_SPLIT_CORNERS || n > soup::MAX_SPLIT_CORNERS) continue;
    split_work += n * n;
    large.push_back(i);
  }
  if (split_work > soup::MAX_SPLIT_WORK) {
    const std::size_t top = *std::max_element(
        large.begin(), large.end(),
        [&](std::size_t a, std::size_t b) { return polygons[a].size() < polygons[b].size(); });
    fail_faces(path, "polygons too large in all",
               std::to_string(large.size()) + " polygons have more than " +
                   std::to_string(soup::SMALL_SPLIT_CORNERS) + " vertices (the largest: " +
                   name.polygon(top) + ", " + std::to_string(polygons[top].size()) +
                   " vertices); splitting one takes time of the square of its vertices, and theirs "
                   "add up to " +
                   std::to_string(split_work) + ", more than the " +
                   std::to_string(soup::MAX_SPLIT_WORK) + " (ten polygons of " +
                   std::to_string(soup::MAX_SPLIT_CORNERS) +
                   " vertices) that this reader splits into triangles; triangulate them in your "
                   "modelling tool"
                   " (Blender: Face > Triangulate Faces) before using the file",
               large);
  }
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    const Polygon& p = polygons[i];
    if (p.size() < 3)
      fail_faces(path, "degenerate face", name.polygon(i) + " has " + counted(p.size(), "vertex", "vertices"), {i});
    // Before the corner checks below, whose time grows with the square of the corners too.
    if (p.size() > soup::MAX_SPLIT_CORNERS)
      fail_faces(
          path, "polygon too large",
          name.polygon(i) + " has " + std::to_string(p.size()) + " vertices, more than the " +
              std::to_string(soup::MAX_SPLIT_CORNERS) +
              " of the largest polygon this reader splits into triangles; triangulate it in your"
              " modelling tool (Blender: Face > Triangulate Faces) before using the file",
          {i});
    for (std::size_t k = 0; k < p.size(); ++k) {
      if (p[k] >= nv)
        fail_faces(path, "vertex index out of range", name.polygon(i) + " refers to vertex " + std::to_string(p[k]) + ", but the file has " + counted(nv, "vertex", "vertices") + " (0.." + std::to_string(nv - 1) + ")", {i});
      for (std::size_t l = 0; l < k; ++l)
        if (p[l] == p[k])
          fail_faces(path, "degenerate face", name.polygon(i) + (name.stl ? " uses " + name.vertex(p[k]) + " twice" : " uses vertex " + std::to_string(p[k]) + " twice"), {i});
    }
    if (p.size() == 3) {
      tris[i] = p;
      continue;
    }
    std::vector<Polygon> t;
    if (follow != nullptr && i < follow->polygons.size() && i < follow->triangles.size())
      t = soup::split_like(p, follow->polygons[i], follow->triangles[i]);
    if (!t.empty()) {
      ++followed;
    } else {
      soup::SplitRule rule = soup::SplitRule::fan;
      t = soup::split_polygon(p, unit, &rule);
      if (t.empty())
        fail_faces(path, "non-convex polygon",
                   name.polygon(i) + " has " + std::to_string(p.size()) +
                       " vertices, and neither ear clipping nor a fan without a zero-area triangle "
                       "splits it;"
                       " triangulate it in your modelling tool (Blender: Face > Triangulate Faces) "
                       "before using the file",
                   {i});
      ++by_rule[static_cast<std::size_t>(rule)];
      if (follow != nullptr) ++unfollowed;
    }
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

  soup::AcceptOptions options;
  options.who = "read_input_mesh";
  options.gltf = is_mesh_format(ext, &MeshFormat::gltf);
  options.triangulated = split;
  if (split > 0)
    options.split_warning = split_warning(split, split + extra.size(), by_rule, polygons.size(),
                                          follow, followed, unfollowed);
  return soup::accept_triangles(path, points, tris, normalized, name, options, report);
}

}  // namespace

Mesh check_input_soup(const std::string& name, std::vector<Point3> points,
                      const std::vector<std::vector<std::size_t>>& polygons, InputReport* report) {
  const SourceLines no_lines;
  return check_soup(name, "", points, polygons, no_lines, report);
}

// ================================================================================== read_input_mesh

namespace {

/// read_input_mesh, and read_input_mesh_following with `follow`.
Mesh read_mesh(const std::string& path, InputReport* report, const SplitsToFollow* follow) {
  const std::string ext = lower_extension(path);
  std::vector<Point3> points;
  std::vector<Polygon> polygons;
  SourceLines lines;
  // The readers bound every declared count by the file's size; these handlers are the last line
  // of defence, so that no file can end the process with an uncaught exception.
  try {
    require_mesh_extension(path, ext);  // before "reading PATH"
    const auto start = std::chrono::steady_clock::now();
    progress_stage("reading " + path);
    std::vector<std::string> read_warnings;  // lines after an OFF's declared faces
    std::vector<std::string> read_notes;     // a glTF's morph targets, not applied
    read_polygon_soup(path, ext, points, polygons, lines, &read_warnings, MissingVertices::Refuse,
                      &read_notes);
    const auto read = std::chrono::steady_clock::now();
    progress_stage("checking " + path);
    Mesh mesh = [&] {
      try {
        return check_soup(path, ext, points, polygons, lines, report, follow);
      } catch (const FaceListError& e) {
        // Faces left unread (more than the header counts) open the mesh: the refusal says so.
        if (read_warnings.empty()) throw;
        throw FaceListError(std::string(e.what()) + " (" + read_warnings.front() + ")", e.faces());
      } catch (const InputError& e) {
        if (read_warnings.empty()) throw;
        throw InputError(std::string(e.what()) + " (" + read_warnings.front() + ")");
      }
    }();
    if (report) report->warnings.insert(report->warnings.begin(), read_warnings.begin(), read_warnings.end());
    if (report) report->notes.insert(report->notes.begin(), read_notes.begin(), read_notes.end());
    if (report) {
      report->read_seconds = std::chrono::duration<double>(read - start).count();
      report->check_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - read).count();
    }
    return mesh;
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    // Memory, not the file, is short: exit code 3 (README "Exit codes"), not a bad input's 2.
    throw OutOfMemoryError(path + ": out of memory: reading it needs more memory than there is (" +
                           std::to_string(points.size()) + " vertices and " +
                           std::to_string(polygons.size()) + " faces read)");
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

}  // namespace

Mesh read_input_mesh(const std::string& path, InputReport* report) {
  return read_mesh(path, report, nullptr);
}

Mesh read_input_mesh_following(const std::string& path, const SplitsToFollow& follow,
                               InputReport* report) {
  return read_mesh(path, report, &follow);
}

}  // namespace shellcontract
