// CCD broad phase: swept, inflated axis-aligned boxes over one normalized time step, and the
// vertex-face (VF) and edge-edge (EE) pairs whose boxes overlap (math-spec 10.1-10.2). The
// narrow phase (collision/ccd) runs only on these pairs.
//
// Eigen and std only. CGAL's box_intersection_d is used inside src/collision/broad_phase*.cpp.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "shellcontract/core/types.hpp"

namespace shellcontract {

/// Unique mesh edges, one row per edge, smaller vertex id first (#E by 2).
using Edges = Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>;

/// Edge ids of each face's three sides (#F by 3): column k is the side from corner k to corner
/// (k+1) mod 3.
using FaceEdges = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Connectivity the broad phase needs; built once per mesh by make_collision_topology and reused
/// every step (positions change, connectivity does not).
struct CollisionTopology {
  Faces faces;           ///< #F by 3 vertex ids (a copy of the input)
  Edges edges;           ///< #E by 2, edges(e, 0) < edges(e, 1), rows sorted lexicographically
  FaceEdges face_edges;  ///< #F by 3 edge ids, see FaceEdges
  int num_vertices = 0;  ///< #V; every vertex 0..#V-1 is a VF candidate, referenced or not
  std::vector<int> orphan_vertices;  ///< the vertices no face references, increasing
  /// VF pairs with the vertex not a corner of the face: #V #F - 3 #F (paper Table 2 "no culling").
  std::int64_t all_vertex_face_pairs = 0;
  /// EE pairs a < b sharing no vertex: #E(#E-1)/2 - sum_v deg(v)(deg(v)-1)/2.
  std::int64_t all_edge_edge_pairs = 0;
};

/// Builds the unique edges and face-edge incidence of a triangle mesh.
/// @param faces         #F by 3 vertex ids in [0, num_vertices), three distinct ids per face
/// @param num_vertices  #V, the number of rows of the position arrays that will be passed later
/// @return the topology; edge ids are deterministic (lexicographic order of (min id, max id))
/// @throws InputError if a face has an id out of range or a repeated corner
/// @throws UsageError if num_vertices < 0
/// \note The mesh need not be closed or manifold: the broad phase only needs ids.
CollisionTopology make_collision_topology(const Faces& faces, int num_vertices);

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
  /// Uniform grid (cell size 1.5 x the median face/edge box extent) filled by a counting sort;
  /// in each cell, vertex boxes against face boxes and edge boxes against each other, each pair
  /// emitted only in the first cell the two boxes share (no hash set), culled by a vectorized
  /// test on boxes rounded outward to float, confirmed by the exact double test; on CPUs with
  /// AVX-512 (checked at run time, detail::GridIsa) one 8-lane pass tests the exact double
  /// boxes directly and emits the same pairs in the same order. Pairs come out
  /// in cell order, not sorted (see CandidatePairs). Falls back to PrimitiveBoxes when the boxes
  /// are so large or spread out that the grid would degenerate towards brute force
  /// (BroadPhaseStats::method_run says which ran).
  /// The default: fastest on bear (bench_broad_phase).
  Grid,
};

/// The method find_candidates uses when none is given (the fastest on bear, bench_broad_phase).
static constexpr BroadPhaseMethod DEFAULT_BROAD_PHASE_METHOD = BroadPhaseMethod::Grid;

