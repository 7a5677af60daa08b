// The Grid method's counting sort of the boxes into their cells, in two levels: the boxes go
// first into slabs (runs of whole grid rows, cut by cells, not by threads), then each slab sorts
// its own boxes into its own cells. A flat counting sort over all cells kept a counter per cell
// for every part of the boxes (megabytes per part on the largest meshes) and scattered the
// entries of neighbouring parts into the same cache lines, so it hardly ran faster on many
// cores than on one (lab/pages/scale.md, "Sixteen cores"; lab/history.md). Here a
// slab's counters and entries fit in a core's L2 and no two tasks write the same slab.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <vector>

#include "collision/broad_phase/grid.hpp"

#if SHELLCONTRACT_GRID_AVX512
#include <immintrin.h>
#endif

namespace shellcontract {
namespace detail {

namespace {

/// Parts of the boxes (contiguous id ranges) of the first level: a fixed number, so that the
/// work does not depend on the thread count; part p's boxes of a slab follow those of parts < p.
constexpr std::size_t SORT_PARTS = 64;
/// A slab has at most this many cells (its 4-byte counters stay in a core's L2 beside the
/// entries it writes), or one row if a row has more ...
constexpr std::size_t SLAB_MAX_CELLS = 16384;
/// ... and there are about this many slabs, for load balance on many cores.
constexpr std::size_t SLAB_TARGET = 256;

struct Slabs {
  std::size_t dx = 1, dy = 1, rows = 1;  // a row: the cells of one (y, z)
  std::size_t rows_per_slab = 1, count = 1;
};

Slabs slabs_of(const Grid& g) {
  Slabs s;
  s.dx = g.dims[0];
  s.dy = g.dims[1];
  s.rows = g.dims[1] * g.dims[2];
  const std::size_t cells = std::clamp<std::size_t>(g.cells() / SLAB_TARGET, 1, SLAB_MAX_CELLS);
  s.rows_per_slab = std::max<std::size_t>(1, cells / s.dx);
  s.count = (s.rows + s.rows_per_slab - 1) / s.rows_per_slab;
  return s;
}

/// Calls visit(slab, entries) once for each slab that range r has cells in, in increasing slab
/// order, with the number of its cells there. Rows increase with z, so the slabs do too.
template <class Visit>
void for_each_slab(const Slabs& sl, const GridRange& r, Visit visit) {
  const std::size_t nx = std::size_t{r.hi[0]} - r.lo[0] + 1;
  std::size_t current = sl.count, entries = 0;
  for (std::size_t z = r.lo[2]; z <= r.hi[2]; ++z) {
    std::size_t row = r.lo[1] + z * sl.dy;
    const std::size_t last = r.hi[1] + z * sl.dy;
    while (row <= last) {
      const std::size_t slab = row / sl.rows_per_slab;
      const std::size_t end = std::min(last, (slab + 1) * sl.rows_per_slab - 1);
      if (slab != current) {
        if (current != sl.count) visit(current, entries);
        current = slab;
        entries = 0;
      }
      entries += (end - row + 1) * nx;
      row = end + 1;
    }
  }
  if (current != sl.count) visit(current, entries);
}

/// Calls visit(local cell, flags) for the cells of range r in rows [row0, row1), the local cell
/// counted from row0's first cell; flags as in for_each_cell (bit d: the box's first cell on d).
template <class Visit>
void for_each_cell_in_rows(const Slabs& sl, const GridRange& r, std::size_t row0, std::size_t row1,
                           Visit visit) {
  for (std::size_t z = r.lo[2]; z <= r.hi[2]; ++z) {
    const std::size_t zrow = z * sl.dy;
    // The rows y + zrow of this layer inside [row0, row1), as y in [y0, y1].
    if (zrow + r.hi[1] < row0 || zrow + r.lo[1] >= row1) continue;
    const std::size_t y0 = std::max<std::size_t>(r.lo[1], row0 > zrow ? row0 - zrow : 0);
    const std::size_t y1 = std::min<std::size_t>(r.hi[1], row1 - 1 - zrow);
    const std::uint32_t fz = z == r.lo[2] ? 4u : 0u;
    for (std::size_t y = y0; y <= y1; ++y) {
      const std::size_t base = (zrow + y - row0) * sl.dx;
      const std::uint32_t fyz = fz | (y == r.lo[1] ? 2u : 0u);
      for (std::size_t x = r.lo[0]; x <= r.hi[0]; ++x)
        visit(base + x, fyz | (x == r.lo[0] ? 1u : 0u));
    }
  }
}

/// Appends the cells of range r in rows [row0, row1) (local cell, as in for_each_cell_in_rows)
/// and their tags (tag | flags) at cell[n], tag[n]; returns the new n. The arrays need 8 spare
/// slots: a range of at most 2 cells per axis (nearly all) writes its 2x2x2 pattern and keeps
/// the valid cells, with no data-dependent branch.
std::size_t emit_cells_in_rows(const Slabs& sl, const GridRange& r, std::size_t row0,
                               std::size_t row1, std::uint32_t tag, std::uint32_t* cell,
                               std::uint32_t* tags, std::size_t n) {
  const unsigned ex = r.hi[0] - r.lo[0], ey = r.hi[1] - r.lo[1], ez = r.hi[2] - r.lo[2];
  if ((ex | ey | ez) <= 1) {
    for (unsigned corner = 0; corner < 8; ++corner) {
      const unsigned ox = corner & 1u, oy = (corner >> 1) & 1u, oz = corner >> 2;
      const std::size_t row = r.lo[1] + oy + (r.lo[2] + oz) * sl.dy;
      const bool valid = (ox <= ex) & (oy <= ey) & (oz <= ez) & (row >= row0) & (row < row1);
      cell[n] = static_cast<std::uint32_t>(valid ? (row - row0) * sl.dx + r.lo[0] + ox : 0);
      tags[n] = tag | (ox ^ 1u) | (oy ^ 1u) << 1 | (oz ^ 1u) << 2;
      n += valid;
    }
    return n;
  }
  for_each_cell_in_rows(sl, r, row0, row1, [&](std::size_t c, std::uint32_t flags) {
    cell[n] = static_cast<std::uint32_t>(c);
    tags[n++] = tag | flags;
  });
  return n;
}

#if SHELLCONTRACT_GRID_AVX512
#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl")
/// emit_cells_in_rows with the 2x2x2 pattern in eight 32-bit lanes: the same cells and tags in
/// the same order (a compress keeps the lanes' order, corner 0 first), two stores per box
/// instead of sixteen. Cells and rows fit 32 bits: a grid has at most 2 boxes' worth of cells
/// (GRID_CELLS_PER_BOX), and fewer than GRID_MAX_BOXES boxes.
std::size_t emit_cells_in_rows_avx512(const Slabs& sl, const GridRange& r, std::size_t row0,
                                      std::size_t row1, std::uint32_t tag, std::uint32_t* cell,
                                      std::uint32_t* tags, std::size_t n) {
  const unsigned ex = r.hi[0] - r.lo[0], ey = r.hi[1] - r.lo[1], ez = r.hi[2] - r.lo[2];
  if ((ex | ey | ez) > 1) return emit_cells_in_rows(sl, r, row0, row1, tag, cell, tags, n);
  const __m256i corner = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i one = _mm256_set1_epi32(1);
  const __m256i ox = _mm256_and_si256(corner, one);
  const __m256i oy = _mm256_and_si256(_mm256_srli_epi32(corner, 1), one);
  const __m256i oz = _mm256_srli_epi32(corner, 2);
  const __m256i row = _mm256_add_epi32(
      _mm256_add_epi32(_mm256_set1_epi32(r.lo[1]), oy),
      _mm256_mullo_epi32(_mm256_add_epi32(_mm256_set1_epi32(r.lo[2]), oz),
                         _mm256_set1_epi32(static_cast<int>(sl.dy))));
  const __m256i r0 = _mm256_set1_epi32(static_cast<int>(row0));
  const __mmask8 valid = _mm256_cmple_epu32_mask(ox, _mm256_set1_epi32(static_cast<int>(ex))) &
                         _mm256_cmple_epu32_mask(oy, _mm256_set1_epi32(static_cast<int>(ey))) &
                         _mm256_cmple_epu32_mask(oz, _mm256_set1_epi32(static_cast<int>(ez))) &
                         _mm256_cmpge_epu32_mask(row, r0) &
                         _mm256_cmplt_epu32_mask(row, _mm256_set1_epi32(static_cast<int>(row1)));
  const __m256i c = _mm256_add_epi32(
      _mm256_mullo_epi32(_mm256_sub_epi32(row, r0), _mm256_set1_epi32(static_cast<int>(sl.dx))),
      _mm256_add_epi32(_mm256_set1_epi32(r.lo[0]), ox));
  // The flags of corner k are those of the scalar path: (ox ^ 1) | (oy ^ 1) << 1 | (oz ^ 1) << 2.
  const __m256i t = _mm256_or_si256(_mm256_set1_epi32(static_cast<int>(tag)),
                                    _mm256_sub_epi32(_mm256_set1_epi32(7), corner));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(cell + n), _mm256_maskz_compress_epi32(valid, c));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(tags + n), _mm256_maskz_compress_epi32(valid, t));
  return n + static_cast<std::size_t>(__builtin_popcount(valid));
}
#pragma GCC pop_options
#endif

}  // namespace

