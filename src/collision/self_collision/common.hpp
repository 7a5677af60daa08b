// What the parts of the collision pipeline (docs/design/collision-pipeline.md) have in common: the
// per-pair array type, a pair's record and rest-state role, the narrow-phase stencils, the thread
// arena and the fixed blocks that keep every result independent of the thread count.
#pragma once

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "collision/ccd.hpp"
#include "collision/topology.hpp"
#include "core/arena_threads.hpp"
#include "core/no_zero_allocator.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract::collision_pipeline {

/// A per-pair array of the collision step (its records and flags, the live list and the tests):
/// every broad phase sizes it with resize_for_rewrite and then rewrites it whole, in parallel.
template <class T>
using PairArray = NoZeroVector<T>;

inline Vec3 row(const Positions& x, int i) { return Vec3(x(i, 0), x(i, 1), x(i, 2)); }

/// Response target: contacts closer than delta are pushed to RESPONSE_FACTOR * delta, so that a
/// resolved pair is not detected again in the next round (detection thickness < response
/// thickness, as in Bridson et al. 2002). The warm start pushes to the same distance.
inline constexpr double RESPONSE_FACTOR = 2.0;

/// Vertices per task of the passes over the vertices (predict, the speculative completion).
inline constexpr std::size_t VERTEX_BLOCK = 4096;
/// Pairs per task of the per-pair bookkeeping loops (records, stale marks).
inline constexpr std::size_t PAIR_GRAIN = 4096;

/// A candidate VF or EE pair of the current broad phase, ready for the narrow phase.
struct PairRecord {
  std::array<int, 4> v;     ///< vertex ids in the CCD stencil order (ccd.hpp)
  std::array<int, 2> pair;  ///< (vertex, face) or (edge a, edge b)
  CcdPrimitive kind;
};

/// Per pair (StepPairs::role): how the rest state classed it.
enum PairRole : std::uint8_t {
  NORMAL = 0,
  NEAR = 1,           ///< closer than delta at rest: no response push, fail-safe only
  EXCLUDED = 2,       ///< touching at rest: never tested
  NOT_CANDIDATE = 3,  ///< speculative pair whose actual boxes do not overlap: never tested
};

/// Live pairs StepPairs::live[begin, begin + count) (and their stencils in live_v): the unit of
/// work of the passes over the live pairs (see StepPairs::live_units).
struct LiveUnit {
  std::size_t begin = 0, count = 0;
};

/// The thread arena of every stage and the speculative broad phase's task group.
struct Workers {
  ArenaLease lease;        ///< the run's arena (run_arena): the caller's run's, or one of its own
  tbb::task_arena& arena;  ///< lease.arena()
  tbb::task_group background;  ///< the speculative broad phase (SelfCollision::predict)
  explicit Workers(int threads) : lease(run_arena(threads)), arena(lease.arena()) {}
};

/// Runs body(block, begin, end) for the fixed blocks [begin, end) of VERTEX_BLOCK vertices of n,
/// in parallel on `arena`.
template <class Body>
void for_vertex_blocks(tbb::task_arena& arena, std::size_t n, Body body) {
  const std::size_t blocks = (n + VERTEX_BLOCK - 1) / VERTEX_BLOCK;
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      body(b, b * VERTEX_BLOCK, std::min(n, (b + 1) * VERTEX_BLOCK));
    });
  });
}

/// The narrow-phase stencil (ccd.hpp order) of a VF pair (vertex, face) or an EE pair.
inline std::array<int, 4> stencil(CcdPrimitive kind, const std::array<int, 2>& p,
                                  const CollisionTopology& topo) {
  if (kind == CcdPrimitive::VertexFace)
    return {p[0], topo.faces(p[1], 0), topo.faces(p[1], 1), topo.faces(p[1], 2)};
  return {topo.edges(p[0], 0), topo.edges(p[0], 1), topo.edges(p[1], 0), topo.edges(p[1], 1)};
}

inline void gather(const Positions& x0, const Positions& x1, const std::array<int, 4>& v,
                   CcdStencil& s0, CcdStencil& s1) {
  for (int k = 0; k < 4; ++k) {
    s0[static_cast<std::size_t>(k)] = row(x0, v[static_cast<std::size_t>(k)]);
    s1[static_cast<std::size_t>(k)] = row(x1, v[static_cast<std::size_t>(k)]);
  }
}

/// The largest |coordinate| of a and b (same row counts), in parallel fixed blocks; unspecified
/// (possibly NaN) if a coordinate is not finite.
double max_abs(tbb::task_arena& arena, const Positions& a, const Positions& b);

/// Closes up blocks compacted in place: block b's counts[b] entries, at the front of its slice
/// out[b block, (b + 1) block), are moved after those of the blocks before it; returns the total.
template <class T>
std::size_t close_up(PairArray<T>& out, std::size_t block, const std::vector<std::size_t>& counts) {
  std::size_t total = 0;
  for (std::size_t b = 0; b < counts.size(); ++b) {
    if (total != b * block)
      std::memmove(out.data() + total, out.data() + b * block, counts[b] * sizeof(T));
    total += counts[b];
  }
  return total;
}

/// close_up for slices that start at the units' begins: unit u's counts[u] entries.
std::size_t close_up(PairArray<std::uint32_t>& out, const std::vector<LiveUnit>& units,
                     const std::vector<std::size_t>& counts);

}  // namespace shellcontract::collision_pipeline
