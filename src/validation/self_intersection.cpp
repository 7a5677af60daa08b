// Self-intersection queries: PMP::self_intersections / does_self_intersect with the position
// array as vertex point map (no mesh copy). During a run's preparation (the Simulator's baseline
// of the input's own intersections) the faces are checked slab by slab, so that a run's cancel
// is heard between the slabs (core/cancellation.hpp): one CGAL call on a large mesh cannot be
// interrupted and takes seconds.
#include "shellcontract/validation.hpp"

#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>

#include "core/cancellation.hpp"
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

/// `faces` in slabs of about CANCELLATION_CHUNK faces across the axis where `x` spans most: a
/// face goes into every slab its extent along the axis meets. Two intersecting faces share a
/// point, whose coordinate lies in both extents and so in one slab (a slab's index is a
/// monotone function of the coordinate, rounding included), which holds both: the slabs' pairs
/// together are the whole call's.
std::vector<std::vector<FaceIndex>> slabs(const Mesh& mesh, const Positions& x,
                                          const std::vector<FaceIndex>& faces) {
  const std::size_t count = (faces.size() + CANCELLATION_CHUNK - 1) / CANCELLATION_CHUNK;
  Eigen::Index axis = 0;
  (x.colwise().maxCoeff() - x.colwise().minCoeff()).maxCoeff(&axis);
  const double low = x.col(axis).minCoeff();
  const double width = (x.col(axis).maxCoeff() - low) / static_cast<double>(count);
  const auto slab = [&](double c) {
    const double at = width > 0.0 ? std::floor((c - low) / width) : 0.0;
    return static_cast<std::size_t>(std::clamp(at, 0.0, static_cast<double>(count - 1)));
  };
  std::vector<std::vector<FaceIndex>> out(count);
  for (const FaceIndex f : faces) {
    double lo = INFINITY, hi = -INFINITY;
    for (const VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      lo = std::min(lo, x(static_cast<Eigen::Index>(v.idx()), axis));
      hi = std::max(hi, x(static_cast<Eigen::Index>(v.idx()), axis));
    }
    for (std::size_t k = slab(lo), last = slab(hi); k <= last; ++k) out[k].push_back(f);
  }
  return out;
}

}  // namespace

std::vector<FacePair> self_intersecting_pairs(const Mesh& mesh, const Positions& x) {
  check_preconditions(mesh, x, "self_intersecting_pairs");
  std::vector<FacePair> pairs;
  const std::vector<FaceIndex> faces = triangle_faces(mesh, x);
  const auto points = CGAL::parameters::vertex_point_map(EigenPointMap(x));
  if (!CancellationScope::current() || faces.size() <= CANCELLATION_CHUNK) {
    PMP::self_intersections(faces, mesh, std::back_inserter(pairs), points);
  } else {
    for (const std::vector<FaceIndex>& slab : slabs(mesh, x, faces)) {
      cancellation_point();
      PMP::self_intersections(slab, mesh, std::back_inserter(pairs), points);
    }
  }
  // One slab's call (or a small mesh's only one) cannot be interrupted: heard at its end.
  cancellation_point();
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
