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

}  // namespace shellcontract::soup
