// Validating a run's result (CGAL PMP; docs/architecture.md, "validation"): self-intersections at
// given positions, the enclosed volume, and the Hausdorff distance between two shapes of one mesh.
// The heavy PMP headers stay in the .cpp files.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// Two faces that intersect, smaller face index first.
using FacePair = std::pair<FaceIndex, FaceIndex>;

/// All pairs of faces that intersect when the vertices are at x. Faces sharing a vertex or an
/// edge count only if they intersect beyond the shared element (CGAL's definition). A face whose
/// corners are collinear at x (zero area: read_input_mesh warns of it) is in no pair: it is not
/// two faces that intersect, and CGAL tests it against no other face.
/// @param mesh  triangle mesh (connectivity; its own points are ignored)
/// @param x     #V by 3 positions, row i = vertex i, any length unit
/// @pre !mesh.has_garbage(), x.rows() == number of vertices, triangle mesh
/// @return the pairs, each ordered (smaller index first), sorted; empty if none
/// @throws std::invalid_argument if a precondition fails
std::vector<FacePair> self_intersecting_pairs(const Mesh& mesh, const Positions& x);

/// Calls visit(p) once for each pair p of faces that intersect at x (as self_intersecting_pairs
/// defines them), each ordered (smaller index first), in no particular order; a visit that
/// returns false ends the search there. Holds no pair itself: the way to count the pairs of a
/// mesh whose parts pass through each other, whose pairs can number the square of its faces.
/// @pre as for self_intersecting_pairs
void for_each_self_intersection(const Mesh& mesh, const Positions& x,
                                const std::function<bool(const FacePair&)>& visit);

/// The `keep` smallest (face order) of the pairs given to add(), and how many were given, in
/// memory bounded by `keep` whatever their number.
class FacePairSample {
 public:
  explicit FacePairSample(std::size_t keep);
  void add(const FacePair& p);
  std::size_t count() const { return count_; }
  /// The smallest min(keep, count()) pairs given, sorted.
  std::vector<FacePair> pairs() const;
  /// Whether pairs() leaves some out.
  bool truncated() const { return heap_.size() < count_; }

 private:
  std::size_t keep_;
  std::size_t count_ = 0;
  std::vector<FacePair> heap_;
};

/// How many face pairs intersect at some positions, and the first few of them.
struct SelfIntersectionCount {
  std::size_t count = 0;        ///< all the pairs; limit + 1 when the search stopped there
  bool complete = true;         ///< false: more than `limit` pairs, the search stopped at limit + 1
  std::vector<FacePair> first;  ///< the `keep` smallest pairs in face order, sorted (all of them
                                ///< when count <= keep and complete)
};

/// Counts the pairs of self_intersecting_pairs, keeping only the `keep` smallest (face order),
/// and stops at limit + 1 pairs (complete false) when there are more than `limit`.
/// @pre as for self_intersecting_pairs
SelfIntersectionCount count_self_intersections(
    const Mesh& mesh, const Positions& x, std::size_t keep,
    std::size_t limit = std::numeric_limits<std::size_t>::max());

/// The most self-intersecting pairs `check --json` and Python's check() list: the first in face
/// order; their counts are of all the pairs.
inline constexpr std::size_t CHECK_LISTED_PAIRS = 1000;

/// The most pairs a baseline of an input's own intersections may hold (run --validate, check
/// --against, which must remember them all to tell new pairs from them): 1,000,000, or 8 a
/// face on a mesh of more than 125,000 faces. An input with more, parts that pass through each
/// other, is refused for these two rather than held in memory that grows with the square of
/// its faces (docs/cli.md, "--validate").
inline constexpr std::size_t BASELINE_PAIRS = 1000000;
inline constexpr std::size_t BASELINE_PAIRS_PER_FACE = 8;
std::size_t baseline_pair_limit(std::size_t faces);
/// "WHO has more than LIMIT self-intersecting face pairs of its own (...)": the start of the
/// refusal of a baseline past baseline_pair_limit, the same for every command.
std::string too_many_own_pairs(const std::string& who, std::size_t limit);

/// Whether any two faces intersect at positions x; stops at the first pair found (cheaper than
/// self_intersecting_pairs when the answer is usually "no"); a face with collinear corners does
/// not count, as there.
/// @pre as for self_intersecting_pairs
bool does_self_intersect(const Mesh& mesh, const Positions& x);

