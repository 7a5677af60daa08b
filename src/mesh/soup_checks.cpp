#include "mesh/soup_checks.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace shellcontract::soup {

/// Duplicate faces (same three vertices in any order) would make a zero-volume double sheet.
void check_no_duplicate_face(const std::string& path, const std::vector<Polygon>& tris, const Namer& name) {
  const std::size_t nf = tris.size();
  // Sorted (corners, face) records: the faces with the same corners are one run, by face index.
  // The face reported is the same as a scan in file order would give: the first face (in file
  // order) whose corners an earlier face has, named with the earliest face of its run.
  struct Corners {
    std::array<std::size_t, 3> key;
    std::size_t face;
    bool operator<(const Corners& o) const {
      for (std::size_t k = 0; k < 3; ++k)
        if (key[k] != o.key[k]) return key[k] < o.key[k];
      return face < o.face;
    }
  };
  std::vector<Corners> records(nf);
  // Counted by the smallest corner, then each corner's few faces sorted: the order one sort of
  // all records gives, in linear time (that sort was a tenth of reading a 442k-face mesh).
  std::size_t nv = 0;
  for (std::size_t f = 0; f < nf; ++f) {
    records[f] = {{tris[f][0], tris[f][1], tris[f][2]}, f};
    std::sort(records[f].key.begin(), records[f].key.end());
    nv = std::max(nv, records[f].key[2] + 1);
  }
  std::vector<std::size_t> start(nv + 1, 0);
  for (const Corners& c : records) ++start[c.key[0] + 1];
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<Corners> sorted(nf);
  for (const Corners& c : records) sorted[start[c.key[0]]++] = c;
  // start[v] is now where corner v's run ends, the previous corner's end where it starts.
  for (std::size_t v = 0, begin = 0; v < nv; begin = start[v++])
    std::sort(sorted.begin() + static_cast<std::ptrdiff_t>(begin), sorted.begin() + static_cast<std::ptrdiff_t>(start[v]));
  std::size_t later = nf, earlier = nf;
  for (std::size_t i = 1; i < nf; ++i)
    if (sorted[i].key == sorted[i - 1].key && (i < 2 || sorted[i - 2].key != sorted[i].key) &&
        sorted[i].face < later)
      later = sorted[i].face, earlier = sorted[i - 1].face;
  if (later < nf) fail_faces(path, "duplicate face", name.face(later) + " has the same corners as " + name.face(earlier), {later, earlier});
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
