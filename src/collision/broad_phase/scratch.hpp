// The broad phase's private types: its boxes, the BVH's nodes, the grid's cells and chunks, and
// the scratch buffers a CandidatePairs owns (public headers see BroadPhaseScratch only as an
// incomplete type). Included by src/collision/broad_phase/*.cpp, by the speculative broad phase
// (src/collision/self_collision/) and by the white-box tests and benchmarks of the grid.
#pragma once

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "collision/broad_phase.hpp"

namespace shellcontract {
namespace detail {

/// A swept box with an id, in the form CGAL's Box_traits_d reads (min_coord, max_coord, id,
/// dimension).
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
using GridVertexBox = VertexBox;

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
  std::array<std::vector<float>, 3> lo, hi;     ///< float boxes, per axis (portable, superset)
  std::array<std::vector<double>, 3> dlo, dhi;  ///< exact boxes, per axis (AVX-512 path)
  std::array<std::vector<int>, 3> v;            ///< vertex ids (see GridPrimitives::ids)
  std::vector<std::uint32_t> flags;             ///< bit d: the box's first cell on axis d
  std::vector<std::uint32_t> gid;               ///< vertex id, V + face id or V + F + edge id
  std::vector<std::uint32_t> mask;              ///< candidate mask of the current row
};

/// Grid method: one chunk of cells processed by one task, with its own buffers.
/// Grid method: a task's buffers for one slab at a time of the counting sort (grid_sort.cpp).
struct GridSlabBuffers {
  std::vector<std::uint32_t> cell, tag, cursor;
};

struct GridChunk {
  GridCell cell;                       ///< the boxes of the current cell
  std::vector<std::uint64_t> vf_keys;  ///< pairs found in this chunk (see BroadPhaseScratch)
  std::vector<std::uint64_t> ee_keys;
  /// AVX-512 loop: the keys of rows 1, 2, 3 of a group of rows (cell_rows_avx512)
  std::array<std::vector<std::uint64_t>, 3> row_keys;
  std::int64_t reported = 0;  ///< box overlaps (statistics, see BroadPhaseStats)
};

/// Which code the Grid method's cell loop runs. All emit the same pairs in the same order with
/// the same close flags (tested); Auto takes AVX-512 when the CPU has it, else AVX2 when it has
/// that (checked at run time); Avx2 takes AVX2 even where AVX-512 is there (tests).
enum class GridIsa { Auto, Avx2, Portable };

/// True if GridIsa::Auto runs the AVX-512 cell loop on this CPU (AVX-512 F and VL, GCC x86-64).
bool grid_avx512_available();
/// True if the AVX2 cell loop can run on this CPU (AVX2, GCC x86-64).
bool grid_avx2_available();

}  // namespace detail

