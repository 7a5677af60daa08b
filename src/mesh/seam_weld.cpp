// Welding the vertices that a UV seam split (seam_weld.hpp).
#include "mesh/seam_weld.hpp"

#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>

#include "core/plural.hpp"
#include "mesh/properties.hpp"
#include "shellcontract/face_error.hpp"

namespace shellcontract::soup {
namespace {

using Bits = std::array<std::uint64_t, 3>;

/// A position's bits: equal bits are the same position, whatever the values compare as.
Bits bits_of(const Point3& p) {
  const double c[3] = {p.x(), p.y(), p.z()};
  Bits b;
  std::memcpy(b.data(), c, sizeof c);
  return b;
}

/// A refusal's "problem: details", without the file's name before them ("<path>: ").
std::string without_path(const InputError& e, const std::string& path) {
  const std::string s = e.what();
  const std::string prefix = path + ": ";
  return s.compare(0, prefix.size(), prefix) == 0 ? s.substr(prefix.size()) : s;
}

}  // namespace

std::vector<std::size_t> first_at_same_position(const Positions& x) {
  std::map<Bits, std::size_t> first;
  std::vector<std::size_t> out(static_cast<std::size_t>(x.rows()));
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const auto v = static_cast<std::size_t>(i);
    out[v] = first.emplace(bits_of(Point3(x(i, 0), x(i, 1), x(i, 2))), v).first->second;
  }
  return out;
}

SeamWeld weld_identical_positions(const std::vector<Point3>& points, const std::vector<Polygon>& tris) {
  const std::size_t nv = points.size();
  std::vector<Bits> key(nv);
  for (std::size_t i = 0; i < nv; ++i) key[i] = bits_of(points[i]);
  std::vector<std::size_t> order(nv);
  std::iota(order.begin(), order.end(), std::size_t{0});
  // By position, then by index: each run of equal positions starts at its first copy.
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return key[a] != key[b] ? key[a] < key[b] : a < b;
  });
  std::vector<std::size_t> first(nv);
  for (std::size_t r = 0; r < nv; ++r)
    first[order[r]] = r > 0 && key[order[r]] == key[order[r - 1]] ? first[order[r - 1]] : order[r];
  SeamWeld w;
  w.welded_of.resize(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    if (first[i] == i) {
      w.welded_of[i] = w.points.size();
      w.points.push_back(points[i]);
    } else {
      w.welded_of[i] = w.welded_of[first[i]];  // first[i] < i: already numbered
    }
  }
  w.tris = tris;
  for (Polygon& t : w.tris)
    for (std::size_t& v : t) v = w.welded_of[v];
  return w;
}

bool has_boundary_edge(const std::vector<Polygon>& tris, std::size_t nv) {
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * tris.size());
  for (const Polygon& t : tris)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t a = t[k], b = t[(k + 1) % 3];
      edges.push_back(static_cast<std::uint64_t>(std::min(a, b)) * nv + std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) return true;
    i = j;
  }
  return false;
}

