// The Grid method's AVX2 cell loop (GCC on x86-64; chosen at run time where the CPU has AVX2 but
// not AVX-512, see grid_avx2_available), and the check of the CPU.
//
// It is the AVX-512 float loop (grid_avx512.cpp, cell_rows_avx512_float) on 8 float lanes: the
// same cells, rows, dedupe flags, float box test on the monotone float boxes, adjacency test and
// key layout, so it emits the same superset of the exact pairs in the same order, and grid_pairs
// cuts it to the exact pairs with confirm_keys, as on AVX-512. The portable loop it replaces tests
// 4 SSE2 lanes, writes a mask per item, scans it, and gathers each hit's exact boxes again.
#include "collision/broad_phase/grid.hpp"
#include "core/kernels.hpp"

#if SHELLCONTRACT_GRID_AVX512
#include <immintrin.h>
#endif

namespace shellcontract {
namespace detail {

#if SHELLCONTRACT_GRID_AVX512
namespace {

/// Lanes past a row's end are loaded (never used): the cell's buffers hold this many spare
/// entries, so a load of 8 lanes never leaves them.
constexpr std::size_t LANES = 8;

/// The current cell's buffers (GridCell) as raw pointers.
struct CellView {
  float* lo[3];
  float* hi[3];
  int* v[3];
  std::uint32_t* flags;
  std::uint32_t* gid;
};

/// A chunk's key list being appended to: `count` keys written, room for `room`.
struct KeyOut {
  std::vector<std::uint64_t>* keys;
  std::uint64_t* data;
  std::size_t room, count;
};

// Everything that touches a std::vector lives here, outside the AVX2 region below: a
// standard-library template instantiated inside it would be compiled for AVX2 and could be the
// copy the linker keeps for every caller, including those on CPUs without AVX2. The region sees
// raw pointers only.
__attribute__((noinline)) CellView size_cell(detail::GridCell& cell, std::size_t k) {
  const std::size_t need = k + LANES;
  if (cell.flags.size() < need || cell.lo[0].size() < need) {
    for (std::size_t d = 0; d < 3; ++d) {
      cell.lo[d].resize(need);
      cell.hi[d].resize(need);
      cell.v[d].resize(need);
    }
    cell.flags.resize(need);
    cell.gid.resize(need);
  }
  CellView view{};
  for (std::size_t d = 0; d < 3; ++d) {
    view.lo[d] = cell.lo[d].data();
    view.hi[d] = cell.hi[d].data();
    view.v[d] = cell.v[d].data();
  }
  view.flags = cell.flags.data();
  view.gid = cell.gid.data();
  return view;
}

__attribute__((noinline)) void grow(KeyOut& out) {
  std::vector<std::uint64_t>& keys = *out.keys;
  keys.resize(std::max<std::size_t>(2 * keys.size(), out.count + 256));
  out.data = keys.data();
  out.room = keys.size();
}

KeyOut key_out(std::vector<std::uint64_t>& keys) { return KeyOut{&keys, keys.data(), keys.size(), 0}; }

/// What the chunk's loop reads: the grid's cells and entries, the vertex float boxes and the
/// topology, as raw pointers.
struct ChunkInput {
  const std::uint32_t* start;
  const std::uint32_t* entry;
  const detail::GridFloatBox* vbox;
  const int* face_v;  ///< 3 per face
  const int* edge_v;  ///< 2 per edge
  std::size_t nv, nf;
};

}  // namespace

#pragma GCC push_options
#pragma GCC target("avx2,popcnt")

namespace {

inline unsigned lane_bits(__m256 m) { return static_cast<unsigned>(_mm256_movemask_ps(m)); }
inline __m256i load_ints(const void* p) { return _mm256_loadu_si256(static_cast<const __m256i*>(p)); }

/// Item i of the cell against items [j0, j1): appends the key key_base + ((gid_j - sub) << 1) of
/// every j (increasing) that passes the dedupe flags, the float box test and the adjacency test
/// (the AVX-512 float loop's key, flagged close), and returns the flag-and-box hits (adjacent
/// pairs included).
inline __attribute__((always_inline)) std::int64_t row_avx2(const CellView& cell, std::size_t i,
                                                             std::size_t j0, std::size_t j1,
                                                             std::uint64_t key_base,
                                                             std::uint32_t sub, KeyOut& out) {
  const __m256 lx = _mm256_set1_ps(cell.lo[0][i]), ly = _mm256_set1_ps(cell.lo[1][i]),
               lz = _mm256_set1_ps(cell.lo[2][i]);
  const __m256 hx = _mm256_set1_ps(cell.hi[0][i]), hy = _mm256_set1_ps(cell.hi[1][i]),
               hz = _mm256_set1_ps(cell.hi[2][i]);
  const __m256i fi = _mm256_set1_epi32(static_cast<int>(cell.flags[i]));
  const __m256i a = _mm256_set1_epi32(cell.v[0][i]), b = _mm256_set1_epi32(cell.v[1][i]),
                c = _mm256_set1_epi32(cell.v[2][i]);
  const __m256i all_first = _mm256_set1_epi32(static_cast<int>(GRID_ALL_FIRST));
  std::int64_t box_hits = 0;
  for (std::size_t j = j0; j < j1; j += LANES) {
    const unsigned live = j1 - j >= LANES ? 0xffu : (1u << (j1 - j)) - 1u;
    // overlap(i, j) on closed intervals (ordered compares: a NaN never overlaps, as in the
    // AVX-512 loop), then the dedupe flags.
    __m256 in = _mm256_and_ps(_mm256_cmp_ps(lx, _mm256_loadu_ps(cell.hi[0] + j), _CMP_LE_OQ),
                              _mm256_cmp_ps(_mm256_loadu_ps(cell.lo[0] + j), hx, _CMP_LE_OQ));
    in = _mm256_and_ps(in, _mm256_cmp_ps(ly, _mm256_loadu_ps(cell.hi[1] + j), _CMP_LE_OQ));
    in = _mm256_and_ps(in, _mm256_cmp_ps(_mm256_loadu_ps(cell.lo[1] + j), hy, _CMP_LE_OQ));
    in = _mm256_and_ps(in, _mm256_cmp_ps(lz, _mm256_loadu_ps(cell.hi[2] + j), _CMP_LE_OQ));
    in = _mm256_and_ps(in, _mm256_cmp_ps(_mm256_loadu_ps(cell.lo[2] + j), hz, _CMP_LE_OQ));
    const __m256i first = _mm256_cmpeq_epi32(_mm256_or_si256(fi, load_ints(cell.flags + j)), all_first);
    const unsigned box = live & lane_bits(_mm256_and_ps(in, _mm256_castsi256_ps(first)));
    box_hits += __builtin_popcount(box);
    // Adjacent iff a vertex id is shared; the -1/-2 placeholders never match (see ids()). The
    // seven comparisons of the AVX-512 loop. They run on every block: whether a block has a box
    // hit varies without a pattern, so a branch on it is often mispredicted, while the branch on
    // `pass` below is rarely taken (lab/kernels/collision_coherence.md, section 8).
    const __m256i qa = load_ints(cell.v[0] + j), qb = load_ints(cell.v[1] + j),
                  qc = load_ints(cell.v[2] + j);
    __m256i shared = _mm256_or_si256(_mm256_cmpeq_epi32(a, qa), _mm256_cmpeq_epi32(a, qb));
    shared = _mm256_or_si256(shared, _mm256_cmpeq_epi32(a, qc));
    shared = _mm256_or_si256(shared, _mm256_cmpeq_epi32(b, qa));
    shared = _mm256_or_si256(shared, _mm256_cmpeq_epi32(b, qb));
    shared = _mm256_or_si256(shared, _mm256_cmpeq_epi32(c, qa));
    shared = _mm256_or_si256(shared, _mm256_cmpeq_epi32(c, qb));
    unsigned pass = box & ~lane_bits(_mm256_castsi256_ps(shared));
    if (pass == 0) continue;
    if (out.room < out.count + LANES) grow(out);
    // Few lanes pass (most overlaps are adjacent pairs): a scalar loop over them, in lane order.
    for (; pass != 0; pass &= pass - 1) {
      const std::size_t l = j + static_cast<std::size_t>(__builtin_ctz(pass));
      out.data[out.count++] = key_base + (static_cast<std::uint64_t>(cell.gid[l] - sub) << 1);
    }
  }
  return box_hits;
}

/// The cells [c0, c1): returns the flag-and-box hits.
std::int64_t chunk_rows_avx2(const ChunkInput& in, detail::GridCell& grid_cell, std::size_t c0,
                             std::size_t c1, int vf_shift, int ee_shift, KeyOut& vf, KeyOut& ee) {
  const std::size_t nv = in.nv, nf = in.nf;
  std::int64_t hits = 0;
  for (std::size_t c = c0; c < c1; ++c) {
    const std::uint32_t b = in.start[c], e = in.start[c + 1];
    if (e - b < 2) continue;
    const std::size_t k = e - b;
    const CellView cell = size_cell(grid_cell, k);
    // Each cell lists its vertices, then faces, then edges, each by increasing id (the counting
    // sort's order, kept by patch_grid): three runs, ended by two binary searches.
    const std::uint32_t* const tags = in.entry + b;
    const auto run_end = [&](std::size_t lo, std::size_t below) {
      std::size_t hi = k;
      while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if ((tags[mid] >> 3) < below)
          lo = mid + 1;
        else
          hi = mid;
      }
      return lo;
    };
    const std::size_t fb = run_end(0, nv), eb = run_end(fb, nv + nf);
    // A primitive's float box is the union of its vertices' (min and max are exact: the box the
    // AVX-512 float loop tests).
    const auto put = [&](std::size_t t, int v0, int v1, int v2, int corners) {
      const int v[3] = {v0, v1, v2};
      for (std::size_t d = 0; d < 3; ++d) {
        float lo = in.vbox[v0].lo[d], hi = in.vbox[v0].hi[d];
        for (int q = 1; q < corners; ++q) {
          const float l = in.vbox[v[q]].lo[d], h = in.vbox[v[q]].hi[d];
          lo = l < lo ? l : lo;
          hi = h > hi ? h : hi;
        }
        cell.lo[d][t] = lo;
        cell.hi[d][t] = hi;
        cell.v[d][t] = v[d];
      }
      cell.flags[t] = tags[t] & GRID_ALL_FIRST;
      cell.gid[t] = tags[t] >> 3;
    };
    for (std::size_t t = 0; t < fb; ++t) put(t, static_cast<int>(tags[t] >> 3), -1, -1, 1);
    for (std::size_t t = fb; t < eb; ++t) {
      const std::size_t f = (tags[t] >> 3) - nv;
      put(t, in.face_v[3 * f], in.face_v[3 * f + 1], in.face_v[3 * f + 2], 3);
    }
    for (std::size_t t = eb; t < k; ++t) {
      const std::size_t ed = (tags[t] >> 3) - nv - nf;
      put(t, in.edge_v[2 * ed], in.edge_v[2 * ed + 1], -2, 2);
    }
    // Vertex-face rows: every vertex against the faces [fb, eb). The AVX-512 float loop's keys,
    // ((p << shift | (gid - sub)) << 1) | 1, with (p << shift) << 1 | 1 the row's base.
    if (eb > fb)
      for (std::size_t i = 0; i < fb; ++i)
        hits += row_avx2(cell, i, fb, eb, (static_cast<std::uint64_t>(cell.v[0][i]) << vf_shift) << 1 | 1u,
                         static_cast<std::uint32_t>(nv), vf);
    // Edge-edge rows: edge i against the edges after it.
    for (std::size_t i = eb; i + 1 < k; ++i)
      hits += row_avx2(cell, i, i + 1, k, (static_cast<std::uint64_t>(cell.gid[i] - nv - nf) << ee_shift) << 1 | 1u,
                       static_cast<std::uint32_t>(nv + nf), ee);
  }
  return hits;
}

}  // namespace

#pragma GCC pop_options

void grid_chunk_avx2(const GridPrimitives& prim, const std::uint32_t* start,
                     const std::uint32_t* entry, std::size_t c0, std::size_t c1, int vf_shift,
                     int ee_shift, detail::GridChunk& out_chunk) {
  const ChunkInput in{start, entry, prim.s.grid_vertex_floats.data(), prim.topo.faces.data(),
                      prim.topo.edges.data(), prim.nv, prim.nf};
  KeyOut vf = key_out(out_chunk.vf_keys), ee = key_out(out_chunk.ee_keys);
  out_chunk.reported += chunk_rows_avx2(in, out_chunk.cell, c0, c1, vf_shift, ee_shift, vf, ee);
  out_chunk.vf_keys.resize(vf.count);
  out_chunk.ee_keys.resize(ee.count);
}

#endif  // SHELLCONTRACT_GRID_AVX512

bool grid_avx2_available() {
#if SHELLCONTRACT_GRID_AVX512
  static const bool available = detail::vector_kernels_allowed() &&
                                __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt");
  return available;
#else
  return false;
#endif
}

}  // namespace detail
}  // namespace shellcontract
