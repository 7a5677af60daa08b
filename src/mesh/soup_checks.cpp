#include "mesh/soup_checks.hpp"

#include <algorithm>
#include <array>
#include <map>

namespace shellcontract::soup {

/// Duplicate faces (same three vertices in any order) would make a zero-volume double sheet.
void check_no_duplicate_face(const std::string& path, const std::vector<Polygon>& tris, const Namer& name) {
  const std::size_t nf = tris.size();
  std::map<std::array<std::size_t, 3>, std::size_t> seen;
  for (std::size_t f = 0; f < nf; ++f) {
    std::array<std::size_t, 3> key{tris[f][0], tris[f][1], tris[f][2]};
    std::sort(key.begin(), key.end());
    const auto [it, inserted] = seen.emplace(key, f);
    if (!inserted)
      fail(path, "duplicate face", name.face(f) + " has the same corners as " + name.face(it->second));
  }
}

/// Edges: each undirected edge must have exactly two faces that traverse it in opposite
/// directions (closed, manifold, consistently oriented).
void check_edges(const std::string& path, const std::vector<Polygon>& tris, std::size_t nv, const Namer& name) {
  const std::size_t nf = tris.size();
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
      const std::string edge = name.edge(a, b);
      if (count == 1)
        fail(path, "open boundary", edge + " of " + name.face(f) + " has no neighbouring face (boundary edge between " + (name.stl ? name.vertex(a) + " and " + name.vertex(b) : "vertex " + std::to_string(a) + " and vertex " + std::to_string(b)) + "); the mesh must be closed");
      if (count > 2) {
        std::string fs_list;
        for (std::size_t u = 0; u < count && u < MAX_LISTED; ++u) fs_list += (u ? ", " : "") + std::to_string(first[static_cast<std::ptrdiff_t>(u)].face);
        fail(path, "non-manifold edge", name.edge(std::min(a, b), std::max(a, b)) + " is shared by " + std::to_string(count) + " faces (" + fs_list + "), at most 2 allowed");
      }
      fail(path, "inconsistent orientation", name.face(first[0].face) + " and " + name.face(first[1].face) + " traverse " + edge + " in the same direction (the surface is not consistently oriented there)");
    }
}

/// Isolated vertices have no mass and no forces; they would be free degrees of freedom. Checked
/// after the edges: an open boundary is the more fundamental problem of a mesh with both.
void check_no_isolated_vertex(const std::string& path, const std::vector<Polygon>& tris, std::size_t nv,
                               const Namer& name) {
  std::vector<char> used(nv, 0);
  for (const Polygon& t : tris)
    for (std::size_t v : t) used[v] = 1;
  for (std::size_t v = 0; v < nv; ++v)
    if (!used[v]) fail(path, "isolated vertex", name.vertex(v) + " is not used by any face");
}

/// Vertices: the faces around a vertex must form one fan (their link edges one cycle). With
/// manifold, consistently oriented edges, each link vertex has exactly one successor.
void check_vertex_fans(const std::string& path, const std::vector<Polygon>& tris, std::size_t nv, const Namer& name) {
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
      fail(path, "non-manifold vertex", name.vertex(v) + ": its " + std::to_string(l.size()) + " faces form several fans (the fan through its first face has " + std::to_string(steps + 1) + "); the surface pinches there");
  }
}

}  // namespace shellcontract::soup
