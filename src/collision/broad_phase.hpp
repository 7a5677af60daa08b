// CCD broad phase: swept, inflated axis-aligned boxes over one normalized time step, and the
// vertex-face (VF) and edge-edge (EE) pairs whose boxes overlap (math-spec 10.1-10.2). The
// narrow phase (collision/ccd) runs only on these pairs.
//
// Eigen and std only. The algorithms (CGAL's box_intersection_d, the BVH, the grid) and their
// buffers are private to src/collision/broad_phase/.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "collision/topology.hpp"
#include "core/no_zero_allocator.hpp"
#include "shellcontract/simulation_options.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// An axis-aligned box, closed on every side (lo <= hi): one vertex's box for
/// find_candidates_in_vertex_boxes and query_kept_grid.
struct VertexBox {
  std::array<double, 3> lo;
  std::array<double, 3> hi;
};

/// The broad phase's reusable buffers (opaque outside the library).
struct BroadPhaseScratch;

/// Candidate pairs for the narrow phase. Reuse one object across steps: the vectors keep their
/// capacity.
struct CandidatePairs {
  /// (vertex id, face id), the vertex not a corner of the face; unique. From find_candidates:
  /// sorted. (The Grid method emits them in the order of its cells, which depends on the grid a
  /// call keeps from the last one; find_candidates sorts them so that the order, on which the
  /// collision step's result depends, comes from the pairs alone: the same after a checkpoint's
  /// resume.) From find_candidates_in_vertex_boxes: sorted too, for the same reason.
  NoZeroVector<std::array<int, 2>> vertex_face;
  /// (edge id a, edge id b), a < b, the edges share no vertex; unique; ordered as vertex_face.
  NoZeroVector<std::array<int, 2>> edge_edge;
  /// Per pair of vertex_face and of edge_edge: 0 only if the two primitives' swept boxes,
  /// before inflation, are certainly more than find_candidates' `far_distance` apart on some
  /// axis (so they never come that close during the step); 1 otherwise. Only the Grid method,
  /// which has the exact boxes at hand when it emits a pair, sets 0; the others report 1.
  NoZeroVector<std::uint8_t> vertex_face_close;
  NoZeroVector<std::uint8_t> edge_edge_close;
  /// The broad phase's buffers, kept between calls (a steady-state call does not allocate) and
  /// the grid that query_kept_grid reads. Not part of the result; the type is complete only
  /// inside the library (src/collision/broad_phase/scratch.hpp).
  std::unique_ptr<BroadPhaseScratch> scratch;

  CandidatePairs();
  ~CandidatePairs();
  CandidatePairs(CandidatePairs&&) noexcept;
  CandidatePairs& operator=(CandidatePairs&&) noexcept;
};

/// Finds every VF and EE pair whose swept, inflated boxes overlap (math-spec 10.2).
///
/// A vertex's swept box is the min/max of its start and end positions (the straight trajectory of
/// math-spec 10.1 stays inside it for t in [0,1]); a face's or edge's box is the min/max over its
/// vertices' start and end positions. Each box is grown by `inflation` on every side, and two
/// boxes overlap if their closed intervals intersect on all three axes (touching counts).
///
/// @param x0         #V by 3 start positions x^n (caller's length units)
/// @param x1         #V by 3 end positions x^* (same units)
/// @param topo       from make_collision_topology for this mesh; topo.num_vertices == #V
/// @param inflation  added to each side of every box, >= 0, same units as x. Boxes of two
///                   primitives closer than `inflation` (Euclidean) at some common time always
///                   overlap; pass the contact tolerance tau (math-spec 10.6) or delta (10.7).
/// @param out        receives the pairs (previous contents are discarded, capacity is reused)
/// @param stats      optional counters of this call; may be nullptr
/// @param method     algorithm; every method gives the same pairs
/// @param far_distance  if >= 0, the distance for CandidatePairs' close flags (a caller that
///                   tests the pairs with tolerance far_distance can skip the pairs flagged 0);
///                   if negative, every pair is flagged close
/// @pre positions are finite
/// @throws UsageError on a row-count mismatch or a negative or non-finite inflation
void find_candidates(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                     double inflation, CandidatePairs& out, BroadPhaseStats* stats = nullptr,
                     BroadPhaseMethod method = DEFAULT_BROAD_PHASE_METHOD,
                     double far_distance = -1.0);

