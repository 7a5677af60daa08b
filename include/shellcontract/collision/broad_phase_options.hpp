// The broad phase's choice of algorithm and its per-call counters: what a caller configures and
// reads, without the broad phase's declarations.
#pragma once

#include <cstdint>

namespace shellcontract {

/// Broad-phase algorithm. All of them return exactly the same pairs (tests compare each with
/// brute force); they differ only in speed.
enum class BroadPhaseMethod {
  /// CGAL box_intersection_d on primitive boxes: vertex boxes against face boxes (bipartite
  /// mode), edge boxes against themselves (complete mode).
  PrimitiveBoxes,
  /// CGAL box_intersection_d on face boxes (complete mode), then the 6 VF and 9 EE pairs of every
  /// overlapping face pair, box-tested and deduplicated (math-spec 10.2, the paper's way).
  FacePairs,
  /// Our own bounding-volume hierarchy (median split, rebuilt each call) over face boxes and
  /// over edge boxes; one query per vertex box and per edge box. Output comes out grouped by
  /// the first id, so only short runs need sorting and nothing needs deduplicating.
  Bvh,
  /// Uniform grid (cell size 3 x the median face/edge box extent, 1.5 x where such cells hold
  /// too many boxes) filled by a counting sort; in each cell, vertex boxes against face boxes
  /// and edge boxes against each other, each pair emitted only in the first cell the two boxes
  /// share (no hash set), culled by a vectorized test on boxes rounded outward to float,
  /// confirmed by the exact double test (with AVX-512, checked at run time, 16 float lanes at a
  /// time, then one exact test per emitted pair). The cells emit the pairs in cell order;
  /// find_candidates then sorts them (see CandidatePairs), so their order does not depend on the
  /// cell size or on a grid kept from the last call. Falls back to PrimitiveBoxes when the boxes
  /// are so large or spread out that the grid would degenerate towards brute force
  /// (BroadPhaseStats::method_run says which ran).
  /// The default: fastest on bear (bench_broad_phase).
  Grid,
};

/// The method find_candidates uses when none is given (the fastest on bear, bench_broad_phase).
static constexpr BroadPhaseMethod DEFAULT_BROAD_PHASE_METHOD = BroadPhaseMethod::Grid;

/// Counters of one find_candidates call (for logs and the paper's Table 2).
struct BroadPhaseStats {
  std::int64_t no_culling_vertex_face = 0;  ///< topo.all_vertex_face_pairs
  std::int64_t no_culling_edge_edge = 0;    ///< topo.all_edge_edge_pairs
  /// Overlapping box pairs the box search reported, adjacent ones included. PrimitiveBoxes:
  /// VF + EE primitive box pairs. FacePairs: face box pairs. Bvh: VF box pairs plus EE box
  /// pairs with a < b. Grid: VF plus EE (a < b) pairs whose boxes overlap after rounding outward
  /// to float (a superset of the exact overlaps, in practice equal), in both the portable and
  /// the AVX-512 cell loop (the latter confirms each pair with the exact test afterwards).
  std::int64_t box_overlaps = 0;
  /// The algorithm that ran: the requested one, except that Grid falls back to PrimitiveBoxes
  /// when its grid would degenerate (see BroadPhaseMethod::Grid).
  BroadPhaseMethod method_run = DEFAULT_BROAD_PHASE_METHOD;
  std::int64_t vertex_face = 0;  ///< VF pairs emitted
  std::int64_t edge_edge = 0;    ///< EE pairs emitted
  double seconds = 0.0;          ///< wall time of the call, s
};

}  // namespace shellcontract