SeamWeld weld_seams(const std::string& path, const std::vector<Point3>& points,
                    const std::vector<Polygon>& tris, const InputError& refusal,
                    const Namer& name) {
  if (!has_boundary_edge(tris, points.size())) rethrow_input_error(refusal);
  SeamWeld weld = weld_identical_positions(points, tris);
  if (weld.copies() == 0) rethrow_input_error(refusal);
  // Welding does not close the mesh: the refusal names the problem as given, then what is left
  // after welding, with the faces left (the same indices: welding renumbers vertices, not faces)
  // and not the refusal's, most of which are the seams' own, closed by the weld (an artist
  // looking for a hole would be sent along every seam).
  const std::string given = without_path(refusal, path);
  const std::string prefix = path + ": " + given.substr(0, given.find(": ")) + ": " +
                             counted(weld.copies(), "vertex is", "vertices are") +
                             " at the position of another vertex (a mesh split along its UV "
                             "seams?), but welding them does not make it a closed manifold mesh: ";
  const auto no_weld = [&](const std::string& why, std::vector<std::size_t> faces = {}) {
    if (faces.empty()) throw InputError(prefix + why);
    throw FaceListError(prefix + why, std::move(faces));
  };
  // The welded soup's vertices are named by their first copies, with the file's lines.
  std::vector<std::size_t> first_copy(weld.points.size(), SIZE_MAX);
  for (std::size_t v = 0; v < points.size(); ++v)
    if (first_copy[weld.welded_of[v]] == SIZE_MAX) first_copy[weld.welded_of[v]] = v;
  Namer welded = name;
  welded.vertex_number = &first_copy;
  for (std::size_t f = 0; f < weld.tris.size(); ++f) {
    const Polygon& t = weld.tris[f];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
      no_weld("after welding, " + name.face(f) + " has two corners at one position", {f});
  }
  // The reader's own checks on the welded soup.
  const std::size_t nv = weld.points.size();
  try {
    check_no_duplicate_face(path, weld.tris, welded);
    check_edges(path, weld.tris, nv, welded);
    check_no_isolated_vertex(path, weld.tris, nv, welded);
    check_vertex_fans(path, weld.tris, nv, welded);
  } catch (const InputError& e) {
    const auto* about_faces = dynamic_cast<const FaceListError*>(&e);
    no_weld("after welding, " + without_path(e, path),
            about_faces ? about_faces->faces() : std::vector<std::size_t>{});
  }
  // The outputs give the input's vertices back (input_faces): every one must be a face's corner,
  // and the soup as given an open surface that a Surface_mesh can hold.
  std::vector<char> used(points.size(), 0);
  for (const Polygon& t : tris)
    for (std::size_t v : t) used[v] = 1;
  for (std::size_t v = 0; v < points.size(); ++v)
    if (!used[v]) no_weld(name.vertex(v) + " is not used by any face");
  if (!CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(tris))
    no_weld("as given, its faces are not a polygon mesh with boundary (separate fans meet at a vertex)");
  return weld;
}

std::string weld_note(const SeamWeld& weld, bool gltf) {
  // A glTF's vertices are read per node that draws them (gltf_reader.cpp): a mesh instanced by
  // two nodes, or two primitives of one node drawing an element of a shared POSITION accessor
  // with different normals or texture coordinates, count it twice, and a glTF result writes the
  // accessor back, so the count is not a file's and no output's count is claimed.
  return counted(weld.copies(), "seam vertex was", "seam vertices were") + " welded: the input's " +
         std::to_string(weld.welded_of.size()) + " vertices" +
         (gltf ? " (counted per glTF node drawing them)" : "") +
         " include copies at the same position (as a UV seam splits them), simulated as one "
         "closed mesh of " +
         std::to_string(weld.points.size()) +
         " vertices; every output keeps the input's vertices, each copy at its vertex's position";
}

void store_input_corners(Mesh& mesh, const SeamWeld& weld, const std::vector<Polygon>& input_tris) {
  auto corners = property::add_map<FaceIndex, std::array<std::size_t, 3>>(mesh, property::INPUT_CORNERS);
  for (const FaceIndex f : mesh.faces()) {
    const Polygon& t = input_tris[f.idx()];
    std::size_t k = 0;
    // The mesh's corner order (reorientation may have swapped two corners of the soup's face):
    // each corner's input vertex is the one of the face that was welded into it.
    for (const VertexIndex v : vertices_around_face(mesh.halfedge(f), mesh)) {
      std::size_t j = 0;
      while (j < 3 && weld.welded_of[t[j]] != v.idx()) ++j;
      if (j == 3 || k == 3)
        throw std::logic_error("store_input_corners: face " + std::to_string(f.idx()) + " is not the welded face");
      corners[f][k++] = t[j];
    }
  }
}

}  // namespace shellcontract::soup
