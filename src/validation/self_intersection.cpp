// Self-intersection queries: PMP::self_intersections / does_self_intersect with the position
// array as vertex point map (no mesh copy). During a run's preparation (the Simulator's baseline
// of the input's own intersections) the faces are checked slab by slab, so that a run's cancel
// is heard between the slabs (core/cancellation.hpp): one CGAL call on a large mesh cannot be
// interrupted and takes seconds.
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>

#include <algorithm>
#include <boost/iterator/function_output_iterator.hpp>
#include <cmath>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <string>

#include "core/cancellation.hpp"
#include "mesh/eigen_point_map.hpp"
#include "shellcontract/validation.hpp"

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
/// together are the whole call's. A pair is in every slab from slab(max of the two faces' lows)
/// to slab(min of their highs): `first_slab` keeps it in the first of these only, so that each
/// pair is visited once without holding the pairs found so far.
struct Slabs {
  std::vector<std::vector<FaceIndex>> faces;
  std::vector<std::size_t> low_slab;  // per face index: the slab of its extent's low end
  std::size_t first_slab(const FacePair& p) const {
    return std::max(low_slab[p.first.idx()], low_slab[p.second.idx()]);
  }
};

Slabs slabs(const Mesh& mesh, const Positions& x, const std::vector<FaceIndex>& faces) {
  const std::size_t count = (faces.size() + CANCELLATION_CHUNK - 1) / CANCELLATION_CHUNK;
  Eigen::Index axis = 0;
  (x.colwise().maxCoeff() - x.colwise().minCoeff()).maxCoeff(&axis);
  const double low = x.col(axis).minCoeff();
  const double width = (x.col(axis).maxCoeff() - low) / static_cast<double>(count);
  const auto slab = [&](double c) {
    const double at = width > 0.0 ? std::floor((c - low) / width) : 0.0;
    return static_cast<std::size_t>(std::clamp(at, 0.0, static_cast<double>(count - 1)));
  };
  Slabs out;
  out.faces.resize(count);
  out.low_slab.assign(mesh.number_of_faces(), 0);
  for (const FaceIndex f : faces) {
    double lo = INFINITY, hi = -INFINITY;
    for (const VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      lo = std::min(lo, x(static_cast<Eigen::Index>(v.idx()), axis));
      hi = std::max(hi, x(static_cast<Eigen::Index>(v.idx()), axis));
    }
    out.low_slab[f.idx()] = slab(lo);
    for (std::size_t k = slab(lo), last = slab(hi); k <= last; ++k) out.faces[k].push_back(f);
  }
  return out;
}

// Thrown through CGAL's search by a visitor that wants no more pairs.
struct StopSearch {};

void visit_pairs(const Mesh& mesh, const Positions& x,
                 const std::function<bool(const FacePair&)>& visit, const char* who) {
  check_preconditions(mesh, x, who);
  const std::vector<FaceIndex> faces = triangle_faces(mesh, x);
  const auto points = CGAL::parameters::vertex_point_map(EigenPointMap(x));
  // CGAL copies the output iterator: the state lives here, the iterator only points at it.
  const auto search = [&](const std::vector<FaceIndex>& range, const Slabs* in, std::size_t slab) {
    const auto out =
        boost::make_function_output_iterator([&](const std::pair<FaceIndex, FaceIndex>& found) {
          const FacePair p = ordered(found.first, found.second);
          if (in && in->first_slab(p) != slab) return;  // visited in an earlier slab
          if (!visit(p)) throw StopSearch{};
        });
    PMP::self_intersections(range, mesh, out, points);
  };
  try {
    if (!CancellationScope::current() || faces.size() <= CANCELLATION_CHUNK) {
      search(faces, nullptr, 0);
    } else {
      const Slabs s = slabs(mesh, x, faces);
      for (std::size_t k = 0; k < s.faces.size(); ++k) {
        cancellation_point();
        search(s.faces[k], &s, k);
      }
    }
  } catch (const StopSearch&) {
    return;
  }
  // One slab's call (or a small mesh's only one) cannot be interrupted: heard at its end.
  cancellation_point();
}

}  // namespace

void for_each_self_intersection(const Mesh& mesh, const Positions& x,
                                const std::function<bool(const FacePair&)>& visit) {
  visit_pairs(mesh, x, visit, "for_each_self_intersection");
}

FacePairSample::FacePairSample(std::size_t keep) : keep_(keep) {}

void FacePairSample::add(const FacePair& p) {
  ++count_;
  if (keep_ == 0) return;
  // A max-heap of the smallest pairs so far: most pairs of a mesh with many lose to its top.
  if (heap_.size() < keep_) {
    heap_.push_back(p);
    std::push_heap(heap_.begin(), heap_.end());
  } else if (p < heap_.front()) {
    std::pop_heap(heap_.begin(), heap_.end());
    heap_.back() = p;
    std::push_heap(heap_.begin(), heap_.end());
  }
}

std::vector<FacePair> FacePairSample::pairs() const {
  std::vector<FacePair> out = heap_;
  std::sort(out.begin(), out.end());
  return out;
}

SelfIntersectionCount count_self_intersections(const Mesh& mesh, const Positions& x,
                                               std::size_t keep, std::size_t limit) {
  FacePairSample sample(keep);
  bool complete = true;
  const auto add = [&](const FacePair& p) {
    sample.add(p);
    complete = sample.count() <= limit;
    return complete;
  };
  visit_pairs(mesh, x, add, "count_self_intersections");
  return {sample.count(), complete, sample.pairs()};
}

std::vector<FacePair> self_intersecting_pairs(const Mesh& mesh, const Positions& x) {
  std::vector<FacePair> pairs;
  const auto add = [&](const FacePair& p) {
    pairs.push_back(p);
    return true;
  };
  visit_pairs(mesh, x, add, "self_intersecting_pairs");
  std::sort(pairs.begin(), pairs.end());
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
  const auto add = [&](const FacePair& p) {
    if (!std::binary_search(known.begin(), known.end(), p)) ++fresh;
    return true;
  };
  visit_pairs(mesh, x, add, "self_intersecting_pairs");
  return fresh;
}

std::size_t baseline_pair_limit(std::size_t faces) {
  return std::max(BASELINE_PAIRS, BASELINE_PAIRS_PER_FACE * faces);
}

std::string too_many_own_pairs(const std::string& who, std::size_t limit) {
  return who + " has more than " + std::to_string(limit) +
         " self-intersecting face pairs of its own (parts that pass through each other): too many "
         "to hold in memory to tell a result's new intersections from them";
}

}  // namespace shellcontract
