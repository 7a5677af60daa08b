// Area, perimeter and compactness of a face set; IoU of two face sets.
#include "geometry/region_metrics.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "core/constants.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {

RegionShape region_shape(const Mesh& mesh, const Positions& x, const std::vector<char>& in_region) {
  if (in_region.size() != mesh.number_of_faces() || static_cast<std::size_t>(x.rows()) != mesh.number_of_vertices())
    throw UsageError("region_shape: " + std::to_string(in_region.size()) + " flags and " + std::to_string(x.rows()) +
                     " positions for " + std::to_string(mesh.number_of_faces()) + " faces and " +
                     std::to_string(mesh.number_of_vertices()) + " vertices");
  const auto point = [&](VertexIndex v) { return Vec3(x.row(static_cast<Eigen::Index>(v.idx()))); };
  RegionShape s;
  for (FaceIndex f : mesh.faces()) {
    if (!in_region[f.idx()]) continue;
    const HalfedgeIndex h = mesh.halfedge(f);
    const Vec3 p0 = point(mesh.source(h)), p1 = point(mesh.target(h)), p2 = point(mesh.target(mesh.next(h)));
    s.area += 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  for (EdgeIndex e : mesh.edges()) {
    const FaceIndex a = mesh.face(mesh.halfedge(e, 0)), b = mesh.face(mesh.halfedge(e, 1));
    const bool ia = a != Mesh::null_face() && in_region[a.idx()];
    const bool ib = b != Mesh::null_face() && in_region[b.idx()];
    if (ia != ib) s.perimeter += (point(mesh.vertex(e, 0)) - point(mesh.vertex(e, 1))).norm();
  }
  s.compactness = s.area > 0.0 ? s.perimeter * s.perimeter / (4.0 * PI * s.area)
                               : std::numeric_limits<double>::infinity();
  return s;
}

double face_set_iou(const std::vector<char>& a, const std::vector<char>& b) {
  if (a.size() != b.size())
    throw UsageError("face_set_iou: " + std::to_string(a.size()) + " and " + std::to_string(b.size()) + " flags");
  std::size_t inter = 0, uni = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    inter += (a[i] && b[i]) ? 1 : 0;
    uni += (a[i] || b[i]) ? 1 : 0;
  }
  return uni == 0 ? 1.0 : static_cast<double>(inter) / static_cast<double>(uni);
}

}  // namespace shellcontract
