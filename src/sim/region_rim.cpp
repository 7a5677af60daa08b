// Regions without a rim are refused before a run (region_rim.hpp).
#include "sim/region_rim.hpp"

#include <algorithm>
#include <cstddef>

#include "shellcontract/error.hpp"

namespace shellcontract {

void check_regions_have_rims(const Mesh& mesh, const std::vector<int>& region_of_face,
                             const std::string& source) {
  if (region_of_face.size() != mesh.number_of_faces())
    throw UsageError("check_regions_have_rims: " + std::to_string(region_of_face.size()) +
                     " region ids for " + std::to_string(mesh.number_of_faces()) + " faces");
  if (region_of_face.empty()) return;
  if (std::all_of(region_of_face.begin(), region_of_face.end(), [](int id) { return id >= 0; }))
    throw InputError(source + ": the regions cover every face of the mesh (" +
                     std::to_string(region_of_face.size()) +
                     "), so a region has no rim to sink from; leave out the faces that should "
                     "hold still");
  const int count = *std::max_element(region_of_face.begin(), region_of_face.end()) + 1;
  std::vector<char> has_rim(static_cast<std::size_t>(std::max(count, 0)), 0);
  std::vector<char> used(has_rim.size(), 0);
  for (FaceIndex f : mesh.faces()) {
    const int id = region_of_face[f.idx()];
    if (id < 0) continue;
    used[static_cast<std::size_t>(id)] = 1;
    for (HalfedgeIndex h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh)) {
      const FaceIndex g = mesh.face(mesh.opposite(h));
      if (g == Mesh::null_face() || region_of_face[g.idx()] != id) has_rim[static_cast<std::size_t>(id)] = 1;
    }
  }
  for (std::size_t r = 0; r < has_rim.size(); ++r)
    if (used[r] && !has_rim[r])
      throw InputError(source + ": region " + std::to_string(r) +
                       " covers a whole closed part of the mesh, so it has no rim to sink from");
}

}  // namespace shellcontract
