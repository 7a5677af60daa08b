// Reading and checking meshes (design.md, data flow: read -> check input); writing is in
// write_mesh.cpp.
//
// Reading goes through a polygon soup (CGAL::IO::read_OFF/OBJ/PLY/STL), which we check
// ourselves before PMP::polygon_soup_to_polygon_mesh: that function only *asserts* that the soup
// is a valid polygon mesh, and a failed Euler::add_face in a release build silently yields a
// null face. Checking the soup also lets every message name the face, the vertex and (for OFF,
// through a small line-based pre-scan) the line. The soup keeps the input vertex and face order,
// which users rely on (textures, per-vertex data); read_input_mesh verifies that it was kept.
#include "shellcontract/mesh/io.hpp"

#include <unistd.h>  // getpid, for unique temporary names

#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <map>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "shellcontract/core/error.hpp"
#include "shellcontract/mesh/eigen_point_map.hpp"
#include "shellcontract/validation/volume.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using Polygon = std::vector<std::size_t>;

/// Faces with 2A below this fraction of the squared mean edge length count as zero-area
/// (relative, so that the test does not depend on the mesh's units).
constexpr double ZERO_AREA_RELATIVE = 1e-10;
/// How many indices a warning or an error message lists before "...".
constexpr std::size_t MAX_LISTED = 10;

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// Thrown messages all read "<file>: <problem>: <where and details>", so that a user (and a
/// test) finds the problem name and its place in a fixed spot.
[[noreturn]] void fail(const std::string& path, const std::string& problem, const std::string& details) {
  throw InputError(path + ": " + problem + ": " + details);
}

std::string list_indices(const std::vector<std::size_t>& ids) {
  std::string s;
  for (std::size_t i = 0; i < ids.size() && i < MAX_LISTED; ++i) s += (i ? ", " : "") + std::to_string(ids[i]);
  if (ids.size() > MAX_LISTED) s += ", ...";
  return s;
}

// ------------------------------------------------------------------------------------ OFF pre-scan
// CGAL's OFF reader returns a bare `false` on a truncated or garbled file. This scan walks the
// plain-ASCII "OFF" layout line by line (one vertex or face per line, '#' comments) to say which
// line is wrong, and records the line of every vertex and face for later messages. Variants
// (COFF, NOFF, OFF BINARY, ...) are left to CGAL alone.

struct OffLines {
  std::vector<std::size_t> vertex_line;  ///< 1-based line of vertex i; empty if not scanned
  std::vector<std::size_t> face_line;    ///< 1-based line of face i; empty if not scanned
};

class OffScanner {
 public:
  OffScanner(const std::string& path, std::istream& in) : path_(path), in_(in) {}