/// The threshold find_candidates compares the gaps of inflated boxes with to flag a pair far
/// (CandidatePairs' close flags), for boxes of x0 and x1 grown by `inflation`: a gap above it on
/// some axis leaves the boxes before inflation more than far_distance apart, rounding included.
/// +infinity if far_distance is negative or not finite (nothing is flagged far).
double far_gap_threshold(const Positions& x0, const Positions& x1, double inflation,
                         double far_distance);

/// far_gap_threshold for coordinates of magnitude at most `max_abs` (the largest |coordinate| of
/// x0 and x1), for callers that have it from a pass of their own.
double far_gap_threshold_for_magnitude(double max_abs, double inflation, double far_distance);

/// The Grid method on given per-vertex boxes: a face's or edge's box is the union of its vertices'
/// boxes, and every non-adjacent VF and EE pair whose boxes overlap (closed intervals) is
/// emitted, flagged close, in the Grid's order. With the AVX-512 cell loop and
/// the scratch's grid_float_superset (the default) the boxes are tested in float, mapped from the
/// doubles monotonically, which keeps every overlap: the pairs are then a superset, the extra
/// ones apart by no more than float rounding (about 1e-7 of the scene's extent; bear: none). The
/// caller must test its pairs' exact boxes itself (SelfCollision does, on the actual step's
/// boxes). The grid is kept in out.scratch for
/// query_kept_grid until the next broad-phase call on `out`. SelfCollision builds it on predicted
/// swept boxes while the constraint solve runs (see SelfCollision::predict).
/// @param boxes  one box per vertex, lo <= hi, finite
/// @param topo   the mesh's topology; boxes.size() == topo.num_vertices
/// @param out    receives the pairs
/// @return false if the grid would degenerate towards brute force (see BroadPhaseMethod::Grid):
///         then out holds no pairs and no grid, and find_candidates is the way
/// @throws UsageError if boxes.size() != topo.num_vertices
bool find_candidates_in_vertex_boxes(const std::vector<VertexBox>& boxes,
                                     const CollisionTopology& topo, CandidatePairs& out);

/// The primitives whose boxes in the grid kept by the last find_candidates_in_vertex_boxes call
/// on `pairs` overlap `box` (closed intervals on all three axes), each once, appended to `out`
/// as ids: vertex v, face V + f, edge V + F + e. Adjacency is not checked.
/// @param first_id, end_id  only ids in [first_id, end_id) are reported (e.g. [V, V + F): the
///                          faces a vertex can pair with); the others are skipped without a box
///                          test, since each cell lists its boxes by increasing id
/// @throws UsageError if `pairs` keeps no grid
void query_kept_grid(const CandidatePairs& pairs, const CollisionTopology& topo,
                     const VertexBox& box, std::vector<std::uint32_t>& out,
                     std::uint32_t first_id = 0,
                     std::uint32_t end_id = std::numeric_limits<std::uint32_t>::max());

/// Wall time of the Grid method's parts in the last broad-phase call on a CandidatePairs, in
/// seconds (diagnostics; 0 for a part the call did not reach).
struct GridPartSeconds {
  double build = 0.0;      ///< scene bounds, cell size, cell ranges, counting sort or its patch
  double cell_loop = 0.0;  ///< the cell loop
  double output = 0.0;     ///< the output of its pairs in chunk order
};

/// The part times of the last find_candidates or find_candidates_in_vertex_boxes call on `pairs`.
GridPartSeconds grid_part_seconds(const CandidatePairs& pairs);

/// Fast conservative step check: does find_candidates have at least one pair to report?
/// Stops at the first non-adjacent overlapping VF or EE box pair, so a `false` answer (nothing
/// can collide this step, skip the narrow phase) costs one box search and a `true` answer usually
/// much less.
/// @param x0, x1, topo, inflation  as for find_candidates
/// @param buffers    its scratch buffers are reused (its pairs are left as they were)
/// @return true iff find_candidates would emit at least one VF or EE pair
/// @throws UsageError as find_candidates
bool has_any_candidate(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                       double inflation, CandidatePairs& buffers);

}  // namespace shellcontract