namespace detail {
/// A swept box with an id, in the form CGAL's Box_traits_d reads (min_coord, max_coord, id,
/// dimension). Internal; in the header only so CandidatePairs can own the buffers.
struct BroadPhaseBox {
  using NT = double;
  using ID = std::size_t;
  std::array<double, 3> lo;
  std::array<double, 3> hi;
  std::size_t box_id;
  double min_coord(int d) const { return lo[static_cast<std::size_t>(d)]; }
  double max_coord(int d) const { return hi[static_cast<std::size_t>(d)]; }
  std::size_t id() const { return box_id; }
  static int dimension() { return 3; }
};

/// A node of the broad phase's BVH, in depth-first order: an inner node's left child is the next
/// node and `right` the other; a leaf holds items order[first, first + count).
struct BvhNode {
  std::array<double, 3> lo;
  std::array<double, 3> hi;
  int first = 0;  ///< leaf: first index into the order array; inner node: right child
  int count = 0;  ///< leaf: number of items (> 0); inner node: 0
};

/// Grid method: a vertex's swept box (face and edge boxes are recomputed from these).
struct GridVertexBox {
  std::array<double, 3> lo;
  std::array<double, 3> hi;
};

/// The Grid method's primitive ids (also query_kept_grid's): vertex v, face V + f, edge V + F + e.
/// Returns the primitive's vertices: vertex {v, -1, -1}, face {a, b, c}, edge {a, b, -2} (-2:
/// never equal to an id nor to a vertex's -1, so one set of comparisons tests adjacency for VF
/// and EE).
inline std::array<int, 3> primitive_vertices(const CollisionTopology& topo, std::size_t id) {
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  const std::size_t nf = static_cast<std::size_t>(topo.faces.rows());
  if (id < nv) return {static_cast<int>(id), -1, -1};
  if (id < nv + nf) {
    const Eigen::Index f = static_cast<Eigen::Index>(id - nv);
    return {topo.faces(f, 0), topo.faces(f, 1), topo.faces(f, 2)};
  }
  const Eigen::Index e = static_cast<Eigen::Index>(id - nv - nf);
  return {topo.edges(e, 0), topo.edges(e, 1), -2};
}

/// The number of vertices in primitive_vertices' answer: 1, 3 or 2.
inline int primitive_corners(const std::array<int, 3>& v) {
  return v[1] < 0 ? 1 : v[2] < 0 ? 2 : 3;
}

/// A primitive's box: the union of its vertices' boxes (min and max are exact).
inline GridVertexBox primitive_box(const std::vector<GridVertexBox>& vertex_boxes,
                                   const std::array<int, 3>& v) {
  GridVertexBox b = vertex_boxes[static_cast<std::size_t>(v[0])];
  for (int k = 1; k < primitive_corners(v); ++k) {
    const GridVertexBox& q = vertex_boxes[static_cast<std::size_t>(v[static_cast<std::size_t>(k)])];
    for (std::size_t d = 0; d < 3; ++d) {
      b.lo[d] = std::min(b.lo[d], q.lo[d]);
      b.hi[d] = std::max(b.hi[d], q.hi[d]);
    }
  }
  return b;
}

/// Grid method: the cells a box covers, inclusive, per axis.
struct GridRange {
  std::array<std::uint16_t, 3> lo;
  std::array<std::uint16_t, 3> hi;
};

/// Grid method: a swept box rounded outward to float, relative to the scene minimum.
struct GridFloatBox {
  std::array<float, 3> lo;
  std::array<float, 3> hi;
};

/// Grid method: the boxes of one cell as structure-of-arrays buffers (for vectorized tests).
struct GridCell {
  std::array<std::vector<float>, 3> lo, hi;  ///< float boxes, per axis (portable, superset)
  std::array<std::vector<double>, 3> dlo, dhi;  ///< exact boxes, per axis (AVX-512 path)
  std::array<std::vector<int>, 3> v;         ///< vertex ids (see GridPrimitives::ids)
  std::vector<std::uint32_t> flags;          ///< bit d: the box's first cell on axis d
  std::vector<std::uint32_t> gid;            ///< vertex id, V + face id or V + F + edge id
  std::vector<std::uint32_t> mask;           ///< candidate mask of the current row
};

/// Grid method: one chunk of cells processed by one task, with its own buffers.
struct GridChunk {
  GridCell cell;                         ///< the boxes of the current cell
  std::vector<std::uint64_t> vf_keys;    ///< pairs found in this chunk (see BroadPhaseScratch)
  std::vector<std::uint64_t> ee_keys;
  /// AVX-512 loop: the keys of rows 1, 2, 3 of a group of rows (cell_rows_avx512)
  std::array<std::vector<std::uint64_t>, 3> row_keys;
  std::int64_t reported = 0;             ///< box overlaps (statistics, see BroadPhaseStats)
};

/// Which code the Grid method's cell loop runs. Both emit the same pairs in the same order with
/// the same close flags (tested); Auto takes AVX-512 when the CPU has it (checked at run time).
enum class GridIsa { Auto, Portable };

/// True if GridIsa::Auto runs the AVX-512 cell loop on this CPU (AVX-512 F and VL, GCC x86-64).
bool grid_avx512_available();

/// Scratch buffers reused between calls, so a steady-state call does not allocate.
struct BroadPhaseScratch {
  GridIsa grid_isa = GridIsa::Auto;  ///< tests set Portable to compare the two cell loops
  /// find_candidates_in_vertex_boxes with the AVX-512 cell loop: test float boxes 16 lanes at a
  /// time and emit a superset of the exact pairs (see there); false: the exact pairs (tests and
  /// bench_broad_phase compare the two).
  bool grid_float_superset = true;
  std::vector<BroadPhaseBox> vertex_boxes;  ///< indexed by vertex id
  std::vector<BroadPhaseBox> face_boxes;    ///< indexed by face id
  std::vector<BroadPhaseBox> edge_boxes;    ///< indexed by edge id
  std::vector<BroadPhaseBox> work_a;        ///< copies CGAL may reorder
  std::vector<BroadPhaseBox> work_b;
  std::vector<std::uint64_t> vf_keys;       ///< packed (vertex << 32 | face) pair keys
  std::vector<std::uint64_t> ee_keys;       ///< packed (edge a << 32 | edge b) pair keys
  std::vector<BvhNode> face_tree;           ///< Bvh method: tree over face boxes
  std::vector<int> face_order;              ///< face ids in leaf order
  std::vector<BvhNode> edge_tree;           ///< Bvh method: tree over edge boxes
  std::vector<int> edge_order;              ///< edge ids in leaf order
  std::vector<int> stack;                   ///< traversal stack
  std::vector<GridVertexBox> grid_vertex_boxes;  ///< Grid method: indexed by vertex id
  std::vector<GridFloatBox> grid_vertex_floats;  ///< Grid: float vertex boxes
  std::vector<GridRange> grid_vertex_ranges;     ///< Grid: cell ranges of the vertex boxes
  std::vector<GridRange> grid_ranges;            ///< Grid: of vertex, face, then edge boxes
  std::vector<GridChunk> chunks;                 ///< Grid: per-chunk buffers of the cell loop
  std::vector<std::size_t> chunk_cells;          ///< Grid: first cell of each chunk, then #cells
  std::vector<double> extent_sample;        ///< Grid: box extents for the cell size
  std::vector<std::uint32_t> cell_start;    ///< Grid: CSR offsets per cell
  std::vector<std::uint32_t> cell_count;    ///< Grid: per part of the counting sort, per cell
  std::vector<std::uint32_t> cell_fill;     ///< Grid: fill cursors, per part, per cell
  std::vector<std::uint32_t> cell_entries;  ///< Grid: box id << 3 | first-cell flags
  std::vector<std::size_t> chunk_offsets;   ///< Grid: each chunk's first output VF, then EE pair
  /// Grid: whether the grid of the last call (cell_start, cell_entries, grid_vertex_boxes and the
  /// geometry below) is complete and may be queried (query_kept_grid).
  bool grid_kept = false;
  std::array<double, 3> grid_origin{};        ///< Grid: its minimum corner
  double grid_inv_h = 1.0;                    ///< Grid: 1 / cell size
  std::array<std::size_t, 3> grid_dims{};     ///< Grid: cells per axis
  /// Grid: keep the last call's grid and patch its counting sort when it still fits (tests turn
  /// it off); grid_patch_always_rebuild keeps the grid but rebuilds the counting sort, so that a
  /// test can compare a patch with a rebuild on the same grid.
  bool grid_patch = true;
  bool grid_patch_always_rebuild = false;
  /// Grid: boxes whose cell range the last call patched, or -1 if it rebuilt the counting sort.
  std::int64_t grid_patched_boxes = -1;
  std::vector<GridRange> grid_vertex_ranges_prev;  ///< Grid: the last call's vertex ranges
  std::vector<std::uint64_t> grid_maybe_bits;   ///< Grid: boxes the patch recomputes (bitset)
  std::vector<std::uint32_t> grid_changed_ids;  ///< Grid: the patch's changed boxes
  std::vector<GridRange> grid_changed_ranges;   ///< Grid: their new ranges
  std::vector<std::uint64_t> grid_changed_bits; ///< Grid: the changed boxes as a bitset
  /// Grid: the topology (faces, then edges) the vertex-to-primitive lists were built for
  std::vector<int> grid_topology;
  std::size_t grid_topology_vertices = 0;
  std::vector<std::uint32_t> grid_vertex_prims_start;  ///< Grid: CSR offsets per vertex
  std::vector<std::uint32_t> grid_vertex_prims;  ///< Grid: each vertex's faces and edges (ids)
  std::vector<std::uint32_t> grid_add_start;    ///< Grid: the patch's new entries per cell
  std::vector<std::uint8_t> grid_dirty;         ///< Grid: per cell, the patch changes it
  std::vector<std::uint32_t> grid_adds;         ///< Grid: the patch's new entries (tags)
  std::vector<std::uint32_t> cell_start_next;   ///< Grid: the patch's output buffers
  std::vector<std::uint32_t> cell_entries_next;
  /// Grid: wall time of the last call's three parts, for diagnostics (0 for a part it did not
  /// reach): the grid (scene bounds, cell size, cell ranges, the counting sort or its patch),
  /// the cell loop, and the output of its pairs in chunk order.
  double grid_build_seconds = 0.0;
  double grid_cell_loop_seconds = 0.0;
  double grid_output_seconds = 0.0;
};
}  // namespace detail

