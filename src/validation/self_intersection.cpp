// Self-intersection queries: PMP::self_intersections / does_self_intersect with the position
// array as vertex point map (no mesh copy).
#include "shellcontract/validation.hpp"

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

}  // namespace

std::vector<FacePair> self_intersecting_pairs(const Mesh& mesh, const Positions& x) {
  check_preconditions(mesh, x, "self_intersecting_pairs");
  std::vector<FacePair> pairs;
  PMP::self_intersections(mesh, std::back_inserter(pairs), CGAL::parameters::vertex_point_map(EigenPointMap(x)));
  for (FacePair& p : pairs) p = ordered(p.first, p.second);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

bool does_self_intersect(const Mesh& mesh, const Positions& x) {
  check_preconditions(mesh, x, "does_self_intersect");
  return PMP::does_self_intersect(mesh, CGAL::parameters::vertex_point_map(EigenPointMap(x)));
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
