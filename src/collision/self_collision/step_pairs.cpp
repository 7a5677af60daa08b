// The step's pairs: the live list, its consistency check, the candidate lists for tests; the
// response regions.
#include "collision/self_collision/step_pairs.hpp"

#include <tbb/blocked_range.h>

namespace shellcontract::collision_pipeline {

namespace {

/// Indices per block of compact(): fixed, so the result never depends on the threads.
constexpr std::size_t COMPACT_BLOCK = 8192;

/// Writes the i in [0, n) with keep(i) to out[0, count), in increasing order, in parallel (the
/// same result for any number of threads); returns count. out keeps its capacity; block_count
/// is scratch.
template <class Keep>
std::size_t compact(tbb::task_arena& arena, std::size_t n, Keep keep, PairArray<std::uint32_t>& out,
                    std::vector<std::size_t>& block_count) {
  // Fixed blocks (never cut by the thread count): block b compacts its kept indices, in order,
  // to the front of its own slice out[b B, (b + 1) B); the slices are then closed up in order.
  constexpr std::size_t B = COMPACT_BLOCK;
  const std::size_t blocks = (n + B - 1) / B;
  if (out.size() < n) resize_for_rewrite(out, n);
  block_count.resize(blocks);
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      std::uint32_t* dst = out.data() + b * B;
      const std::size_t end = std::min(n, (b + 1) * B);
      std::size_t k = 0;
      for (std::size_t i = b * B; i < end; ++i) {
        dst[k] = static_cast<std::uint32_t>(i);  // branch-free: keep() is hard to predict
        k += keep(i) ? 1 : 0;
      }
      block_count[b] = k;
    });
  });
  return close_up(out, B, block_count);
}

}  // namespace

std::size_t close_up(PairArray<std::uint32_t>& out, const std::vector<LiveUnit>& units,
                     const std::vector<std::size_t>& counts) {
  std::size_t total = 0;
  for (std::size_t u = 0; u < units.size(); ++u) {
    if (total != units[u].begin)
      std::memmove(out.data() + total, out.data() + units[u].begin,
                   counts[u] * sizeof(std::uint32_t));
    total += counts[u];
  }
  return total;
}

void StepPairs::collect_live(tbb::task_arena& arena) {
  live_count = compact(
      arena, records.size(), [&](std::size_t i) { return role[i] < EXCLUDED; }, live, block_count_);
  if (live_v.size() < live_count) resize_for_rewrite(live_v, live_count);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, live_count, PAIR_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t j = r.begin(); j < r.end(); ++j)
                          live_v[j] = records[live[j]].v;
                      });
  });
  set_live_units(live_count);
}

void StepPairs::set_live_units(std::size_t count) {
  live_count = count;
  live_units.clear();
  for (std::size_t b = 0; b < live_count; b += COMPACT_BLOCK)
    live_units.push_back(LiveUnit{b, std::min(COMPACT_BLOCK, live_count - b)});
}

bool StepPairs::live_consistent() const {
  std::size_t count = 0, next = 0;
  bool first = true;
  std::uint32_t last = 0;
  for (const LiveUnit& u : live_units) {
    if (u.begin < next || u.begin + u.count > live.size() || u.begin + u.count > live_v.size())
      return false;
    next = u.begin + u.count;
    for (std::size_t j = u.begin; j < next; ++j) {
      const std::uint32_t i = live[j];
      if (i >= records.size() || i >= role.size() || role[i] >= EXCLUDED) return false;
      if (!first && last >= i) return false;
      if (live_v[j] != records[i].v) return false;
      first = false;
      last = i;
    }
    count += u.count;
  }
  return count == live_count;
}

std::pair<std::vector<std::array<int, 2>>, std::vector<std::array<int, 2>>>
StepPairs::candidate_pairs() const {
  std::pair<std::vector<std::array<int, 2>>, std::vector<std::array<int, 2>>> out;
  for (std::size_t i = 0; i < records.size(); ++i) {
    if (i < role.size() && role[i] == NOT_CANDIDATE) continue;
    (records[i].kind == CcdPrimitive::VertexFace ? out.first : out.second)
        .push_back(records[i].pair);
  }
  std::sort(out.first.begin(), out.first.end());
  std::sort(out.second.begin(), out.second.end());
  return out;
}

void Regions::set(tbb::task_arena& arena, const Positions& x0, const Positions& x1, double half) {
  // In parallel blocks of rows: a serial pass is too slow on the largest meshes (lab/history.md).
  lo.resize(x0.rows(), 3);
  hi.resize(x0.rows(), 3);
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<Eigen::Index>(0, x0.rows(), 4096),
        [&](const tbb::blocked_range<Eigen::Index>& r) {
          const Eigen::Index b = r.begin(), n = r.end() - r.begin();
          lo.middleRows(b, n) = x0.middleRows(b, n).cwiseMin(x1.middleRows(b, n)).array() - half;
          hi.middleRows(b, n) = x0.middleRows(b, n).cwiseMax(x1.middleRows(b, n)).array() + half;
        });
  });
}

}  // namespace shellcontract::collision_pipeline
