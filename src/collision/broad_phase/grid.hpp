// The Grid method's shared pieces: its tuning constants, the grid's geometry, the per-primitive
// view of the vertex data, and the entry points of its parts (grid.cpp: construction and the
// portable cell loop; grid_patch.cpp: the kept grid's patch; grid_avx512.cpp and grid_avx2.cpp:
// the AVX-512 and AVX2 cell loops).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/broad_phase/scratch.hpp"

// The Grid method's AVX-512 cell loop needs GCC's target pragma and x86-64 (as cull_batch.cpp);
// other compilers get the portable loop only.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define SHELLCONTRACT_GRID_AVX512 1
#else
#define SHELLCONTRACT_GRID_AVX512 0
#endif

namespace shellcontract {
namespace detail {

/// Cell size over the median swept-box extent (the largest side of a face or edge box).
/// Smaller cells put each box in more cells (a dearer counting sort, fewer patches of the kept
/// grid); larger ones test more pairs per cell. lab/scripts/scale_benchmark.py --phases (its grid
/// and cell loop rows, bear and bear x16, one and two threads): 3 lies in the fastest range;
/// smaller factors are measurably slower per step, and larger ones approach the limit of
/// GRID_CROWDED_WORK_PER_BOX on the largest meshes (lab/pages/scale.md, lab/history.md).
constexpr double GRID_CELL_FACTOR = 3.0;
/// The cell size tried, over the same median extent, when GRID_CELL_FACTOR's cells would exceed
/// GRID_CROWDED_WORK_PER_BOX.
constexpr double GRID_SMALL_CELL_FACTOR = 1.5;
/// After a call that had to take the small cells, the next calls start with them (1, 2, 4, ...
/// up to this many, as GRID_PATCH_MAX_BACKOFF), so that a crowded scene does not build two grids
/// per call; then the large cells are tried again.
constexpr int GRID_SMALL_CELL_MAX_BACKOFF = 8;
/// Boxes sampled for the median extent; a sample keeps it O(1) and robust to a few huge boxes
/// (e.g. one vertex that flies off), which would drag a mean up.
constexpr std::size_t GRID_EXTENT_SAMPLES = 1024;
/// At most this many cells per box on average: caps the cell count (memory, the counting-sort
/// passes) when the boxes are tiny compared with the scene.
constexpr std::size_t GRID_CELLS_PER_BOX = 2;
/// At most this many (box, cell) entries per box on average; beyond it the cell size is doubled.
constexpr std::size_t GRID_ENTRIES_PER_BOX = 16;
/// Where the cells of GRID_CELL_FACTOR would make the per-cell pair loops visit more than this
/// many entry pairs per box, the cells of GRID_SMALL_CELL_FACTOR are tried.
constexpr std::int64_t GRID_CROWDED_WORK_PER_BOX = 256;
/// If the pair loops would still visit more than this many entry pairs per box (every box in a
/// few cells: boxes spread over a huge range, or nearly all of the scene overlapping), the grid
/// degenerates towards brute force, so PrimitiveBoxes (CGAL's box_intersection_d) runs instead
/// (same result). The limit is where the cell loop's cost per box (BM_GridCellLoop) matches what
/// PrimitiveBoxes costs per box on a scene with almost no overlaps
/// (BM_FindCandidates/PrimitiveBoxes); on a crowded scene PrimitiveBoxes costs much more, and a
/// lower limit made the largest meshes fall back to it and run several times slower per step
/// (lab/pages/scale.md, "Beyond a million faces"; lab/history.md).
constexpr std::int64_t GRID_WORK_PER_BOX = 1024;
/// The per-cell pair loops run as this many chunks of cells (about equal entry counts each), in
/// parallel with TBB; more chunks than threads balance the load (eight per thread on 16 cores:
/// the chunks' costs differ, as their work grows with the square of a cell's entries;
/// lab/history.md). The pairs come out in the same order for any number of chunks.
constexpr std::size_t GRID_CHUNKS = 128;
/// Grid reuse (temporal coherence, grid_pairs): a call keeps the last call's grid while the
/// desired cell size is within this factor of the kept one and the scene is inside the kept grid.
constexpr double GRID_REUSE_FACTOR = 1.25;
/// A new grid extends this many cells beyond the scene on every side (see GRID_REUSE_FACTOR).
constexpr double GRID_MARGIN_CELLS = 0.5;
/// The kept grid's counting sort is patched (patch_grid) if at most 1 / GRID_PATCH_DIVISOR of the
/// boxes changed their cell range, else rebuilt. Bear at P = 4: 7.2k of 83k boxes per step on
/// average; patching costs about a third of a rebuild there (lab/benchmarks/bench_broad_phase.cpp).
constexpr std::size_t GRID_PATCH_DIVISOR = 4;
/// After a failed patch attempt (too many changed boxes) the next calls rebuild without trying,
/// 1, 2, 4, ... up to this many calls, until an attempt succeeds again. On bear x16 every attempt
/// fails (its cells are small against the motion), and each cost a serial pass over the boxes
/// before the rebuild (lab/scripts/scale_benchmark.py --phases, the grid row).
constexpr int GRID_PATCH_MAX_BACKOFF = 8;
/// The kept grid is patched only in an arena of at most this many threads. The patch runs on
/// one thread, the rebuild on all. Up to two threads the serial patch is cheaper than the parallel
/// rebuild; a parallel patch has not paid so far (lab/kernels/collision_coherence.md, section 8).
/// The grid is the same either way: results do not depend on it.
constexpr int GRID_PATCH_MAX_THREADS = 2;
/// Cells per task of the patched grid's pass over its cells (the pair work).
constexpr std::size_t GRID_CELL_GRAIN = 16384;
/// Vertices per task of the grid's per-vertex loops.
constexpr std::size_t GRID_VERTEX_GRAIN = 2048;
/// Rows of the AVX-512 cell loop processed together (cell_rows_avx512). 2 rows were the fastest
/// in bench_broad_phase (lab/history.md): 4 rows' broadcast row values no longer fit the 32
/// vector registers. At most 4 (BroadPhaseScratch's row buffers).
constexpr int GRID_ROW_GROUP = 2;
static_assert(GRID_ROW_GROUP >= 1 && GRID_ROW_GROUP <= 4, "see detail::GridChunk::row_keys");
/// Ids are stored as gid << 3 | flags in 32 bits.
constexpr std::size_t GRID_MAX_BOXES = std::size_t{1} << 29;
/// Cells per axis fit the 16-bit fields of detail::GridRange.
constexpr double GRID_MAX_DIM = 65535.0;

/// Entry flags: bit d is set iff the cell is the box's first cell on axis d. Two overlapping
/// boxes meet in every cell of the intersection of their cell ranges; we emit the pair only in
/// the cell max(first cell of a, first cell of b) (per axis), i.e. where on every axis at least
/// one of the two is in its first cell: (flags_a | flags_b) == 7. Each pair is emitted once, no
/// hash set needed.
constexpr std::uint32_t GRID_ALL_FIRST = 7;

/// Uniform grid over the bounding box of all swept boxes (with a margin, and kept from call to
/// call while it fits: grid_pairs). coord() is monotone in x (a rounded subtraction, a
/// multiplication by a positive number, a clamp, a truncation of a non-negative value), so if two
/// boxes' closed intervals overlap on an axis, so do their cell ranges: no pair is lost to
/// rounding, and the exact double box test decides. Monotone also means the cell range of a union
/// of boxes is the union (min/max) of their cell ranges.
struct Grid {
  std::array<double, 3> origin{};
  double inv_h = 1.0;
  std::array<std::size_t, 3> dims{1, 1, 1};