std::uint64_t grid_sort_count(const Grid& g, const GridPrimitives& prim, std::size_t nboxes,
                              BroadPhaseScratch& s) {
  const Slabs sl = slabs_of(g);
  // Per part and slab: its boxes, then its entries (slab_counts[2 (p * slabs + slab) + 0/1]).
  s.slab_counts.assign(2 * SORT_PARTS * sl.count, 0);
  s.grid_ranges.resize(nboxes);
  tbb::parallel_for(std::size_t{0}, SORT_PARTS, [&](std::size_t p) {
    std::uint64_t* counts = s.slab_counts.data() + 2 * p * sl.count;
    for (std::size_t i = nboxes * p / SORT_PARTS; i < nboxes * (p + 1) / SORT_PARTS; ++i) {
      s.grid_ranges[i] = prim.range(prim.ids(i));
      for_each_slab(sl, s.grid_ranges[i], [&](std::size_t slab, std::size_t entries) {
        counts[2 * slab] += 1;
        counts[2 * slab + 1] += entries;
      });
    }
  });
  std::uint64_t entries = 0;
  for (std::size_t k = 1; k < s.slab_counts.size(); k += 2) entries += s.slab_counts[k];
  return entries;
}

std::uint64_t grid_sort_fill(const Grid& g, std::size_t nboxes, std::uint64_t entries,
                             BroadPhaseScratch& s) {
  const Slabs sl = slabs_of(g);
  assert(s.slab_counts.size() == 2 * SORT_PARTS * sl.count);
  // Offsets: slab_box_begin[slab] and slab_entry_begin[slab]; the parts' counts of boxes become
  // their cursors in the slab's box list, in place.
  s.slab_box_begin.assign(sl.count + 1, 0);
  s.slab_entry_begin.assign(sl.count + 1, 0);
  std::uint64_t boxes = 0, before = 0;
  for (std::size_t slab = 0; slab < sl.count; ++slab) {
    s.slab_box_begin[slab] = boxes;
    s.slab_entry_begin[slab] = before;
    for (std::size_t p = 0; p < SORT_PARTS; ++p) {
      std::uint64_t* c = s.slab_counts.data() + 2 * (p * sl.count + slab);
      const std::uint64_t k = c[0];
      c[0] = boxes;
      boxes += k;
      before += c[1];
    }
  }
  s.slab_box_begin[sl.count] = boxes;
  s.slab_entry_begin[sl.count] = before;
  assert(before == entries);

  // First level: each part appends its boxes, in id order, to the lists of the slabs they touch.
  s.slab_boxes.resize(boxes);
  tbb::parallel_for(std::size_t{0}, SORT_PARTS, [&](std::size_t p) {
    std::uint64_t* cursor = s.slab_counts.data() + 2 * p * sl.count;
    for (std::size_t i = nboxes * p / SORT_PARTS; i < nboxes * (p + 1) / SORT_PARTS; ++i)
      for_each_slab(sl, s.grid_ranges[i], [&](std::size_t slab, std::size_t) {
        s.slab_boxes[cursor[2 * slab]++] = static_cast<std::uint32_t>(i);
      });
  });

  // Second level: each slab counts its cells' entries, writes their offsets and scatters its
  // boxes into them. Its boxes come in id order, so each cell lists its boxes in id order (the
  // same lists as a flat counting sort: vertices, then faces, then edges, each by id).
  std::vector<std::uint32_t>& start = s.cell_start;
  start.resize(g.cells() + 1);
  start[0] = 0;
  s.cell_entries.resize(entries);
  s.slab_work.assign(sl.count, 0);
  // The AVX-512 emission where the cell loop is AVX-512 too (GridIsa::Portable: neither).
  const bool avx512 = s.grid_isa == GridIsa::Auto && grid_avx512_available();
  (void)avx512;
  tbb::parallel_for(std::size_t{0}, sl.count, [&](std::size_t slab) {
    const std::size_t row0 = slab * sl.rows_per_slab;
    const std::size_t row1 = std::min(sl.rows, row0 + sl.rows_per_slab);
    const std::size_t first_cell = row0 * sl.dx, ncell = (row1 - row0) * sl.dx;
    const std::size_t nentries = s.slab_entry_begin[slab + 1] - s.slab_entry_begin[slab];
    GridSlabBuffers& buf = s.slab_buffers.local();
    buf.cursor.assign(ncell, 0);
    if (buf.cell.size() < nentries + 8) {
      buf.cell.resize(nentries + 8);
      buf.tag.resize(nentries + 8);
    }
    // The slab's entries in box id order, then counted and scattered from the buffer: the
    // enumeration of a box's cells (which branches) runs once.
    const std::uint32_t* ids = s.slab_boxes.data() + s.slab_box_begin[slab];
    const std::size_t nids = s.slab_box_begin[slab + 1] - s.slab_box_begin[slab];
    std::size_t n = 0;
#if SHELLCONTRACT_GRID_AVX512
    if (avx512)
      for (std::size_t k = 0; k < nids; ++k)
        n = emit_cells_in_rows_avx512(sl, s.grid_ranges[ids[k]], row0, row1, ids[k] << 3,
                                      buf.cell.data(), buf.tag.data(), n);
    else
#endif
      for (std::size_t k = 0; k < nids; ++k)
        n = emit_cells_in_rows(sl, s.grid_ranges[ids[k]], row0, row1, ids[k] << 3,
                               buf.cell.data(), buf.tag.data(), n);
    assert(n == nentries);
    std::uint32_t* cursor = buf.cursor.data();
    for (std::size_t i = 0; i < n; ++i) ++cursor[buf.cell[i]];
    std::uint32_t offset = static_cast<std::uint32_t>(s.slab_entry_begin[slab]);
    std::uint64_t work = 0;
    for (std::size_t c = 0; c < ncell; ++c) {
      const std::uint32_t k = cursor[c];
      work += pairs_among(k);
      cursor[c] = offset;
      offset += k;
      start[first_cell + c + 1] = offset;
    }
    std::uint32_t* entry = s.cell_entries.data();
    for (std::size_t i = 0; i < n; ++i) entry[cursor[buf.cell[i]]++] = buf.tag[i];
    s.slab_work[slab] = work;
  });
  std::uint64_t work = 0;
  for (const std::uint64_t w : s.slab_work) work += w;
  return work;
}

}  // namespace detail
}  // namespace shellcontract
