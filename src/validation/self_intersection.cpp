// Self-intersection queries: PMP::self_intersections / does_self_intersect with the position
// array as vertex point map (no mesh copy).
#include "shellcontract/validation.hpp"

#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <algorithm>
#include <iterator>
#include <stdexcept>
#include <string>

#include "mesh/eigen_point_map.hpp"

namespace shellcontract {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

void check_preconditions(const Mesh& mesh, const Positions& x, const char* who) {
  if (mesh.has_garbage())
    throw std::invalid_argument(std::string(who) + ": the mesh has removed elements; call collect_garbage() first");
  if (static_cast<std::size_t>(x.rows()) != mesh.number_of_vertices())
    throw std::invalid_argument(std::string(who) + ": " + std::to_string(x.rows()) + " position rows for " +
                                std::to_string(mesh.number_of_vertices()) + " vertices");
  if (!CGAL::is_triangle_mesh(mesh)) throw std::invalid_argument(std::string(who) + ": not a triangle mesh");
  // CGAL's predicates on NaN give arbitrary answers; refuse rather than report nonsense.
  if (!x.allFinite()) throw std::invalid_argument(std::string(who) + ": non-finite positions");
}

FacePair ordered(FaceIndex a, FaceIndex b) { return a < b ? FacePair(a, b) : FacePair(b, a); }

// The faces that are triangles at x, not segments or points. CGAL reports a degenerate face f
// (collinear corners) as the pair (f, f) and tests it against no other face; such a pair is no
// intersection of two faces, and read_input_mesh already reports the face as one of (nearly)
// zero area. Leaving these faces out of the range gives the same pairs without the (f, f) ones,
// and keeps does_self_intersect from answering yes for a mesh that only has a degenerate face.
std::vector<FaceIndex> triangle_faces(const Mesh& mesh, const Positions& x) {
  const EigenPointMap points(x);
  std::vector<FaceIndex> faces;
  faces.reserve(mesh.number_of_faces());
  for (const FaceIndex f : mesh.faces())
    if (!PMP::is_degenerate_triangle_face(f, mesh, CGAL::parameters::vertex_point_map(points))) faces.push_back(f);
  return faces;
}

}  // namespace

std::vector<FacePair> self_intersecting_pairs(const Mesh& mesh, const Positions& x) {
  check_preconditions(mesh, x, "self_intersecting_pairs");
  std::vector<FacePair> pairs;
  PMP::self_intersections(triangle_faces(mesh, x), mesh, std::back_inserter(pairs),
                          CGAL::parameters::vertex_point_map(EigenPointMap(x)));
  for (FacePair& p : pairs) p = ordered(p.first, p.second);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

bool does_self_intersect(const Mesh& mesh, const Positions& x) {
  check_preconditions(mesh, x, "does_self_intersect");
  return PMP::does_self_intersect(triangle_faces(mesh, x), mesh, CGAL::parameters::vertex_point_map(EigenPointMap(x)));
}

std::size_t new_self_intersections(const Mesh& mesh, const Positions& x, const std::vector<FacePair>& baseline) {
  std::vector<FacePair> known;
  known.reserve(baseline.size());
  for (const FacePair& p : baseline) known.push_back(ordered(p.first, p.second));
  std::sort(known.begin(), known.end());
  std::size_t fresh = 0;
  for (const FacePair& p : self_intersecting_pairs(mesh, x))
    if (!std::binary_search(known.begin(), known.end(), p)) ++fresh;
  return fresh;
}

}  // namespace shellcontract