  std::uint16_t coord(double x, std::size_t d) const {
    const double t = std::min((x - origin[d]) * inv_h, static_cast<double>(dims[d] - 1));
    return static_cast<std::uint16_t>(std::max(t, 0.0));
  }
  std::size_t cells() const { return dims[0] * dims[1] * dims[2]; }
};

/// Largest float <= x (the conversion rounds to nearest; step down if it went up). Infinite
/// results are still bounds: e.g. x = 1e300 gives FLT_MAX <= x.
inline float round_down(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity())
                                    : f;
}
inline float round_up(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

/// Per-primitive data of the grid, derived from the per-vertex data on the fly: stored face and
/// edge boxes would be megabytes per call and memory traffic dominated earlier versions, while
/// the vertex arrays and the topology stay in cache (lab/history.md).
struct GridPrimitives {
  const CollisionTopology& topo;
  const BroadPhaseScratch& s;
  std::size_t nv, nf;

  /// Vertex ids (detail::primitive_vertices).
  std::array<int, 3> ids(std::size_t gid) const { return detail::primitive_vertices(topo, gid); }
  static int corners(const std::array<int, 3>& v) { return detail::primitive_corners(v); }

  detail::GridRange range(const std::array<int, 3>& v) const {
    detail::GridRange r = s.grid_vertex_ranges[static_cast<std::size_t>(v[0])];
    for (int k = 1; k < corners(v); ++k) {
      const detail::GridRange& q = s.grid_vertex_ranges[static_cast<std::size_t>(v[k])];
      for (std::size_t d = 0; d < 3; ++d) {
        r.lo[d] = std::min(r.lo[d], q.lo[d]);
        r.hi[d] = std::max(r.hi[d], q.hi[d]);
      }
    }
    return r;
  }
  detail::GridFloatBox float_box(const std::array<int, 3>& v) const {
    detail::GridFloatBox b = s.grid_vertex_floats[static_cast<std::size_t>(v[0])];
    for (int k = 1; k < corners(v); ++k) {
      const detail::GridFloatBox& q = s.grid_vertex_floats[static_cast<std::size_t>(v[k])];
      for (std::size_t d = 0; d < 3; ++d) {
        b.lo[d] = std::min(b.lo[d], q.lo[d]);
        b.hi[d] = std::max(b.hi[d], q.hi[d]);
      }
    }
    return b;
  }
  /// The exact box: the same arithmetic as build_boxes, bit-identical to the other methods'.
  detail::GridVertexBox box(const std::array<int, 3>& v) const {
    return detail::primitive_box(s.grid_vertex_boxes, v);
  }
};

/// k (k - 1) / 2, the pairs among a cell's k entries (0 for k = 0: the product is 0).
inline std::uint64_t pairs_among(std::uint64_t k) { return k * (k - 1) / 2; }

inline bool overlap(const detail::GridVertexBox& a, const detail::GridVertexBox& b) {
  return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1] &&
         a.lo[2] <= b.hi[2] && b.lo[2] <= a.hi[2];
}

/// Calls visit(cell index, flags, valid) for the cells of a range. Ranges of at most 2 cells per
/// axis (nearly all, with cells about as large as the boxes) take a fixed 2x2x2 pattern with
/// `valid` false for the cells outside the range, so there are no data-dependent branches;
/// visit must do nothing for invalid cells (whose index is then the range's first cell).
template <class Visit>
void for_each_cell(const Grid& g, const detail::GridRange& r, Visit visit) {
  const std::size_t sx = 1, sy = g.dims[0], sz = g.dims[0] * g.dims[1];
  const std::size_t first = r.lo[0] * sx + r.lo[1] * sy + r.lo[2] * sz;
  const unsigned dx = r.hi[0] - r.lo[0], dy = r.hi[1] - r.lo[1], dz = r.hi[2] - r.lo[2];
  if ((dx | dy | dz) <= 1) {
    for (unsigned corner = 0; corner < 8; ++corner) {
      const unsigned ox = corner & 1u, oy = (corner >> 1) & 1u, oz = corner >> 2;
      const bool valid = ox <= dx && oy <= dy && oz <= dz;
      const std::size_t c = first + (valid ? ox * sx + oy * sy + oz * sz : 0);
      visit(c, (ox ^ 1u) | (oy ^ 1u) << 1 | (oz ^ 1u) << 2, valid);
    }
    return;
  }
  for (std::size_t z = r.lo[2]; z <= r.hi[2]; ++z)
    for (std::size_t y = r.lo[1]; y <= r.hi[1]; ++y) {
      const std::size_t row = z * sz + y * sy;
      const std::uint32_t fyz = (y == r.lo[1] ? 2u : 0u) | (z == r.lo[2] ? 4u : 0u);
      for (std::size_t x = r.lo[0]; x <= r.hi[0]; ++x)
        visit(row + x, fyz | (x == r.lo[0] ? 1u : 0u), true);
    }
}

/// True if, on some axis, the gap between the two boxes is larger than `threshold` (a negative
/// threshold asks for an overlap of at least -threshold).
inline bool gap_above(const detail::GridVertexBox& a, const detail::GridVertexBox& b,
                      double threshold) {
  return b.lo[0] - a.hi[0] > threshold || a.lo[0] - b.hi[0] > threshold ||
         b.lo[1] - a.hi[1] > threshold || a.lo[1] - b.hi[1] > threshold ||
         b.lo[2] - a.hi[2] > threshold || a.lo[2] - b.hi[2] > threshold;
}

void build_grid_vertex_boxes(const Positions& x0, const Positions& x1, double inflation,
                             std::vector<detail::GridVertexBox>& boxes);

/// The first level of the counting sort of the boxes into the cells of g (grid_sort.cpp): sets
/// s.grid_ranges to the boxes' cell ranges and counts their entries per slab. Returns the number
/// of (cell, box) entries.
std::uint64_t grid_sort_count(const Grid& g, const GridPrimitives& prim, std::size_t nboxes,
                              BroadPhaseScratch& s);
/// The rest of that counting sort, after grid_sort_count on the same grid: s.cell_start and
/// s.cell_entries, each cell listing its boxes (id << 3 | first-cell flags) in increasing id
/// order. Returns the pair work, the sum over the cells of k (k - 1) / 2 for k entries.
std::uint64_t grid_sort_fill(const Grid& g, std::size_t nboxes, std::uint64_t entries,
                             BroadPhaseScratch& s);

/// Updates the kept grid's counting sort (s.cell_start, s.cell_entries over s.grid_ranges) for
/// this call's vertex ranges (s.grid_vertex_ranges; the last call's, on the same grid g, in
/// s.grid_vertex_ranges_prev): the boxes whose range changed leave their old cells and enter
/// their new ones, and s.grid_ranges gets their new ranges. Only a box with a vertex whose range
/// changed can change (a box's range is the union of its vertices'; the topology is compared
/// with the last call's, and if it differs every box is recomputed). The result is what the
/// counting sort builds from the new ranges (each cell lists its boxes in increasing id order,
/// with the same flags), because an entry depends only on its box's id and range. Returns false,
/// leaving the counting sort as it was, if more than nboxes / GRID_PATCH_DIVISOR ranges changed
/// (s.grid_ranges is then stale: the caller rebuilds it).
bool patch_grid(const Grid& g, const GridPrimitives& prim, std::size_t nboxes,
                BroadPhaseScratch& s);

/// The chunks' keys (a << shift | b) << 1 | close of one kind (vf: the VF lists, else the EE
/// lists; unique pairs) into pairs[0..] and close[0..], sorted by (a, b): a counting sort by a
/// (ids below `firsts`), then each a's few keys sorted among themselves. Linear in the pairs and
/// the ids, where a comparison sort of all the pairs is not.
/// count and sorted are its buffers, kept from call to call (grid_output.cpp).
void sort_chunk_keys(const std::vector<GridChunk>& chunks, bool vf, int shift, std::size_t firsts,
                     std::vector<std::uint32_t>& count, std::vector<std::uint64_t>& sorted,
                     NoZeroVector<std::array<int, 2>>& pairs, NoZeroVector<std::uint8_t>& close);

/// Method Grid (x0, x1 already in s.grid_vertex_boxes). A pair whose two boxes have a gap above
/// far_gap on some axis is flagged 0 in out's close flags (see find_candidates). With
/// float_superset and the AVX-512 loop, the pairs whose float boxes overlap, all flagged close
/// (see find_candidates_in_vertex_boxes). Returns -1
/// (nothing done) if the grid would degenerate (see GRID_WORK_PER_BOX), otherwise the number of
/// box pairs that overlap after rounding outward to float, adjacent ones included (VF, plus EE
/// once per unordered pair).
/// With `sorted`, the pairs are sorted by (first id, second id), each with its flag
/// (find_candidates, find_candidates_in_vertex_boxes); otherwise they come in the order of the
/// chunks, cells and rows, which does not depend on the thread count either but does on the grid
/// kept from the last call.
std::int64_t grid_pairs(const CollisionTopology& topo, double far_gap, CandidatePairs& out,
                        bool float_superset = false, bool sorted = false);

#if SHELLCONTRACT_GRID_AVX512
/// The cells [c0, c1) of the grid with the AVX-512 rows: the same cells, rows and pairs as the
/// portable loop in grid_pairs, on exact boxes (cell_rows_avx512), or with Float a superset of
/// them on float boxes (cell_rows_avx512_float; far_gap unused). The key buffers serve as their
/// own capacity and are trimmed at the end.
template <bool Float>
void grid_chunk_avx512(const GridPrimitives& prim, const std::uint32_t* start,
                       const std::uint32_t* entry, std::size_t c0, std::size_t c1, int vf_shift,
                       int ee_shift, double far_gap, detail::GridChunk& out_chunk);
/// The cells [c0, c1) with the AVX2 rows (grid_avx2.cpp): the keys of cell_rows_avx512_float
/// (a superset of the exact pairs, every key flagged close) on 8 float lanes, in the same order.
void grid_chunk_avx2(const GridPrimitives& prim, const std::uint32_t* start,
                     const std::uint32_t* entry, std::size_t c0, std::size_t c1, int vf_shift,
                     int ee_shift, detail::GridChunk& out_chunk);
#endif

}  // namespace detail
}  // namespace shellcontract
