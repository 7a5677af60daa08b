#pragma once
// The regional order of the Coloured solve (private to src/pbd): how the padded rows are ordered
// and cut into parts whose interior constraints run on different threads with no barrier
// between colours. Used by solver.cpp only.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "pbd/colouring.hpp"

namespace shellcontract::regional {

/// The regional order of the Coloured solve. The padded rows (in breadth-first order, see
/// breadth_first_rows) are cut into REGIONS parts (split_vertices); a constraint whose vertices
/// all lie in one part is interior to it, the others form the interface. A sweep then runs, for
/// membranes and then for hinges, the interior constraints of every part (the parts share no
/// vertex, so they run on different threads with no barrier between colours), then the
/// interface constraints, colour after colour, on one thread. Why: a colour of bear is only a few
/// microseconds of work, and where exchanging a cache line between cores is slow (as on the
/// 2-vCPU development machine) the per-colour barriers and the vertex rows shared at the two
/// threads' boundary in every colour cost as much as the work (BM_SolverStep). Here a sweep has
/// 4 barriers instead of ~31, and only interface vertices change core (bear: about 500 of 27,648
/// faces and 1,000 of 41,472 hinges are interface). On 2 threads the regional order scales far
/// better than one phase per colour (BM_SolverStep, lab/history.md). The order is a valid
/// Gauss-Seidel order (each constraint once per sweep, in the kinds' order of math-spec 9.4) and
/// does not depend on the thread count, so results are bit-identical for any number of threads.
/// The number of parts is fixed (not the thread count) for that reason.
constexpr std::size_t REGIONS = 2;
/// Groups of a kind's constraints in the regional order: the REGIONS interiors, then the interface.
constexpr std::size_t REGION_GROUPS = REGIONS + 1;

/// Parts of the padded rows [0, n) (records given in row numbers): rows below the cut are part
/// 0, the others part 1. A cut of the row order, so that each part is contiguous in memory: two
/// rows share a cache line, and parts that interleave in memory share lines (a breadth-first
/// split of bear's vertex ids with the rows in id order made each thread several times slower
/// per constraint, slower on 2 threads than on one; lab/history.md). The cut is the one
/// with the shortest critical path: per kind, the larger interior runs beside the smaller and
/// then the interface runs alone, so a kind costs (count - the smaller interior); the sum over
/// both kinds is minimized over every cut, in O(#V + #constraints). If the interface is still
/// large, the solver keeps the plain colour order.
template <class RecordA, class RecordB>
std::vector<std::uint8_t> split_vertices(int n, const std::vector<RecordA>& a,
                                         const std::vector<RecordB>& b) {
  static_assert(REGIONS == 2, "the cut search splits the rows in two");
  const std::size_t N = static_cast<std::size_t>(n);
  // Per kind: how many constraints have their largest id at x (interior to part 0 once the
  // cut is above x) and their smallest id at x (interior to part 1 while the cut is at most x).
  auto spans = [&](const auto& records, std::vector<std::size_t>& with_max,
                   std::vector<std::size_t>& with_min) {
    with_max.assign(N + 1, 0);
    with_min.assign(N + 1, 0);
    for (const auto& r : records) {
      const auto [lo, hi] = std::minmax_element(r.v.begin(), r.v.end());
      ++with_max[static_cast<std::size_t>(*hi)];
      ++with_min[static_cast<std::size_t>(*lo)];
    }
  };
  std::vector<std::size_t> a_max, a_min, b_max, b_min;
  spans(a, a_max, a_min);
  spans(b, b_max, b_min);
  // Interior counts for cut t: part 0 = #(max id < t), part 1 = #(min id >= t).
  std::size_t a0 = 0, b0 = 0, a1 = a.size(), b1 = b.size();
  std::size_t best_cut = N / 2, best_cost = static_cast<std::size_t>(-1);
  for (std::size_t t = 0; t <= N; ++t) {
    if (t > 0) {
      a0 += a_max[t - 1];
      b0 += b_max[t - 1];
      a1 -= a_min[t - 1];
      b1 -= b_min[t - 1];
    }
    const std::size_t cost = (a.size() - std::min(a0, a1)) + (b.size() - std::min(b0, b1));
    if (cost < best_cost) {
      best_cost = cost;
      best_cut = t;
    }
  }
  std::vector<std::uint8_t> part(N);
  for (std::size_t v = 0; v < N; ++v) part[v] = v < best_cut ? 0 : 1;
  return part;
}

/// The order of the batches' padded rows: breadth-first over the triangles' edges, component by
/// component from the smallest unvisited id, then the vertices no triangle references, in id
/// order; row_vertex[k] is the vertex of row k (a permutation of [0, n)). Why: the cut of the
/// regional layout is a cut of the row order, and meshes do not always number their vertices
/// coherently (the kitten from CGAL's mesher: 71% of its faces span the best cut of the ids). A
/// breadth-first order is coherent for any input numbering (bear: 504 interface faces against
/// 861 by id), and the two parts stay contiguous in memory (no shared cache lines).
template <class Record>
std::vector<int> breadth_first_rows(const std::vector<Record>& triangles, int n) {
  const std::size_t N = static_cast<std::size_t>(n);
  std::vector<int> start(N + 1, 0), adj;
  for (const Record& t : triangles)
    for (int v : t.v) start[static_cast<std::size_t>(v) + 1] += 2;
  for (std::size_t i = 0; i < N; ++i) start[i + 1] += start[i];
  adj.resize(static_cast<std::size_t>(start[N]));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (const Record& t : triangles)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t v = static_cast<std::size_t>(t.v[k]);
      adj[static_cast<std::size_t>(fill[v]++)] = t.v[(k + 1) % 3];
      adj[static_cast<std::size_t>(fill[v]++)] = t.v[(k + 2) % 3];
    }
  std::vector<int> order;
  order.reserve(N);
  std::vector<std::uint8_t> seen(N, 0);
  for (std::size_t root = 0; root < N; ++root) {
    if (seen[root] || start[root] == start[root + 1]) continue;
    seen[root] = 1;
    for (std::size_t head = order.size(), i = (order.push_back(static_cast<int>(root)), head);
         i < order.size(); ++i) {
      const std::size_t v = static_cast<std::size_t>(order[i]);
      for (int a = start[v]; a < start[v + 1]; ++a) {
        const std::size_t w = static_cast<std::size_t>(adj[static_cast<std::size_t>(a)]);
        if (!seen[w]) {
          seen[w] = 1;
          order.push_back(static_cast<int>(w));
        }
      }
    }
  }
  for (std::size_t v = 0; v < N; ++v)
    if (!seen[v]) order.push_back(static_cast<int>(v));
  return order;
}

