// The Grid method (BroadPhaseMethod::Grid): the grid over the swept boxes, its counting sort, the
// portable cell loop, and the output of the pairs in chunk order.
#include "collision/broad_phase/grid.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/stage_timer.hpp"

namespace shellcontract {
namespace detail {

namespace {

/// Grid with cell size h over [lo, hi], at most max_cells cells (h grows if needed).
Grid make_grid(const std::array<double, 3>& lo, const std::array<double, 3>& hi, double h,
               std::size_t max_cells) {
  Grid g;
  g.origin = lo;
  for (;;) {
    std::size_t n = 1;
    for (std::size_t d = 0; d < 3; ++d) {
      // Clamped in double first: (hi - lo) / h may exceed any integer for a tiny h.
      const double cells = std::min(std::floor((hi[d] - lo[d]) / h) + 1.0, GRID_MAX_DIM);
      g.dims[d] = static_cast<std::size_t>(cells);
      n *= g.dims[d];
    }
    if (n <= max_cells) break;
    h *= std::max(1.01, std::cbrt(static_cast<double>(n) / static_cast<double>(max_cells)));
  }
  g.inv_h = 1.0 / h;
  return g;
}

int bit_width(std::uint64_t v) {
  int n = 0;
  while (v != 0) {
    ++n;
    v >>= 1;
  }
  return n;
}

/// Unpacks keys (a << shift | b) << 1 | close into pairs[at..] and close[at..].
void unpack_keys(const std::vector<std::uint64_t>& keys, int shift, std::size_t at,
                 NoZeroVector<std::array<int, 2>>& pairs, NoZeroVector<std::uint8_t>& close) {
  const std::uint64_t mask = (std::uint64_t{1} << shift) - 1;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const std::uint64_t k = keys[i] >> 1;
    pairs[at + i] = {static_cast<int>(k >> shift), static_cast<int>(k & mask)};
    close[at + i] = static_cast<std::uint8_t>(keys[i] & 1u);
  }
}

/// Keeps the keys ((p << shift | q) << 1 | close) of `keys` whose pair's exact double boxes
/// overlap, in order, with close set as the double cell loop sets it (0 iff gap_above(box p,
/// box q, far_gap); gap_above is symmetric in its boxes). The float loop's keys are a superset
/// of the double loop's, emitted by the same cells, rows and lanes in the same order (the two
/// loops differ only in the box test), so the kept keys are the double loop's, in its order.
/// p is a vertex and q a face (vf), or p and q are edges.
[[maybe_unused]] void confirm_keys(const GridPrimitives& prim, bool vf, int shift, double far_gap,
                  std::vector<std::uint64_t>& keys) {
  const std::uint64_t mask = (std::uint64_t{1} << shift) - 1;
  const CollisionTopology& topo = prim.topo;
  std::size_t kept = 0;
  for (const std::uint64_t k : keys) {
    const std::uint64_t body = k >> 1;
    const auto p = static_cast<Eigen::Index>(body >> shift);
    const auto q = static_cast<Eigen::Index>(body & mask);
    const detail::GridVertexBox a =
        vf ? prim.s.grid_vertex_boxes[static_cast<std::size_t>(p)]
           : prim.box({topo.edges(p, 0), topo.edges(p, 1), -2});
    const detail::GridVertexBox b =
        vf ? prim.box({topo.faces(q, 0), topo.faces(q, 1), topo.faces(q, 2)})
           : prim.box({topo.edges(q, 0), topo.edges(q, 1), -2});
    if (!overlap(a, b)) continue;
    keys[kept++] = body << 1 | (gap_above(a, b, far_gap) ? 0u : 1u);
  }
  keys.resize(kept);
}

/// Item i of the current cell against items [j0, j1): mask[j] = 1 iff the pair passes the dedupe
/// flags, the float box test and the adjacency test. Plain loops over structure-of-arrays data,
/// written so that the compiler vectorizes them (no branches, 32-bit lanes throughout); they are
/// the hot loop (~10^6 pairs on bear). Adds the number of flag-and-box hits (adjacent pairs
/// included) to `hits`, for the statistics; returns whether any mask is set (most rows have
/// none, and then the caller skips its scan).
bool cell_masks(const detail::GridCell& cell, std::size_t i, std::size_t j0, std::size_t j1,
                std::uint32_t* mask, std::int64_t& hits) {
  const float lx = cell.lo[0][i], ly = cell.lo[1][i], lz = cell.lo[2][i];
  const float hx = cell.hi[0][i], hy = cell.hi[1][i], hz = cell.hi[2][i];
  const std::uint32_t fi = cell.flags[i];
  const int a = cell.v[0][i], b = cell.v[1][i], c = cell.v[2][i];
  const float* __restrict qlx = cell.lo[0].data();
  const float* __restrict qly = cell.lo[1].data();
  const float* __restrict qlz = cell.lo[2].data();
  const float* __restrict qhx = cell.hi[0].data();
  const float* __restrict qhy = cell.hi[1].data();
  const float* __restrict qhz = cell.hi[2].data();
  const std::uint32_t* __restrict qf = cell.flags.data();
  const int* __restrict qa = cell.v[0].data();
  const int* __restrict qb = cell.v[1].data();
  const int* __restrict qc = cell.v[2].data();
  std::uint32_t box_hits = 0, any = 0;
  for (std::size_t j = j0; j < j1; ++j) {
    const std::uint32_t box = static_cast<std::uint32_t>(
        ((fi | qf[j]) == GRID_ALL_FIRST) & (lx <= qhx[j]) & (qlx[j] <= hx) & (ly <= qhy[j]) &
        (qly[j] <= hy) & (lz <= qhz[j]) & (qlz[j] <= hz));
    // Adjacent iff a vertex id is shared; the -1/-2 placeholders never match (see ids()).
    const std::uint32_t apart =
        static_cast<std::uint32_t>((a != qa[j]) & (a != qb[j]) & (a != qc[j]) & (b != qa[j]) &
                                   (b != qb[j]) & (c != qa[j]) & (c != qb[j]));
    box_hits += box;
    mask[j] = box & apart;
    any |= box & apart;
  }
  hits += box_hits;
  return any != 0;
}

}  // namespace

std::int64_t grid_pairs(const CollisionTopology& topo, double far_gap, CandidatePairs& out,
                        bool float_superset, bool sorted) {
  BroadPhaseScratch& s = *out.scratch;
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  const std::size_t nf = static_cast<std::size_t>(topo.faces.rows());
  const std::size_t ne = static_cast<std::size_t>(topo.edges.rows());
  const std::size_t nboxes = nv + nf + ne;
  // The output lists are cleared only where nothing is found; the output stage sizes them with
  // resize_for_rewrite, which writes nothing.
  auto nothing = [&](std::int64_t result) {
    out.vertex_face.clear();
    out.edge_edge.clear();
    out.vertex_face_close.clear();
    out.edge_edge_close.clear();
    return result;
  };
  const StageTimer t_start;
  s.grid_build_seconds = s.grid_cell_loop_seconds = s.grid_output_seconds = 0.0;
  // The last call's grid, if complete, and what it was built for (see patch_grid).
  const bool had_grid = s.grid_kept && s.grid_ranges.size() == nboxes &&
                        s.cell_start.size() == s.grid_dims[0] * s.grid_dims[1] * s.grid_dims[2] + 1;
  s.grid_kept = false;
  s.grid_patched_boxes = -1;
  if (nv == 0) return nothing(0);
  if (nboxes >= GRID_MAX_BOXES) return nothing(-1);
  const GridPrimitives prim{topo, s, nv, nf};
  const std::vector<detail::GridVertexBox>& vbox = s.grid_vertex_boxes;

  // Scene bounds: every face and edge box is a union of vertex boxes.
  std::array<double, 3> lo = vbox[0].lo, hi = vbox[0].hi;
  for (const detail::GridVertexBox& b : vbox)
    for (std::size_t d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], b.lo[d]);
      hi[d] = std::max(hi[d], b.hi[d]);
    }

  // Cell size from the median largest side of a deterministic sample of face and edge boxes.
  s.extent_sample.clear();
  const std::size_t stride = std::max<std::size_t>(1, (nf + ne) / GRID_EXTENT_SAMPLES);
  for (std::size_t i = nv; i < nboxes; i += stride) {
    const detail::GridVertexBox b = prim.box(prim.ids(i));
    s.extent_sample.push_back(std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]}));
  }
  double median_extent = 0.0;
  if (!s.extent_sample.empty()) {
    const auto mid =
        s.extent_sample.begin() + static_cast<std::ptrdiff_t>(s.extent_sample.size() / 2);
    std::nth_element(s.extent_sample.begin(), mid, s.extent_sample.end());
    median_extent = *mid;
  }
  const bool small_cells = s.grid_patch && s.grid_small_skips > 0;
  if (small_cells) --s.grid_small_skips;
  double h = (small_cells ? GRID_SMALL_CELL_FACTOR : GRID_CELL_FACTOR) * median_extent;
  const double span = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  // Degenerate extents (points: no motion, no inflation, zero-length edges) or no primitives.
  if (!(h > 0.0)) h = span > 0.0 ? span : 1.0;

  // Float boxes relative to the scene minimum (better precision than absolute coordinates).
  // Each double is rounded outward after the subtraction; the rounded subtraction is monotone,
  // so whenever two double boxes overlap, so do their float boxes: the float test only culls.
  // The AVX-512 double cell loop tests the double boxes directly and needs none; the float
  // loop emits a superset from float boxes alone, which a caller takes as it is (float_superset:
  // find_candidates_in_vertex_boxes) or which confirm_keys cuts to the exact pairs
  // (grid_float_confirm).
  const bool avx512 = s.grid_isa == detail::GridIsa::Auto && detail::grid_avx512_available();
  // Without AVX-512, the exact pairs come from the AVX2 float loop and the confirmation (the
  // same pairs, order and flags). The superset for find_candidates_in_vertex_boxes keeps the
  // portable loop there: its callers take the pairs as they come, so they stay the exact ones.
  const bool avx2 = !avx512 && s.grid_isa != detail::GridIsa::Portable && s.grid_float_confirm &&
                    !float_superset && detail::grid_avx2_available();
  const bool float_cells = (avx512 && (float_superset || s.grid_float_confirm)) || avx2;
  [[maybe_unused]] const bool confirm = float_cells && !float_superset;
  s.grid_vertex_floats.resize(avx512 && !float_cells ? 0 : nv);
  if (float_cells) {
    // The superset loop needs only a monotone map from the doubles to the floats (it keeps
    // every overlap: a <= b implies f(a) <= f(b)), and a rounded subtraction followed by a
    // rounded conversion is one; the outward rounding of the portable path costs much more here
    // (bench_broad_phase; lab/history.md).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, GRID_VERTEX_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t v = r.begin(); v < r.end(); ++v)
                          for (std::size_t d = 0; d < 3; ++d) {
                            detail::GridFloatBox& f = s.grid_vertex_floats[v];
                            f.lo[d] = static_cast<float>(vbox[v].lo[d] - lo[d]);
                            f.hi[d] = static_cast<float>(vbox[v].hi[d] - lo[d]);
                          }
                      });
  } else if (!avx512) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, GRID_VERTEX_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t v = r.begin(); v < r.end(); ++v)
                          for (std::size_t d = 0; d < 3; ++d) {
                            s.grid_vertex_floats[v].lo[d] = round_down(vbox[v].lo[d] - lo[d]);
                            s.grid_vertex_floats[v].hi[d] = round_up(vbox[v].hi[d] - lo[d]);
                          }
                      });
  }

  // Count the (cell, box) entries per cell; double the cell size while there are too many.
  const std::size_t max_cells = std::max<std::size_t>(64, GRID_CELLS_PER_BOX * nboxes);
  Grid g;
  std::vector<std::uint32_t>& start = s.cell_start;
  std::size_t entries = 0;
  auto vertex_ranges = [&] {
    s.grid_vertex_ranges.resize(nv);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, GRID_VERTEX_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t v = r.begin(); v < r.end(); ++v)
                          for (std::size_t d = 0; d < 3; ++d) {
                            s.grid_vertex_ranges[v].lo[d] = g.coord(vbox[v].lo[d], d);
                            s.grid_vertex_ranges[v].hi[d] = g.coord(vbox[v].hi[d], d);
                          }
                      });
  };
  // Temporal coherence: from one step to the next most boxes keep their cell ranges, so the
  // last call's grid is kept while its cell size is still about the desired one and the scene
  // is inside it, and its counting sort is patched for the boxes that changed ranges.
  bool reuse = had_grid && s.grid_patch;
  if (reuse) {
    const double kept_h = 1.0 / s.grid_inv_h;
    reuse = kept_h <= GRID_REUSE_FACTOR * h && h <= GRID_REUSE_FACTOR * kept_h;
    for (std::size_t d = 0; d < 3 && reuse; ++d)
      reuse = lo[d] >= s.grid_origin[d] &&
              (hi[d] - s.grid_origin[d]) * s.grid_inv_h < static_cast<double>(s.grid_dims[d]);
  }
  bool patched = false;
  if (reuse) {
    g.origin = s.grid_origin;
    g.inv_h = s.grid_inv_h;
    g.dims = s.grid_dims;
    // The last call's vertex ranges are on this grid too (it kept it, or made it): patch_grid
    // compares them with this call's.
    s.grid_vertex_ranges_prev.swap(s.grid_vertex_ranges);
    vertex_ranges();
    // A patch is serial and a rebuild parallel: past GRID_PATCH_MAX_THREADS the rebuild wins.
    if (!s.grid_patch_always_rebuild &&
        tbb::this_task_arena::max_concurrency() <= GRID_PATCH_MAX_THREADS) {
      if (s.grid_patch_skips > 0) {
        --s.grid_patch_skips;
      } else {
        patched = patch_grid(g, prim, nboxes, s);
        s.grid_patch_backoff =
            patched ? 0 : std::min(std::max(1, 2 * s.grid_patch_backoff), GRID_PATCH_MAX_BACKOFF);
        s.grid_patch_skips = s.grid_patch_backoff;
      }
    }
    if (patched) entries = start[g.cells()];
  }
  // A new grid of cell size `cell`, its vertex ranges and its entry count, the cell doubled while
  // the entries are too many.
  auto new_grid = [&](double cell) {
    for (;;) {
      // Half a cell of margin on every side, so that a scene that drifts or grows a little
      // keeps the grid (and its patches) in the next steps.
      std::array<double, 3> glo = lo, ghi = hi;
      for (std::size_t d = 0; d < 3; ++d) {
        glo[d] -= GRID_MARGIN_CELLS * cell;
        ghi[d] += GRID_MARGIN_CELLS * cell;
      }
      g = make_grid(glo, ghi, cell, max_cells);
      vertex_ranges();
      entries = grid_sort_count(g, prim, nboxes, s);
      if (entries <= GRID_ENTRIES_PER_BOX * nboxes || g.cells() == 1) return;
      cell = 2.0 / g.inv_h;
    }
  };
  s.grid_ranges.resize(nboxes);
  if (!patched) {
    if (reuse) entries = grid_sort_count(g, prim, nboxes, s);
    if (!reuse || (entries > GRID_ENTRIES_PER_BOX * nboxes && g.cells() > 1))
      new_grid(reuse ? 2.0 / g.inv_h : h);
  }
  std::uint64_t work = 0;
  if (patched) {
    // The pair work from the patched offsets, over fixed blocks of cells (never cut by the
    // thread count).
    const std::size_t ncell = g.cells();
    const std::size_t blocks = (ncell + GRID_CELL_GRAIN - 1) / GRID_CELL_GRAIN;
    s.block_sums.assign(blocks, 0);
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      std::uint64_t w = 0;
      for (std::size_t c = b * GRID_CELL_GRAIN; c < std::min(ncell, (b + 1) * GRID_CELL_GRAIN); ++c)
        w += pairs_among(start[c + 1] - start[c]);
      s.block_sums[b] = w;
    });
    for (const std::uint64_t w : s.block_sums) work += w;
  } else {
    work = grid_sort_fill(g, nboxes, entries, s);
  }
  const std::uint64_t work_limit = static_cast<std::uint64_t>(GRID_WORK_PER_BOX) * nboxes;
  const std::uint64_t crowded = static_cast<std::uint64_t>(GRID_CROWDED_WORK_PER_BOX) * nboxes;
  // Boxes long against the spacing of the surface (a fine mesh's motion) crowd the cells of
  // GRID_CELL_FACTOR: smaller cells are tried, which also keep the grid from giving up.
  const double small_h = GRID_SMALL_CELL_FACTOR * median_extent;
  if (work > crowded && small_h > 0.0 && small_h < 1.0 / g.inv_h) {
    new_grid(small_h);
    work = grid_sort_fill(g, nboxes, entries, s);  // new_grid keeps the entries in bounds
    s.grid_patched_boxes = -1;                     // whatever a patch did, this is a rebuild
    s.grid_small_backoff =
        std::min(std::max(1, 2 * s.grid_small_backoff), GRID_SMALL_CELL_MAX_BACKOFF);
    s.grid_small_skips = s.grid_patch ? s.grid_small_backoff : 0;
  } else if (!small_cells) {
    s.grid_small_backoff = 0;
  }
  if (work > work_limit) return nothing(-1);

  s.grid_kept = true;
  s.grid_build_seconds = t_start.elapsed();
  const StageTimer t_cells;
  s.grid_origin = g.origin;
  s.grid_inv_h = g.inv_h;
  s.grid_dims = g.dims;

  // Per cell: gather the items (float boxes, vertex ids, flags) into structure-of-arrays
  // buffers, build the candidate masks (cell_masks), and confirm the rare survivors with the
  // exact double boxes. Cells are split into GRID_CHUNKS chunks of about equal entry counts,
  // processed in parallel, each into its own key buffers, concatenated in chunk order
  // afterwards (each pair is emitted exactly once).
  const int vf_shift = std::max(1, bit_width(nf));
  const int ee_shift = std::max(1, bit_width(ne));
  s.chunks.resize(GRID_CHUNKS);
  s.chunk_cells.assign(GRID_CHUNKS + 1, g.cells());
  s.chunk_cells[0] = 0;
  // Chunk k starts at the first cell whose entries begin at or after entries * k / GRID_CHUNKS
  // (a binary search over the offsets: a scan of every cell was serial).
  for (std::size_t k = 1; k < GRID_CHUNKS; ++k)
    s.chunk_cells[k] = static_cast<std::size_t>(
        std::lower_bound(start.begin(), start.begin() + static_cast<std::ptrdiff_t>(g.cells()),
                         static_cast<std::uint32_t>(entries * k / GRID_CHUNKS)) -
        start.begin());
  const std::uint32_t* entry = s.cell_entries.data();
  tbb::parallel_for(std::size_t{0}, GRID_CHUNKS, [&](std::size_t chunk) {
    detail::GridChunk& out_chunk = s.chunks[chunk];
    out_chunk.reported = 0;
    detail::GridCell& cell = out_chunk.cell;
#if SHELLCONTRACT_GRID_AVX512
    if (avx2) {
      grid_chunk_avx2(prim, start.data(), entry, s.chunk_cells[chunk], s.chunk_cells[chunk + 1],
                      vf_shift, ee_shift, out_chunk);
      confirm_keys(prim, true, vf_shift, far_gap, out_chunk.vf_keys);
      confirm_keys(prim, false, ee_shift, far_gap, out_chunk.ee_keys);
      return;
    }
    if (float_cells) {
      grid_chunk_avx512<true>(prim, start.data(), entry, s.chunk_cells[chunk],
                              s.chunk_cells[chunk + 1], vf_shift, ee_shift, far_gap, out_chunk);
      if (confirm) {
        confirm_keys(prim, true, vf_shift, far_gap, out_chunk.vf_keys);
        confirm_keys(prim, false, ee_shift, far_gap, out_chunk.ee_keys);
      }
      return;
    }
    if (avx512) {
      grid_chunk_avx512<false>(prim, start.data(), entry, s.chunk_cells[chunk],
                               s.chunk_cells[chunk + 1], vf_shift, ee_shift, far_gap, out_chunk);
      return;
    }
#endif
    out_chunk.vf_keys.clear();
    out_chunk.ee_keys.clear();
    for (std::size_t c = s.chunk_cells[chunk]; c < s.chunk_cells[chunk + 1]; ++c) {
      const std::uint32_t b = start[c], e = start[c + 1];
      if (e - b < 2) continue;
      const std::size_t k = e - b;
      // The AVX-512 loop may have sized the shared buffers but not these.
      if (cell.flags.size() < k || cell.lo[0].size() < k || cell.mask.size() < k) {
        for (std::size_t d = 0; d < 3; ++d) {
          cell.lo[d].resize(k);
          cell.hi[d].resize(k);
          cell.v[d].resize(k);
        }
        cell.flags.resize(k);
        cell.gid.resize(k);
        cell.mask.resize(k);
      }
      std::size_t fb = 0, eb = 0;
      for (std::size_t t = 0; t < k; ++t) {
        const std::uint32_t tag = entry[b + t];
        const std::size_t gid = tag >> 3;
        const std::array<int, 3> v = prim.ids(gid);
        const detail::GridFloatBox fbox = prim.float_box(v);
        for (std::size_t d = 0; d < 3; ++d) {
          cell.lo[d][t] = fbox.lo[d];
          cell.hi[d][t] = fbox.hi[d];
          cell.v[d][t] = v[d];
        }
        cell.flags[t] = tag & GRID_ALL_FIRST;
        cell.gid[t] = static_cast<std::uint32_t>(gid);
        fb += gid < nv;
        eb += gid < nv + nf;
      }
      std::uint32_t* mask = cell.mask.data();
      for (std::size_t i = 0; i < fb && eb > fb; ++i) {
        if (!cell_masks(cell, i, fb, eb, mask, out_chunk.reported)) continue;
        for (std::size_t j = fb; j < eb; ++j) {
          if (mask[j] == 0) continue;
          const std::array<int, 3> fv = {cell.v[0][j], cell.v[1][j], cell.v[2][j]};
          const int vi = cell.v[0][i];
          const detail::GridVertexBox& a = vbox[static_cast<std::size_t>(vi)];
          const detail::GridVertexBox fbox = prim.box(fv);
          if (!overlap(a, fbox)) continue;
          const std::uint64_t close = gap_above(a, fbox, far_gap) ? 0u : 1u;
          out_chunk.vf_keys.push_back(
              (static_cast<std::uint64_t>(vi) << vf_shift | (cell.gid[j] - nv)) << 1 | close);
        }
      }
      for (std::size_t i = eb; i + 1 < k; ++i) {
        if (!cell_masks(cell, i, i + 1, k, mask, out_chunk.reported)) continue;
        const detail::GridVertexBox pbox = prim.box({cell.v[0][i], cell.v[1][i], -2});
        const std::uint64_t high = static_cast<std::uint64_t>(cell.gid[i] - nv - nf) << ee_shift;
        for (std::size_t j = i + 1; j < k; ++j) {
          if (mask[j] == 0) continue;
          const detail::GridVertexBox qbox = prim.box({cell.v[0][j], cell.v[1][j], -2});
          if (!overlap(pbox, qbox)) continue;
          const std::uint64_t close = gap_above(pbox, qbox, far_gap) ? 0u : 1u;
          // Entries of a cell are in increasing id order, so a < b.
          out_chunk.ee_keys.push_back((high | (cell.gid[j] - nv - nf)) << 1 | close);
        }
      }
    }
  });
  s.grid_cell_loop_seconds = t_cells.elapsed();
  const StageTimer t_output;
  std::int64_t reported = 0;
  for (const detail::GridChunk& c : s.chunks) reported += c.reported;
  if (sorted) {
    tbb::parallel_invoke(
        [&] {
          sort_chunk_keys(s.chunks, true, vf_shift, nv, s.sort_counts[0], s.sort_keys[0],
                          out.vertex_face, out.vertex_face_close);
        },
        [&] {
          sort_chunk_keys(s.chunks, false, ee_shift, ne, s.sort_counts[1], s.sort_keys[1],
                          out.edge_edge, out.edge_edge_close);
        });
    s.grid_output_seconds = t_output.elapsed();
    return reported;
  }
  // The chunks' pairs one after the other: the chunks are cut by entry counts, not by threads,
  // so this order (cells, then rows within a cell) does not depend on the thread count (the
  // speculative broad phase's order).
  std::size_t vf_total = 0, ee_total = 0;
  std::vector<std::size_t>& offset = s.chunk_offsets;  // VF offsets, then EE offsets, per chunk
  offset.assign(2 * GRID_CHUNKS, 0);
  for (std::size_t c = 0; c < GRID_CHUNKS; ++c) {
    offset[c] = vf_total;
    offset[GRID_CHUNKS + c] = ee_total;
    vf_total += s.chunks[c].vf_keys.size();
    ee_total += s.chunks[c].ee_keys.size();
  }
  // Sized without writing: the parallel unpack below writes every pair, and takes the page
  // faults of fresh storage on all threads. A resize that zeroed the growth (and copied the old
  // pairs when it reallocated) cost every step serial time, and more at each reallocation
  // (lab/pages/scale.md, "Page faults of the pair arrays").
  resize_for_rewrite(out.vertex_face, vf_total);
  resize_for_rewrite(out.vertex_face_close, vf_total);
  resize_for_rewrite(out.edge_edge, ee_total);
  resize_for_rewrite(out.edge_edge_close, ee_total);
  tbb::parallel_for(std::size_t{0}, GRID_CHUNKS, [&](std::size_t c) {
    unpack_keys(s.chunks[c].vf_keys, vf_shift, offset[c], out.vertex_face, out.vertex_face_close);
    unpack_keys(s.chunks[c].ee_keys, ee_shift, offset[GRID_CHUNKS + c], out.edge_edge,
                out.edge_edge_close);
  });
  s.grid_output_seconds = t_output.elapsed();
  return reported;
}

}  // namespace detail
}  // namespace shellcontract