  OffLines scan() {
    OffLines out;
    std::vector<std::string> t;
    if (!next(t)) fail(path_, "empty file", "no OFF header, the file holds only blank or comment lines");
    const std::size_t header_line = line_;
    if (t[0] != "OFF") {
      const bool variant = t[0].size() > 3 && t[0].compare(t[0].size() - 3, 3, "OFF") == 0;
      if (variant) return out;  // COFF, NOFF, STOFF...: CGAL's reader handles them
      fail(path_, "parse error", "line " + std::to_string(line_) + ": expected the OFF header, found '" + shorten(t[0]) + "'");
    }
    t.erase(t.begin());
    if (!t.empty() && t[0] == "BINARY") return out;
    if (t.empty() && !next(t))
      fail(path_, "truncated file", "the file ends after the OFF header (line " + std::to_string(header_line) + "), before the vertex and face counts");
    if (t.size() < 2)
      fail(path_, "parse error", "line " + std::to_string(line_) + ": expected the vertex, face and edge counts");
    const std::size_t counts_line = line_;
    const std::size_t nv = count(t[0], "vertex count");
    const std::size_t nf = count(t[1], "face count");
    if (nv == 0 || nf == 0)
      fail(path_, "empty mesh", "line " + std::to_string(counts_line) + " announces " + std::to_string(nv) + " vertices and " + std::to_string(nf) + " faces");

    const std::string announced = "the header (line " + std::to_string(counts_line) + ") announces " + std::to_string(nv) + " vertices and " + std::to_string(nf) + " faces";
    out.vertex_line.reserve(nv);
    for (std::size_t i = 0; i < nv; ++i) {
      if (!next(t))
        fail(path_, "truncated file", announced + ", but the file ends after " + std::to_string(i) + " vertices (line " + std::to_string(line_) + ")");
      const std::string where = "vertex " + std::to_string(i) + " (line " + std::to_string(line_) + ")";
      if (t.size() < 3) {
        if (at_end()) fail(path_, "truncated file", announced + ", but the file ends inside " + where);
        fail(path_, "parse error", where + " has " + std::to_string(t.size()) + " numbers, expected 3 coordinates");
      }
      for (int k = 0; k < 3; ++k) {
        char* end = nullptr;
        const double c = std::strtod(t[k].c_str(), &end);
        if (end == t[k].c_str() || *end != '\0')
          fail(path_, "parse error", where + ": '" + shorten(t[k]) + "' is not a number");
        if (!std::isfinite(c))
          fail(path_, "non-finite coordinate", where + " has coordinate " + "xyz"[k] + " = " + t[k]);
      }
      out.vertex_line.push_back(line_);
    }
    out.face_line.reserve(nf);
    for (std::size_t j = 0; j < nf; ++j) {
      if (!next(t))
        fail(path_, "truncated file", announced + ", but the file ends after " + std::to_string(j) + " faces (line " + std::to_string(line_) + ")");
      const std::string where = "face " + std::to_string(j) + " (line " + std::to_string(line_) + ")";
      const std::size_t n = index(t[0], where + ": vertex count");
      if (t.size() < n + 1) {
        if (at_end()) fail(path_, "truncated file", announced + ", but the file ends inside " + where);
        fail(path_, "parse error", where + " announces " + std::to_string(n) + " vertices but lists " + std::to_string(t.size() - 1));
      }
      for (std::size_t k = 1; k <= n; ++k) {
        const std::size_t v = index(t[k], where);
        if (v >= nv)
          fail(path_, "vertex index out of range", where + " refers to vertex " + std::to_string(v) + ", but the file has " + std::to_string(nv) + " vertices (0.." + std::to_string(nv - 1) + ")");
      }
      out.face_line.push_back(line_);
    }
    return out;
  }

 private:
  /// Next non-blank, non-comment line split into tokens; false at end of file.
  bool next(std::vector<std::string>& tokens) {
    std::string s;
    while (std::getline(in_, s)) {
      ++line_;
      const auto hash = s.find('#');
      if (hash != std::string::npos) s.erase(hash);
      std::istringstream ls(s);
      tokens.clear();
      for (std::string w; ls >> w;) tokens.push_back(w);
      if (!tokens.empty()) return true;
    }
    return false;
  }
  bool at_end() {
    in_ >> std::ws;
    return in_.peek() == std::char_traits<char>::eof();
  }
  static std::string shorten(const std::string& s) {
    std::string r = s.size() > 20 ? s.substr(0, 20) + "..." : s;
    for (char& c : r)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) c = '?';
    return r;
  }
  std::size_t index(const std::string& tok, const std::string& where) {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(tok.c_str(), &end, 10);
    if (end == tok.c_str() || *end != '\0' || errno == ERANGE)
      fail(path_, "parse error", where + ": '" + shorten(tok) + "' is not an integer");
    if (v < 0) fail(path_, "vertex index out of range", where + " has the negative index " + tok);
    return static_cast<std::size_t>(v);
  }
  std::size_t count(const std::string& tok, const std::string& what) {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(tok.c_str(), &end, 10);
    if (end == tok.c_str() || *end != '\0' || errno == ERANGE || v < 0)
      fail(path_, "parse error", "line " + std::to_string(line_) + ": " + what + " '" + shorten(tok) + "' is not a non-negative integer");
    return static_cast<std::size_t>(v);
  }

  const std::string& path_;
  std::istream& in_;
  std::size_t line_ = 0;
};

// ------------------------------------------------------------------------------------ soup checks

Vec3 to_vec(const Point3& p) { return Vec3(p.x(), p.y(), p.z()); }

/// Names a face in messages: its index, and where it came from in the file when known.
struct FaceNamer {
  const std::vector<std::size_t>* origin;  ///< input polygon of each output face
  const OffLines* lines;
  std::string operator()(std::size_t f) const {
    std::string s = "face " + std::to_string(f);
    const std::size_t p = (*origin)[f];
    if (p != f) s += " (part of input polygon " + std::to_string(p) + ")";
    if (p < lines->face_line.size()) s += " (line " + std::to_string(lines->face_line[p]) + ")";
    return s;
  }
};

