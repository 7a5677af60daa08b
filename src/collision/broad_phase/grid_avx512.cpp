// The Grid method's AVX-512 cell loop (GCC on x86-64; chosen at run time, see
// grid_avx512_available), and the check of the CPU.
#include "collision/broad_phase/grid.hpp"
#include "core/kernels.hpp"

#if SHELLCONTRACT_GRID_AVX512
#include <immintrin.h>
#endif

namespace shellcontract {
namespace detail {

#if SHELLCONTRACT_GRID_AVX512
// The AVX-512 cell loop. The portable loop tests float boxes (4 SSE2 lanes), writes a mask per
// item, scans it, and confirms each hit with the exact double boxes, gathered again from the
// vertex arrays (cache misses on bear). Here the cell holds the exact double boxes and one pass
// of 8 double lanes applies every test of the portable path to the same doubles with the same
// comparisons (the dedupe flags, overlap(), the adjacency test, gap_above()), then writes the
// finished keys of the lanes that pass with a compress-store, in lane order: the same pairs, in
// the same order, with the same close flags (tested against the portable loop). The float boxes
// were only a cull in front of the exact test, so skipping them changes nothing but the
// box_overlaps statistic, which then counts exact overlaps. By default find_candidates runs the
// float loop below instead and confirms its pairs in double (grid.cpp's confirm_keys, the same
// pairs in the same order); this loop runs with BroadPhaseScratch::grid_float_confirm false.
#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,popcnt")

/// Items i, ..., i + R - 1 of the cell (R rows, see GRID_ROW_GROUP) against items
/// [j0 + r s, j1), where s = 1 if `stagger` (edge-edge rows: row r starts after its own item)
/// and 0 otherwise (vertex-face rows share their range). Row r appends to keys[r][n[r]..] the key
/// (base[r] | (gid_j - sub)) << 1 | close of every j (increasing) that passes the dedupe flags,
/// the exact box test and the adjacency test; close is 0 iff gap_above(box i + r, box j,
/// far_gap). Adds the flag-and-box hits (adjacent pairs included) to `hits`. The rows share the
/// loads of the j items and the loop (EE rows average about three 8-lane steps, so a row's set-up
/// and its loop exit weigh as much as its tests); each row's answers are its own, written to its
/// own buffer, so the caller can append them in row order and keep the order of single rows.
template <int R>
inline __attribute__((always_inline)) void cell_rows_avx512(
    const detail::GridCell& cell, std::size_t i, std::size_t j0, std::size_t j1, bool stagger,
    const std::uint64_t (&base)[R], std::uint32_t sub, double far_gap,
    std::vector<std::uint64_t>* const (&keys)[R], std::size_t* const (&n)[R], std::int64_t& hits) {
  __m512d lx[R], ly[R], lz[R], hx[R], hy[R], hz[R];
  __m256i fi[R], a[R], b[R], c[R];
  __m512i key_base[R];
  std::size_t start[R];
  for (int r = 0; r < R; ++r) {
    const std::size_t q = i + static_cast<std::size_t>(r);
    lx[r] = _mm512_set1_pd(cell.dlo[0][q]);
    ly[r] = _mm512_set1_pd(cell.dlo[1][q]);
    lz[r] = _mm512_set1_pd(cell.dlo[2][q]);
    hx[r] = _mm512_set1_pd(cell.dhi[0][q]);
    hy[r] = _mm512_set1_pd(cell.dhi[1][q]);
    hz[r] = _mm512_set1_pd(cell.dhi[2][q]);
    fi[r] = _mm256_set1_epi32(static_cast<int>(cell.flags[q]));
    a[r] = _mm256_set1_epi32(cell.v[0][q]);
    b[r] = _mm256_set1_epi32(cell.v[1][q]);
    c[r] = _mm256_set1_epi32(cell.v[2][q]);
    key_base[r] = _mm512_set1_epi64(static_cast<long long>(base[r]));
    start[r] = j0 + (stagger ? static_cast<std::size_t>(r) : 0);
  }
  const __m512d gap = _mm512_set1_pd(far_gap);
  const __m256i all_first = _mm256_set1_epi32(static_cast<int>(GRID_ALL_FIRST));
  const __m512i key_sub = _mm512_set1_epi64(sub), one = _mm512_set1_epi64(1);
  std::int64_t box_hits = 0;
  for (std::size_t j = j0; j < j1; j += 8) {
    // Lanes past j1 are masked: their loads read nothing and they never pass. The comparisons
    // are independent of each other (one mask AND at the end, one branch), so they do not form
    // a chain of masked compares.
    const __mmask8 live =
        j1 - j >= 8 ? __mmask8{0xff} : static_cast<__mmask8>((1u << (j1 - j)) - 1u);
    const __m256i qf = _mm256_maskz_loadu_epi32(live, cell.flags.data() + j);
    const __m512d qlx = _mm512_maskz_loadu_pd(live, cell.dlo[0].data() + j);
    const __m512d qhx = _mm512_maskz_loadu_pd(live, cell.dhi[0].data() + j);
    const __m512d qly = _mm512_maskz_loadu_pd(live, cell.dlo[1].data() + j);
    const __m512d qhy = _mm512_maskz_loadu_pd(live, cell.dhi[1].data() + j);
    const __m512d qlz = _mm512_maskz_loadu_pd(live, cell.dlo[2].data() + j);
    const __m512d qhz = _mm512_maskz_loadu_pd(live, cell.dhi[2].data() + j);
    const __m256i qa = _mm256_maskz_loadu_epi32(live, cell.v[0].data() + j);
    const __m256i qb = _mm256_maskz_loadu_epi32(live, cell.v[1].data() + j);
    const __m256i qc = _mm256_maskz_loadu_epi32(live, cell.v[2].data() + j);
    for (int r = 0; r < R; ++r) {
      // Row r's lanes: live, and at or after its start (only a staggered row's first step
      // drops a lane).
      const unsigned lanes =
          start[r] > j ? live & ~((1u << (start[r] - j)) - 1u) : static_cast<unsigned>(live);
      // The dedupe flags and overlap(i + r, j): closed intervals on all three axes.
      const unsigned box =
          lanes & _mm256_cmpeq_epi32_mask(_mm256_or_si256(fi[r], qf), all_first) &
          _mm512_cmp_pd_mask(lx[r], qhx, _CMP_LE_OQ) & _mm512_cmp_pd_mask(qlx, hx[r], _CMP_LE_OQ) &
          _mm512_cmp_pd_mask(ly[r], qhy, _CMP_LE_OQ) & _mm512_cmp_pd_mask(qly, hy[r], _CMP_LE_OQ) &
          _mm512_cmp_pd_mask(lz[r], qhz, _CMP_LE_OQ) & _mm512_cmp_pd_mask(qlz, hz[r], _CMP_LE_OQ);
      // Adjacent iff a vertex id is shared; the -1/-2 placeholders never match (see ids()).
      const unsigned apart =
          _mm256_cmpneq_epi32_mask(a[r], qa) & _mm256_cmpneq_epi32_mask(a[r], qb) &
          _mm256_cmpneq_epi32_mask(a[r], qc) & _mm256_cmpneq_epi32_mask(b[r], qa) &
          _mm256_cmpneq_epi32_mask(b[r], qb) & _mm256_cmpneq_epi32_mask(c[r], qa) &
          _mm256_cmpneq_epi32_mask(c[r], qb);
      box_hits += __builtin_popcount(box);
      const __mmask8 pass = static_cast<__mmask8>(box & apart);
      if (pass == 0) continue;
      // gap_above(box i + r, box j, far_gap), the same subtractions.
      const __mmask8 far =
          static_cast<__mmask8>(_mm512_cmp_pd_mask(_mm512_sub_pd(qlx, hx[r]), gap, _CMP_GT_OQ) |
                                _mm512_cmp_pd_mask(_mm512_sub_pd(lx[r], qhx), gap, _CMP_GT_OQ) |
                                _mm512_cmp_pd_mask(_mm512_sub_pd(qly, hy[r]), gap, _CMP_GT_OQ) |
                                _mm512_cmp_pd_mask(_mm512_sub_pd(ly[r], qhy), gap, _CMP_GT_OQ) |
                                _mm512_cmp_pd_mask(_mm512_sub_pd(qlz, hz[r]), gap, _CMP_GT_OQ) |
                                _mm512_cmp_pd_mask(_mm512_sub_pd(lz[r], qhz), gap, _CMP_GT_OQ));
      const __m512i gid = _mm512_maskz_cvtepu32_epi64(
          pass, _mm256_maskz_loadu_epi32(pass, reinterpret_cast<const int*>(cell.gid.data() + j)));
      __m512i key = _mm512_maskz_slli_epi64(
          pass, _mm512_or_si512(key_base[r], _mm512_sub_epi64(gid, key_sub)), 1);
      key = _mm512_mask_or_epi64(key, static_cast<__mmask8>(~far), key, one);
      std::vector<std::uint64_t>& out = *keys[r];
      std::size_t& count = *n[r];
      if (out.size() < count + 8) out.resize(std::max<std::size_t>(2 * out.size(), count + 256));
      _mm512_mask_compressstoreu_epi64(out.data() + count, pass, key);
      count += static_cast<std::size_t>(__builtin_popcount(pass));
    }
  }
  hits += box_hits;
}

/// The superset variant of cell_rows_avx512 for the speculative broad phase
/// (find_candidates_in_vertex_boxes): items i, ..., i + R - 1 against [j0 + r s, j1) on the
/// cell's float boxes, 16 lanes at a time, with the same dedupe flags, the same adjacency test
/// and the same staggering and key layout. Every pair whose exact boxes overlap passes (the
/// float boxes are the exact ones rounded monotonically: see grid_pairs), and a pair whose float
/// boxes overlap only by rounding passes too; every key is flagged close (no far test). Twice
/// the lanes of the double loop and no confirmation: the speculative task's cell loop is the
/// step's longest part at strong pressure. The float loop is faster than the double one and
/// finds the same pairs (BM_GridOnVertexBoxes; docs/design/self-collision.md, lab/history.md).
template <int R>
inline __attribute__((always_inline)) void cell_rows_avx512_float(
    const detail::GridCell& cell, std::size_t i, std::size_t j0, std::size_t j1, bool stagger,
    const std::uint64_t (&base)[R], std::uint32_t sub, std::vector<std::uint64_t>* const (&keys)[R],
    std::size_t* const (&n)[R], std::int64_t& hits) {
  __m512 lx[R], ly[R], lz[R], hx[R], hy[R], hz[R];
  __m512i fi[R], a[R], b[R], c[R];
  __m512i key_base[R];
  std::size_t start[R];
  for (int r = 0; r < R; ++r) {
    const std::size_t q = i + static_cast<std::size_t>(r);
    lx[r] = _mm512_set1_ps(cell.lo[0][q]);
    ly[r] = _mm512_set1_ps(cell.lo[1][q]);
    lz[r] = _mm512_set1_ps(cell.lo[2][q]);
    hx[r] = _mm512_set1_ps(cell.hi[0][q]);
    hy[r] = _mm512_set1_ps(cell.hi[1][q]);
    hz[r] = _mm512_set1_ps(cell.hi[2][q]);
    fi[r] = _mm512_set1_epi32(static_cast<int>(cell.flags[q]));
    a[r] = _mm512_set1_epi32(cell.v[0][q]);
    b[r] = _mm512_set1_epi32(cell.v[1][q]);
    c[r] = _mm512_set1_epi32(cell.v[2][q]);
    // (base | (gid - sub)) << 1 | 1 = (base << 1 | 1) + ((gid - sub) << 1): base's low bits
    // below the gid field are zero.
    key_base[r] = _mm512_set1_epi64(static_cast<long long>(base[r] << 1 | 1u));
    start[r] = j0 + (stagger ? static_cast<std::size_t>(r) : 0);
  }
  const __m512i all_first = _mm512_set1_epi32(static_cast<int>(GRID_ALL_FIRST));
  const __m512i key_sub = _mm512_set1_epi64(sub);
  std::int64_t box_hits = 0;
  for (std::size_t j = j0; j < j1; j += 16) {
    const __mmask16 live =
        j1 - j >= 16 ? __mmask16{0xffff} : static_cast<__mmask16>((1u << (j1 - j)) - 1u);
    const __m512i qf = _mm512_maskz_loadu_epi32(live, cell.flags.data() + j);
    const __m512 qlx = _mm512_maskz_loadu_ps(live, cell.lo[0].data() + j);
    const __m512 qhx = _mm512_maskz_loadu_ps(live, cell.hi[0].data() + j);
    const __m512 qly = _mm512_maskz_loadu_ps(live, cell.lo[1].data() + j);
    const __m512 qhy = _mm512_maskz_loadu_ps(live, cell.hi[1].data() + j);
    const __m512 qlz = _mm512_maskz_loadu_ps(live, cell.lo[2].data() + j);
    const __m512 qhz = _mm512_maskz_loadu_ps(live, cell.hi[2].data() + j);
    const __m512i qa = _mm512_maskz_loadu_epi32(live, cell.v[0].data() + j);
    const __m512i qb = _mm512_maskz_loadu_epi32(live, cell.v[1].data() + j);
    const __m512i qc = _mm512_maskz_loadu_epi32(live, cell.v[2].data() + j);
    for (int r = 0; r < R; ++r) {
      const unsigned lanes =
          start[r] > j ? live & ~((1u << (start[r] - j)) - 1u) : static_cast<unsigned>(live);
      const unsigned box =
          lanes & _mm512_cmpeq_epi32_mask(_mm512_or_si512(fi[r], qf), all_first) &
          _mm512_cmp_ps_mask(lx[r], qhx, _CMP_LE_OQ) & _mm512_cmp_ps_mask(qlx, hx[r], _CMP_LE_OQ) &
          _mm512_cmp_ps_mask(ly[r], qhy, _CMP_LE_OQ) & _mm512_cmp_ps_mask(qly, hy[r], _CMP_LE_OQ) &
          _mm512_cmp_ps_mask(lz[r], qhz, _CMP_LE_OQ) & _mm512_cmp_ps_mask(qlz, hz[r], _CMP_LE_OQ);
      const unsigned apart =
          _mm512_cmpneq_epi32_mask(a[r], qa) & _mm512_cmpneq_epi32_mask(a[r], qb) &
          _mm512_cmpneq_epi32_mask(a[r], qc) & _mm512_cmpneq_epi32_mask(b[r], qa) &
          _mm512_cmpneq_epi32_mask(b[r], qb) & _mm512_cmpneq_epi32_mask(c[r], qa) &
          _mm512_cmpneq_epi32_mask(c[r], qb);
      box_hits += __builtin_popcount(box);
      const unsigned pass = box & apart;
      if (pass == 0) continue;
      std::vector<std::uint64_t>& out = *keys[r];
      std::size_t& count = *n[r];
      if (out.size() < count + 16) out.resize(std::max<std::size_t>(2 * out.size(), count + 256));
      for (std::size_t half = 0; half < 2; ++half) {
        const __mmask8 m = static_cast<__mmask8>(pass >> (8 * half));
        if (m == 0) continue;
        const __m512i gid = _mm512_maskz_cvtepu32_epi64(
            m, _mm256_maskz_loadu_epi32(
                   m, reinterpret_cast<const int*>(cell.gid.data() + j + 8 * half)));
        const __m512i key = _mm512_add_epi64(
            key_base[r], _mm512_maskz_slli_epi64(m, _mm512_sub_epi64(gid, key_sub), 1));
        _mm512_storeu_si512(out.data() + count, _mm512_maskz_compress_epi64(m, key));
        count += static_cast<std::size_t>(__builtin_popcount(m));
      }
    }
  }
  hits += box_hits;
}

/// The cells [c0, c1) of the grid with the AVX-512 rows: the same cells, rows and pairs as the
/// portable loop in grid_pairs, on exact boxes (cell_rows_avx512), or with Float a superset of
/// them on float boxes (cell_rows_avx512_float; far_gap unused). The key buffers serve as their
/// own capacity and are trimmed at the end.
template <bool Float>
void grid_chunk_avx512(const GridPrimitives& prim, const std::uint32_t* start,
                       const std::uint32_t* entry, std::size_t c0, std::size_t c1, int vf_shift,
                       int ee_shift, double far_gap, detail::GridChunk& out_chunk) {
  const std::size_t nv = prim.nv, nf = prim.nf;
  detail::GridCell& cell = out_chunk.cell;
  std::size_t nvf = 0, nee = 0;
  for (std::size_t c = c0; c < c1; ++c) {
    const std::uint32_t b = start[c], e = start[c + 1];
    if (e - b < 2) continue;
    const std::size_t k = e - b;
    // The portable loop or the other flavour may have sized the shared buffers but not these.
    if (cell.flags.size() < k || (Float ? cell.lo[0].size() : cell.dlo[0].size()) < k) {
      for (std::size_t d = 0; d < 3; ++d) {
        if constexpr (Float) {
          cell.lo[d].resize(k);
          cell.hi[d].resize(k);
        } else {
          cell.dlo[d].resize(k);
          cell.dhi[d].resize(k);
        }
        cell.v[d].resize(k);
      }
      cell.flags.resize(k);
      cell.gid.resize(k);
    }
    // Each cell lists its vertices, then faces, then edges, each by increasing id (the counting
    // sort's order, kept by patch_grid), so the kinds are three runs: one gather loop per kind,
    // without the per-entry branches on the kind and its corner count.
    const std::uint32_t* const tags = entry + b;
    const std::size_t fb = static_cast<std::size_t>(
        std::partition_point(tags, tags + k, [&](std::uint32_t tag) { return (tag >> 3) < nv; }) -
        tags);
    const std::size_t eb = static_cast<std::size_t>(
        std::partition_point(tags + fb, tags + k,
                             [&](std::uint32_t tag) { return (tag >> 3) < nv + nf; }) -
        tags);
    using Box = std::conditional_t<Float, detail::GridFloatBox, detail::GridVertexBox>;
    const Box* const vbox = [&] {
      if constexpr (Float)
        return prim.s.grid_vertex_floats.data();
      else
        return prim.s.grid_vertex_boxes.data();
    }();
    auto put = [&](std::size_t t, std::uint32_t tag, const Box& box, int v0, int v1, int v2) {
      for (std::size_t d = 0; d < 3; ++d) {
        if constexpr (Float) {
          cell.lo[d][t] = box.lo[d];
          cell.hi[d][t] = box.hi[d];
        } else {
          cell.dlo[d][t] = box.lo[d];
          cell.dhi[d][t] = box.hi[d];
        }
      }
      cell.v[0][t] = v0;
      cell.v[1][t] = v1;
      cell.v[2][t] = v2;
      cell.flags[t] = tag & GRID_ALL_FIRST;
      cell.gid[t] = tag >> 3;
    };
    // min and max are exact: a joined box is bit-identical to primitive_box's.
    auto join = [](Box x, const Box& y) {
      for (std::size_t d = 0; d < 3; ++d) {
        x.lo[d] = std::min(x.lo[d], y.lo[d]);
        x.hi[d] = std::max(x.hi[d], y.hi[d]);
      }
      return x;
    };
    auto vb = [&](int v) -> const Box& { return vbox[static_cast<std::size_t>(v)]; };
    for (std::size_t t = 0; t < fb; ++t) {
      const std::uint32_t v = tags[t] >> 3;
      put(t, tags[t], vbox[v], static_cast<int>(v), -1, -1);
    }
    const int* const face_v = prim.topo.faces.data();
    for (std::size_t t = fb; t < eb; ++t) {
      const std::size_t f = (tags[t] >> 3) - nv;
      const int v0 = face_v[3 * f], v1 = face_v[3 * f + 1], v2 = face_v[3 * f + 2];
      put(t, tags[t], join(join(vb(v0), vb(v1)), vb(v2)), v0, v1, v2);
    }
    const int* const edge_v = prim.topo.edges.data();
    for (std::size_t t = eb; t < k; ++t) {
      const std::size_t ed = (tags[t] >> 3) - nv - nf;
      const int v0 = edge_v[2 * ed], v1 = edge_v[2 * ed + 1];
      put(t, tags[t], join(vb(v0), vb(v1)), v0, v1, -2);
    }
    // Rows GRID_ROW_GROUP at a time; row r > 0 of a group writes to row_keys[r - 1], appended
    // after the rows before it, so the keys come in the order of single rows (the portable
    // loop's). `base_of(q)` is item q's key prefix.
    auto rows = [&](auto group, std::size_t i, std::size_t j0, std::size_t j1, bool stagger,
                    auto base_of, std::uint32_t sub, std::vector<std::uint64_t>& keys,
                    std::size_t& count) {
      constexpr int R = decltype(group)::value;
      std::uint64_t base[R];
      std::vector<std::uint64_t>* buffers[R];
      std::size_t row_count[R] = {};
      std::size_t* counts[R];
      for (int r = 0; r < R; ++r) {
        base[r] = base_of(i + static_cast<std::size_t>(r));
        buffers[r] = r == 0 ? &keys : &out_chunk.row_keys[static_cast<std::size_t>(r - 1)];
        counts[r] = r == 0 ? &count : &row_count[r];
      }
      if constexpr (Float)
        cell_rows_avx512_float<R>(cell, i, j0, j1, stagger, base, sub, buffers, counts,
                                  out_chunk.reported);
      else
        cell_rows_avx512<R>(cell, i, j0, j1, stagger, base, sub, far_gap, buffers, counts,
                            out_chunk.reported);
      for (int r = 1; r < R; ++r) {
        const std::size_t m = row_count[r];
        if (m == 0) continue;
        if (keys.size() < count + m) keys.resize(std::max(2 * keys.size(), count + m));
        const std::vector<std::uint64_t>& row = *buffers[r];
        std::copy(row.begin(), row.begin() + static_cast<std::ptrdiff_t>(m),
                  keys.begin() + static_cast<std::ptrdiff_t>(count));
        count += m;
      }
    };
    using Group = std::integral_constant<int, GRID_ROW_GROUP>;
    using Single = std::integral_constant<int, 1>;
    constexpr std::size_t G = GRID_ROW_GROUP;
    // Vertex-face rows: every vertex i < fb against the faces [fb, eb).
    const std::uint32_t vf_sub = static_cast<std::uint32_t>(nv);
    auto vf_base = [&](std::size_t q) {
      return static_cast<std::uint64_t>(cell.v[0][q]) << vf_shift;
    };
    std::size_t i = 0;
    if (eb > fb) {
      for (; i + G <= fb; i += G)
        rows(Group{}, i, fb, eb, false, vf_base, vf_sub, out_chunk.vf_keys, nvf);
      for (; i < fb; ++i) rows(Single{}, i, fb, eb, false, vf_base, vf_sub, out_chunk.vf_keys, nvf);
    }
    // Edge-edge rows: edge i against the edges after it, [i + 1, k) (a group needs a j for its
    // last row).
    const std::uint32_t ee_sub = static_cast<std::uint32_t>(nv + nf);
    auto ee_base = [&](std::size_t q) {
      return static_cast<std::uint64_t>(cell.gid[q] - nv - nf) << ee_shift;
    };
    for (i = eb; i + G < k; i += G)
      rows(Group{}, i, i + 1, k, true, ee_base, ee_sub, out_chunk.ee_keys, nee);
    for (; i + 1 < k; ++i)
      rows(Single{}, i, i + 1, k, true, ee_base, ee_sub, out_chunk.ee_keys, nee);
  }
  out_chunk.vf_keys.resize(nvf);
  out_chunk.ee_keys.resize(nee);
}

template void grid_chunk_avx512<true>(const GridPrimitives&, const std::uint32_t*,
                                      const std::uint32_t*, std::size_t, std::size_t, int, int,
                                      double, GridChunk&);
template void grid_chunk_avx512<false>(const GridPrimitives&, const std::uint32_t*,
                                       const std::uint32_t*, std::size_t, std::size_t, int, int,
                                       double, GridChunk&);

#pragma GCC pop_options
#endif  // SHELLCONTRACT_GRID_AVX512

bool grid_avx512_available() {
#if SHELLCONTRACT_GRID_AVX512
  static const bool available = detail::vector_kernels_allowed() &&
                                __builtin_cpu_supports("avx512f") &&
                                __builtin_cpu_supports("avx512vl");
  return available;
#else
  return false;
#endif
}

}  // namespace detail
}  // namespace shellcontract