/// Number of intersecting face pairs at positions x that are not in `baseline` (the pairs that
/// the input mesh already had, e.g. elk.off's 7), so that validation blames the simulation only
/// for intersections it created.
/// @param baseline  pairs from self_intersecting_pairs on the input positions (any order)
/// @pre as for self_intersecting_pairs
/// @return count of new pairs (0 when the result adds none)
std::size_t new_self_intersections(const Mesh& mesh, const Positions& x, const std::vector<FacePair>& baseline);

}  // namespace shellcontract

// Enclosed volume of a closed triangle mesh at given positions (CGAL PMP::volume through an
// EigenPointMap, so that no mesh copy is made; house-style.md section 3).
namespace shellcontract {

/// The Euler characteristic and genus `shellcontract check` and Python's check() report.
struct SurfaceTopology {
  long long euler_characteristic = 0;  ///< V - E + F
  long long genus = 0;                 ///< the sum of the components' genera
};

/// V - E + F of `mesh`, and its genus as a mesh that read_input_mesh accepted: closed, manifold
/// and oriented, so that every one of its `components` is a closed orientable surface and
/// chi = sum (2 - 2 g_i).
SurfaceTopology surface_topology(const Mesh& mesh, std::size_t components);

/// Signed volume enclosed by the mesh when its vertices are at x.
/// PMP::volume only asserts closedness (and the assertion vanishes in release builds), so this
/// wrapper checks the preconditions itself.
/// @param mesh  triangle mesh, connectivity only is used (its own points are ignored)
/// @param x     #V by 3 positions, row i = vertex i, any length unit L
/// @pre !mesh.has_garbage(), x.rows() == number of vertices
/// @return the volume in L^3; positive for outward-oriented faces, negative when inside-out
/// @throws InputError "not a triangle mesh" or "not closed" (with the border edge count)
/// @throws std::invalid_argument if x has the wrong number of rows or the mesh has garbage
double enclosed_volume(const Mesh& mesh, const Positions& x);

/// enclosed_volume without the triangle-mesh and closedness checks, for a caller that measures
/// the same mesh again and again (the simulator, every frame): the checks walk every face and
/// halfedge, which costs more than the volume itself (lab/history.md).
/// @pre enclosed_volume succeeded on this mesh (with any positions), and the mesh's
///      connectivity has not changed since
/// @throws std::invalid_argument if x has the wrong number of rows or the mesh has garbage
double enclosed_volume_unchecked(const Mesh& mesh, const Positions& x);

}  // namespace shellcontract

// Distance between two states of one mesh (same connectivity, two position arrays): the error
// measure of the speed-against-error bench (docs/cli.md, "bench error").
namespace shellcontract {

/// Default absolute error bound of symmetric_hausdorff_distance (units of the positions). The
/// bench works in normalized units (bounding-box diagonal 1), where 1e-7 is far below any error
/// it reports.
inline constexpr double DEFAULT_HAUSDORFF_ERROR_BOUND = 1e-7;

/// Symmetric Hausdorff distance between the surface of `mesh` with vertex positions `a` and the
/// same surface with positions `b`: max(h(A, B), h(B, A)), h(A, B) = max over points p of A of
/// the distance from p to B (whole triangles, not only vertices).
///
/// Computed with CGAL PMP::bounded_error_symmetric_Hausdorff_distance (Sequential_tag), so the
/// result is within `error_bound` of the true distance and deterministic; identical positions
/// give exactly 0 (every face matches).
/// @param mesh  a garbage-free triangle mesh; its own points are not used
/// @param a, b  one row per vertex (row i = vertex i)
/// @param error_bound  absolute bound on the error of the estimate, > 0
/// @throws std::invalid_argument if the row counts do not match the mesh or the bound is not > 0
double symmetric_hausdorff_distance(const Mesh& mesh, const Positions& a, const Positions& b,
                                    double error_bound = DEFAULT_HAUSDORFF_ERROR_BOUND);

/// max_i |a_i - b_i|: the distance with vertex correspondence. An upper bound of the Hausdorff
/// distance; larger when vertices slide along the surface.
/// @throws std::invalid_argument if the row counts differ
double max_vertex_distance(const Positions& a, const Positions& b);

}  // namespace shellcontract