/// Scratch buffers reused between calls, so a steady-state call does not allocate.
struct BroadPhaseScratch {
  detail::GridIsa grid_isa =
      detail::GridIsa::Auto;  ///< tests set Portable or Avx2 to compare the cell loops
  /// find_candidates_in_vertex_boxes with the AVX-512 cell loop: test float boxes 16 lanes at a
  /// time and emit a superset of the exact pairs (see there); false: the exact pairs (tests and
  /// bench_broad_phase compare the two).
  bool grid_float_superset = true;
  /// find_candidates (exact pairs) with the AVX-512 cell loop: run the float loop of the
  /// superset, then confirm each of its pairs with the exact double test and set its close flag
  /// (grid_pairs' confirm_keys): the same pairs in the same order as the double loop, whose
  /// per-lane double tests cost more than the float cull plus one test per emitted pair. False:
  /// the double loop (tests compare the two).
  bool grid_float_confirm = true;
  std::vector<detail::BroadPhaseBox> vertex_boxes;  ///< indexed by vertex id
  std::vector<detail::BroadPhaseBox> face_boxes;    ///< indexed by face id
  std::vector<detail::BroadPhaseBox> edge_boxes;    ///< indexed by edge id
  std::vector<detail::BroadPhaseBox> work_a;        ///< copies CGAL may reorder
  std::vector<detail::BroadPhaseBox> work_b;
  std::vector<std::uint64_t> vf_keys;      ///< packed (vertex << 32 | face) pair keys
  /// find_candidates' sort of the Grid's VF [0] and EE [1] pairs: the keys, and the counts
  /// (then ends) of pairs per first id
  std::array<std::vector<std::uint64_t>, 2> sort_keys;
  std::array<std::vector<std::uint32_t>, 2> sort_counts;
  std::vector<std::uint64_t> ee_keys;      ///< packed (edge a << 32 | edge b) pair keys
  std::vector<detail::BvhNode> face_tree;  ///< Bvh method: tree over face boxes
  std::vector<int> face_order;             ///< face ids in leaf order
  std::vector<detail::BvhNode> edge_tree;  ///< Bvh method: tree over edge boxes
  std::vector<int> edge_order;             ///< edge ids in leaf order
  std::vector<int> stack;                  ///< traversal stack
  std::vector<detail::GridVertexBox> grid_vertex_boxes;  ///< Grid method: indexed by vertex id
  std::vector<detail::GridFloatBox> grid_vertex_floats;  ///< Grid: float vertex boxes
  std::vector<detail::GridRange> grid_vertex_ranges;     ///< Grid: cell ranges of the vertex boxes
  std::vector<detail::GridRange> grid_ranges;            ///< Grid: of vertex, face, then edge boxes
  std::vector<detail::GridChunk> chunks;    ///< Grid: per-chunk buffers of the cell loop
  std::vector<std::size_t> chunk_cells;     ///< Grid: first cell of each chunk, then #cells
  std::vector<double> extent_sample;        ///< Grid: box extents for the cell size
  std::vector<std::uint32_t> cell_start;    ///< Grid: CSR offsets per cell
  /// Grid's counting sort (grid_sort.cpp): per part and slab, its boxes (then their cursors)
  /// and its entries; each slab's first box and first entry; the slabs' box lists; their work
  std::vector<std::uint64_t> slab_counts;
  std::vector<std::uint64_t> slab_box_begin;
  std::vector<std::uint64_t> slab_entry_begin;
  std::vector<std::uint32_t> slab_boxes;
  std::vector<std::uint64_t> slab_work;
  /// Grid's counting sort: each thread's slab buffers, kept from call to call
  tbb::enumerable_thread_specific<detail::GridSlabBuffers> slab_buffers;
  std::vector<std::uint32_t> cell_fill;     ///< Grid: the patch's fill cursors, per cell
  std::vector<std::uint64_t> block_sums;    ///< Grid: the patched grid's pair work per block
  std::vector<std::uint32_t> cell_entries;  ///< Grid: box id << 3 | first-cell flags
  std::vector<std::size_t> chunk_offsets;   ///< Grid: each chunk's first output VF, then EE pair
  /// Grid: whether the grid of the last call (cell_start, cell_entries, grid_vertex_boxes and the
  /// geometry below) is complete and may be queried (query_kept_grid).
  bool grid_kept = false;
  std::array<double, 3> grid_origin{};     ///< Grid: its minimum corner
  double grid_inv_h = 1.0;                 ///< Grid: 1 / cell size
  std::array<std::size_t, 3> grid_dims{};  ///< Grid: cells per axis
  /// Grid: keep the last call's grid and patch its counting sort when it still fits, and start
  /// from its small cells after a crowded call (tests and benchmarks turn it off: every call
  /// then makes its grid afresh); grid_patch_always_rebuild keeps the grid but rebuilds the
  /// counting sort, so that a test can compare a patch with a rebuild on the same grid.
  bool grid_patch = true;
  bool grid_patch_always_rebuild = false;
  /// Grid: boxes whose cell range the last call patched, or -1 if it rebuilt the counting sort.
  std::int64_t grid_patched_boxes = -1;
  /// Grid: calls that skip the patch attempt and rebuild at once, after a failed attempt
  /// (grid_patch_skips left of the current backoff, grid_patch_backoff; see
  /// GRID_PATCH_MAX_BACKOFF). Depends only on the calls so far, never on the thread count.
  int grid_patch_skips = 0;
  int grid_patch_backoff = 0;
  /// Grid: calls that take GRID_SMALL_CELL_FACTOR from the start, after a call whose
  /// GRID_CELL_FACTOR cells were too crowded (grid_small_skips left of the current backoff,
  /// grid_small_backoff; see GRID_SMALL_CELL_MAX_BACKOFF). Depends only on the boxes so far.
  int grid_small_skips = 0;
  int grid_small_backoff = 0;
  std::vector<detail::GridRange> grid_vertex_ranges_prev;  ///< Grid: the last call's vertex ranges
  std::vector<std::uint64_t> grid_maybe_bits;   ///< Grid: boxes the patch recomputes (bitset)
  std::vector<std::uint32_t> grid_changed_ids;  ///< Grid: the patch's changed boxes
  std::vector<detail::GridRange> grid_changed_ranges;  ///< Grid: their new ranges
  std::vector<std::uint64_t> grid_changed_bits;        ///< Grid: the changed boxes as a bitset
  /// Grid: the topology (faces, then edges) the vertex-to-primitive lists were built for
  std::vector<int> grid_topology;
  std::size_t grid_topology_vertices = 0;
  std::vector<std::uint32_t> grid_vertex_prims_start;  ///< Grid: CSR offsets per vertex
  std::vector<std::uint32_t> grid_vertex_prims;  ///< Grid: each vertex's faces and edges (ids)
  std::vector<std::uint32_t> grid_add_start;     ///< Grid: the patch's new entries per cell
  std::vector<std::uint8_t> grid_dirty;          ///< Grid: per cell, the patch changes it
  std::vector<std::uint32_t> grid_adds;          ///< Grid: the patch's new entries (tags)
  std::vector<std::uint32_t> cell_start_next;    ///< Grid: the patch's output buffers
  std::vector<std::uint32_t> cell_entries_next;
  /// Grid: wall time of the last call's three parts, for diagnostics (0 for a part it did not
  /// reach): the grid (scene bounds, cell size, cell ranges, the counting sort or its patch),
  /// the cell loop, and the output of its pairs in chunk order.
  double grid_build_seconds = 0.0;
  double grid_cell_loop_seconds = 0.0;
  double grid_output_seconds = 0.0;
};

}  // namespace shellcontract