std::string vertex_name(std::size_t v, const OffLines& lines) {
  std::string s = "vertex " + std::to_string(v);
  if (v < lines.vertex_line.size()) s += " (line " + std::to_string(lines.vertex_line[v]) + ")";
  return s;
}

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

struct UnionFind {
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t find(std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void unite(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};

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

}  // namespace

// ================================================================================== read_input_mesh

Mesh read_input_mesh(const std::string& path, InputReport* report) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, "cannot open file", "no such file");
  if (fs::is_directory(path, ec)) fail(path, "cannot open file", "it is a folder");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) fail(path, "cannot open file", std::strerror(errno));
  const std::string ext = lower_extension(path);
  if (ext != "off" && ext != "obj" && ext != "ply" && ext != "stl")
    fail(path, "unknown extension", "'." + ext + "' (expected .off, .obj, .ply or .stl)");
  probe >> std::ws;
  if (probe.peek() == std::char_traits<char>::eof()) fail(path, "empty file", "the file holds no data");
  probe.clear();
  probe.seekg(0);

  OffLines lines;
  if (ext == "off") lines = OffScanner(path, probe).scan();
  probe.close();

  std::vector<Point3> points;
  std::vector<Polygon> polygons;
  bool ok = false;
  // Direct calls rather than read_polygon_soup: the extension is already lower-cased and known.
  if (ext == "off") ok = CGAL::IO::read_OFF(path, points, polygons);
  else if (ext == "obj") ok = CGAL::IO::read_OBJ(path, points, polygons);
  else if (ext == "ply") ok = CGAL::IO::read_PLY(path, points, polygons);
  else ok = CGAL::IO::read_STL(path, points, polygons);
  if (!ok)
    fail(path, "parse error", "CGAL could not read it as a ." + ext + " file (truncated file or garbage)");
  if (points.empty() || polygons.empty())
    fail(path, "empty mesh", std::to_string(points.size()) + " vertices and " + std::to_string(polygons.size()) + " faces");

  const std::size_t nv = points.size();
  for (std::size_t i = 0; i < nv; ++i) {
    const Point3& p = points[i];
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z())) {
      std::ostringstream c;
      c << p.x() << ' ' << p.y() << ' ' << p.z();
      fail(path, "non-finite coordinate", vertex_name(i, lines) + " is (" + c.str() + ")");
    }
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
  auto polygon_name = [&](std::size_t i) {
    std::string s = "face " + std::to_string(i);
    if (i < lines.face_line.size()) s += " (line " + std::to_string(lines.face_line[i]) + ")";
    return s;
  };
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    const Polygon& p = polygons[i];
    if (p.size() < 3)
      fail(path, "degenerate face", polygon_name(i) + " has " + std::to_string(p.size()) + " vertices");
    for (std::size_t k = 0; k < p.size(); ++k) {
      if (p[k] >= nv)
        fail(path, "vertex index out of range", polygon_name(i) + " refers to vertex " + std::to_string(p[k]) + ", but the file has " + std::to_string(nv) + " vertices (0.." + std::to_string(nv - 1) + ")");
      for (std::size_t l = 0; l < k; ++l)
        if (p[l] == p[k])
          fail(path, "degenerate face", polygon_name(i) + " uses vertex " + std::to_string(p[k]) + " twice");
    }
    if (p.size() == 3) {
      tris[i] = p;
      continue;
    }
    std::vector<Polygon> t = fan_triangulate(p, points);
    if (t.empty())
      fail(path, "non-convex polygon", polygon_name(i) + " has " + std::to_string(p.size()) + " vertices and no corner from which a fan triangulates it; triangulate it before");
    ++split;
    tris[i] = t[0];
    for (std::size_t k = 1; k < t.size(); ++k) {
      extra.push_back(std::move(t[k]));
      extra_origin.push_back(i);
    }
  }
  tris.insert(tris.end(), extra.begin(), extra.end());
  origin.insert(origin.end(), extra_origin.begin(), extra_origin.end());
  const FaceNamer face_name{&origin, &lines};
  const std::size_t nf = tris.size();

  // Duplicate faces (same three vertices in any order) would make a zero-volume double sheet.
  {
    std::map<std::array<std::size_t, 3>, std::size_t> seen;
    for (std::size_t f = 0; f < nf; ++f) {
      std::array<std::size_t, 3> key{tris[f][0], tris[f][1], tris[f][2]};
      std::sort(key.begin(), key.end());
      const auto [it, inserted] = seen.emplace(key, f);
      if (!inserted)
        fail(path, "duplicate face", face_name(f) + " has the same vertices (" + std::to_string(key[0]) + ", " + std::to_string(key[1]) + ", " + std::to_string(key[2]) + ") as " + face_name(it->second));
    }
  }

  // Isolated vertices have no mass and no forces; they would be free degrees of freedom.
  {
    std::vector<char> used(nv, 0);
    for (const Polygon& t : tris)
      for (std::size_t v : t) used[v] = 1;
    for (std::size_t v = 0; v < nv; ++v)
      if (!used[v]) fail(path, "isolated vertex", vertex_name(v, lines) + " is not used by any face");
  }

  // Edges: each undirected edge must have exactly two faces that traverse it in opposite
  // directions (closed, manifold, consistently oriented).
  {
    // One record per half-edge, sorted by undirected edge: the uses of an edge are one run
    // (a hash map of vectors cost ~0.1 s on bear, an allocation per edge).
    struct EdgeUse {
      std::uint64_t key;  // undirected edge
      std::size_t face;
      bool forward;  // traversed from the smaller to the larger vertex index
      bool operator<(const EdgeUse& o) const { return key != o.key ? key < o.key : face < o.face; }
    };
    auto key = [nv](std::size_t a, std::size_t b) { return static_cast<std::uint64_t>(std::min(a, b)) * nv + std::max(a, b); };
    std::vector<EdgeUse> uses_sorted;
    uses_sorted.reserve(3 * nf);
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const std::size_t a = tris[f][k], b = tris[f][(k + 1) % 3];
        uses_sorted.push_back({key(a, b), f, a < b});
      }
    std::sort(uses_sorted.begin(), uses_sorted.end());
    // Report the first problem in face order, so that the message does not depend on the sort.
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const std::size_t a = tris[f][k], b = tris[f][(k + 1) % 3];
        const auto first = std::lower_bound(uses_sorted.begin(), uses_sorted.end(), EdgeUse{key(a, b), 0, false});
        std::size_t count = 0;
        while (first + static_cast<std::ptrdiff_t>(count) != uses_sorted.end() && first[static_cast<std::ptrdiff_t>(count)].key == key(a, b)) ++count;
        if (count == 2 && first[0].forward != first[1].forward) continue;
        const std::string edge = "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")";
        if (count == 1)
          fail(path, "open boundary", edge + " of " + face_name(f) + " has no neighbouring face (boundary edge between vertex " + std::to_string(a) + " and vertex " + std::to_string(b) + "); the mesh must be closed");
        if (count > 2) {
          std::string fs_list;
          for (std::size_t u = 0; u < count && u < MAX_LISTED; ++u) fs_list += (u ? ", " : "") + std::to_string(first[static_cast<std::ptrdiff_t>(u)].face);
          fail(path, "non-manifold edge", "edge (" + std::to_string(std::min(a, b)) + ", " + std::to_string(std::max(a, b)) + ") is shared by " + std::to_string(count) + " faces (" + fs_list + "), at most 2 allowed");
        }
        fail(path, "inconsistent orientation", face_name(first[0].face) + " and " + face_name(first[1].face) + " traverse " + edge + " in the same direction (the surface is not consistently oriented there)");
      }
  }

  // Vertices: the faces around a vertex must form one fan (their link edges one cycle). With
  // manifold, consistently oriented edges, each link vertex has exactly one successor.
  {
    std::vector<std::vector<std::pair<std::size_t, std::size_t>>> link(nv);
    for (const Polygon& t : tris)
      for (int k = 0; k < 3; ++k) link[t[k]].emplace_back(t[(k + 1) % 3], t[(k + 2) % 3]);
    for (std::size_t v = 0; v < nv; ++v) {
      const auto& l = link[v];
      std::size_t steps = 0, cur = l[0].second;
      while (cur != l[0].first && steps <= l.size()) {
        const auto it = std::find_if(l.begin(), l.end(), [cur](const auto& e) { return e.first == cur; });
        if (it == l.end()) break;  // cannot happen after the edge checks; never dereference end
        cur = it->second;
        ++steps;
      }
      if (steps + 1 != l.size())
        fail(path, "non-manifold vertex", vertex_name(v, lines) + ": its " + std::to_string(l.size()) + " faces form several fans (the fan through its first face has " + std::to_string(steps + 1) + "); the surface pinches there");
    }
  }

  // Components and their orientation: a component with negative signed volume is inside-out
  // and gets flipped (swapping corners 1 and 2 keeps corner 0 first). Each component is taken as
  // its own shell; a nested inner wall of a hollow solid would also be flipped outward.
  std::vector<std::string> warnings;
  UnionFind uf(nv);
  for (const Polygon& t : tris) {
    uf.unite(t[0], t[1]);
    uf.unite(t[1], t[2]);
  }
  std::map<std::size_t, std::size_t> component_of_root;
  for (const Polygon& t : tris) component_of_root.emplace(uf.find(t[0]), component_of_root.size());
  const std::size_t n_components = component_of_root.size();
  std::vector<double> six_volume(n_components, 0.0);
  std::vector<Vec3> origin_point(n_components);
  std::vector<char> has_origin(n_components, 0);
  std::vector<std::size_t> component_face(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const std::size_t c = component_of_root.at(uf.find(tris[f][0]));
    component_face[f] = c;
    // Measured from a point of the component: the closed-surface sum does not depend on the
    // origin, and a nearby one avoids cancellation for meshes far from (0,0,0).
    if (!has_origin[c]) {
      origin_point[c] = to_vec(points[tris[f][0]]);
      has_origin[c] = 1;
    }
    const Vec3 a = to_vec(points[tris[f][0]]) - origin_point[c];
    const Vec3 b = to_vec(points[tris[f][1]]) - origin_point[c];
    const Vec3 d = to_vec(points[tris[f][2]]) - origin_point[c];
    six_volume[c] += a.dot(b.cross(d));
  }
  bool reoriented = false;
  for (std::size_t c = 0; c < n_components; ++c) {
    if (six_volume[c] >= 0.0) continue;
    reoriented = true;
    std::size_t first = nf, count = 0;
    for (std::size_t f = 0; f < nf; ++f)
      if (component_face[f] == c) {
        std::swap(tris[f][1], tris[f][2]);
        first = std::min(first, f);
        ++count;
      }
    std::ostringstream w;
    w << "component " << c << " (" << count << " faces, starting at face " << first
      << ") was inside-out (signed volume " << six_volume[c] / 6.0 << "); its faces were flipped";
    warnings.push_back(w.str());
  }
  if (split > 0)
    warnings.push_back(std::to_string(split) + " polygons with more than 3 vertices were fan-triangulated into " +
                       std::to_string(split + extra.size()) + " triangles (the first keeps the polygon's face index, the others are appended after face " + std::to_string(polygons.size() - 1) + ")");

  // Zero-area faces: reported, not refused (the rest state gives them no membrane energy).
  std::vector<std::size_t> zero_area;
  {
    double edge_sum = 0.0;
    for (const Polygon& t : tris)
      for (int k = 0; k < 3; ++k) edge_sum += (to_vec(points[t[k]]) - to_vec(points[t[(k + 1) % 3]])).norm();
    const double mean_edge = edge_sum / (3.0 * static_cast<double>(nf));
    const double threshold = ZERO_AREA_RELATIVE * mean_edge * mean_edge;
    for (std::size_t f = 0; f < nf; ++f) {
      const Vec3 a = to_vec(points[tris[f][0]]);
      const double twice_area = (to_vec(points[tris[f][1]]) - a).cross(to_vec(points[tris[f][2]]) - a).norm();
      if (twice_area < threshold) zero_area.push_back(f);
    }
  }
  if (!zero_area.empty())
    warnings.push_back(std::to_string(zero_area.size()) + " faces have (nearly) zero area: " + list_indices(zero_area));

  Mesh mesh;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, tris, mesh);
  align_to_soup(mesh, tris);

  if (report) {
    report->vertices = mesh.number_of_vertices();
    report->faces = mesh.number_of_faces();
    report->triangulated_faces = split;
    report->zero_area_faces = std::move(zero_area);
    report->reoriented = reoriented;
    report->components = n_components;
    report->volume = enclosed_volume(mesh, positions_from_mesh(mesh));
    report->warnings = std::move(warnings);
  }
  return mesh;
}

}  // namespace shellcontract