/// Vertex ids of records, renamed: out[i].v[k] = row[records[i].v[k]].
template <class Record>
std::vector<Record> renamed(std::vector<Record> records, const std::vector<int>& row) {
  for (Record& r : records)
    for (int& v : r.v) v = row[static_cast<std::size_t>(v)];
  return records;
}

/// Sorts each colour's records (colour c at [colours[c], colours[c + 1])) by their smallest row,
/// row[v] over their vertices, keeping the order of ties: a colour's batches then read the padded
/// rows from front to back. The records of a colour share no vertex, so their order within it
/// changes no bit of a sweep.
template <class Record>
void sort_colours_by_row(std::vector<Record>& records, const std::vector<std::size_t>& colours,
                         const std::vector<int>& row) {
  auto first_row = [&](const Record& r) {
    int lowest = row[static_cast<std::size_t>(r.v[0])];
    for (int v : r.v) lowest = std::min(lowest, row[static_cast<std::size_t>(v)]);
    return lowest;
  };
  for (std::size_t c = 0; c + 1 < colours.size(); ++c)
    std::stable_sort(records.begin() + static_cast<std::ptrdiff_t>(colours[c]),
                     records.begin() + static_cast<std::ptrdiff_t>(colours[c + 1]),
                     [&](const Record& a, const Record& b) { return first_row(a) < first_row(b); });
}

/// Largest fraction of a kind's constraints on the interface for which the regional order is
/// used: the interface runs on one thread, so beyond this the plain colour order is faster.
constexpr double MAX_INTERFACE_FRACTION = 0.15;

/// Number of records whose vertices do not all lie in one part.
template <class Record>
std::size_t interface_count(const std::vector<Record>& records,
                            const std::vector<std::uint8_t>& part) {
  std::size_t count = 0;
  for (const Record& r : records) {
    const std::uint8_t g = part[static_cast<std::size_t>(r.v[0])];
    for (int v : r.v)
      if (part[static_cast<std::size_t>(v)] != g) {
        ++count;
        break;
      }
  }
  return count;
}

/// Reorders a coloured kind for the regional order: group g (part g's interior, or g = REGIONS
/// the interface), then colour c, then the colour order; returns the offsets of the
/// REGION_GROUPS x C ranges (range g * C + c). Reordering within a colour changes no bit.
template <class Record>
std::vector<std::size_t> regional_in_place(std::vector<Record>& records,
                                           const std::vector<std::size_t>& colours,
                                           const std::vector<std::uint8_t>& part) {
  const std::size_t C = colours.size() - 1;
  auto group = [&](const Record& r) {
    const std::uint8_t g = part[static_cast<std::size_t>(r.v[0])];
    for (int v : r.v)
      if (part[static_cast<std::size_t>(v)] != g) return REGIONS;
    return static_cast<std::size_t>(g);
  };
  std::vector<std::size_t> order, offsets{0};
  order.reserve(records.size());
  for (std::size_t g = 0; g < REGION_GROUPS; ++g)
    for (std::size_t c = 0; c < C; ++c) {
      for (std::size_t i = colours[c]; i < colours[c + 1]; ++i)
        if (group(records[i]) == g) order.push_back(i);
      offsets.push_back(order.size());
    }
  apply_order(records, order);
  return offsets;
}

}  // namespace shellcontract::regional