/// Candidate pairs for the narrow phase. Reuse one object across steps: the vectors keep their
/// capacity.
struct CandidatePairs {
  /// (vertex id, face id), the vertex not a corner of the face; unique. Sorted, except from the
  /// Grid method, whose pairs come in the order of its cells: the same order for any number of
  /// threads (sorting cost more than a tenth of a grid call).
  std::vector<std::array<int, 2>> vertex_face;
  /// (edge id a, edge id b), a < b, the edges share no vertex; unique; ordered as vertex_face.
  std::vector<std::array<int, 2>> edge_edge;
  /// Per pair of vertex_face and of edge_edge: 0 only if the two primitives' swept boxes,
  /// before inflation, are certainly more than find_candidates' `far_distance` apart on some
  /// axis (so they never come that close during the step); 1 otherwise. Only the Grid method,
  /// which has the exact boxes at hand when it emits a pair, sets 0; the others report 1.
  std::vector<std::uint8_t> vertex_face_close;
  std::vector<std::uint8_t> edge_edge_close;
  /// Internal buffers; not part of the result.
  detail::BroadPhaseScratch scratch;
};

/// Counters of one find_candidates call (for logs and the paper's Table 2).
struct BroadPhaseStats {
  std::int64_t no_culling_vertex_face = 0;  ///< topo.all_vertex_face_pairs
  std::int64_t no_culling_edge_edge = 0;    ///< topo.all_edge_edge_pairs
  /// Overlapping box pairs the box search reported, adjacent ones included. PrimitiveBoxes:
  /// VF + EE primitive box pairs. FacePairs: face box pairs. Bvh: VF box pairs plus EE box
  /// pairs with a < b. Grid: VF plus EE (a < b) pairs whose boxes overlap after rounding outward
  /// to float (a superset of the exact overlaps, in practice equal); exactly overlapping pairs
  /// when the AVX-512 cell loop ran (detail::GridIsa).
  std::int64_t box_overlaps = 0;
  /// The algorithm that ran: the requested one, except that Grid falls back to PrimitiveBoxes
  /// when its grid would degenerate (see BroadPhaseMethod::Grid).
  BroadPhaseMethod method_run = DEFAULT_BROAD_PHASE_METHOD;
  std::int64_t vertex_face = 0;  ///< VF pairs emitted
  std::int64_t edge_edge = 0;    ///< EE pairs emitted
  double seconds = 0.0;          ///< wall time of the call, s
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
/// out.scratch.grid_float_superset (the default) the boxes are tested in float, mapped from the
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
bool find_candidates_in_vertex_boxes(const std::vector<detail::GridVertexBox>& boxes,
                                     const CollisionTopology& topo, CandidatePairs& out);

/// The primitives whose boxes in the grid kept by the last find_candidates_in_vertex_boxes call
/// on `pairs` overlap `box` (closed intervals on all three axes), each once, appended to `out`
/// as ids: vertex v, face V + f, edge V + F + e. Adjacency is not checked.
/// @param first_id, end_id  only ids in [first_id, end_id) are reported (e.g. [V, V + F): the
///                          faces a vertex can pair with); the others are skipped without a box
///                          test, since each cell lists its boxes by increasing id
/// @throws UsageError if `pairs` keeps no grid
void query_kept_grid(const CandidatePairs& pairs, const CollisionTopology& topo,
                     const detail::GridVertexBox& box, std::vector<std::uint32_t>& out,
                     std::uint32_t first_id = 0,
                     std::uint32_t end_id = std::numeric_limits<std::uint32_t>::max());

/// Fast conservative step check: does find_candidates have at least one pair to report?
/// Stops at the first non-adjacent overlapping VF or EE box pair, so a `false` answer (nothing
/// can collide this step, skip the narrow phase) costs one box search and a `true` answer usually
/// much less.
/// @param x0, x1, topo, inflation  as for find_candidates
/// @param scratch    buffers reused between calls (e.g. the scratch of a CandidatePairs)
/// @return true iff find_candidates would emit at least one VF or EE pair
/// @throws UsageError as find_candidates
bool has_any_candidate(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                       double inflation, detail::BroadPhaseScratch& scratch);

}  // namespace shellcontract
