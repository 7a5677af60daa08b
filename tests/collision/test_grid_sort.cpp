// The Grid method's two-level counting sort (grid_sort.cpp) against the definition of its
// output: cell c lists every box whose cell range contains c, in increasing box id, tagged with
// the box's first-cell flags. Grid shapes put one slab inside a layer, across several layers, or
// make the grid a single cell, so that boxes cross slabs in every way the slabs are cut.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "collision/broad_phase/grid.hpp"
#include "collision/broad_phase/scratch.hpp"
#include "collision/topology.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

struct Csr {
  std::vector<std::uint32_t> start, entries;
};

/// The definition: for each box in id order, its tag in each cell of its range.
Csr by_definition(const detail::Grid& g, const std::vector<detail::GridRange>& ranges) {
  const std::size_t ncell = g.cells();
  std::vector<std::vector<std::uint32_t>> lists(ncell);
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    const detail::GridRange& r = ranges[i];
    for (std::size_t z = r.lo[2]; z <= r.hi[2]; ++z)
      for (std::size_t y = r.lo[1]; y <= r.hi[1]; ++y)
        for (std::size_t x = r.lo[0]; x <= r.hi[0]; ++x) {
          const std::uint32_t flags =
              (x == r.lo[0] ? 1u : 0u) | (y == r.lo[1] ? 2u : 0u) | (z == r.lo[2] ? 4u : 0u);
          lists[x + g.dims[0] * (y + g.dims[1] * z)].push_back(static_cast<std::uint32_t>(i) << 3 |
                                                               flags);
        }
  }
  Csr out;
  out.start.push_back(0);
  for (const auto& l : lists) {
    out.entries.insert(out.entries.end(), l.begin(), l.end());
    out.start.push_back(static_cast<std::uint32_t>(out.entries.size()));
  }
  return out;
}

TEST(GridSort, CellListsAreThoseOfTheDefinitionForEverySlabCut) {
  const test::TriMesh m = test::icosphere(2);
  const int nv = static_cast<int>(m.x.rows());
  const CollisionTopology topo = make_collision_topology(m.faces, nv);
  const std::size_t nboxes = static_cast<std::size_t>(nv + topo.faces.rows() + topo.edges.rows());
  std::mt19937 rng(24);
  // (dims, largest extent of a vertex's range in cells): slabs of a few rows inside a layer
  // (40 x 30 x 20), of several whole layers (3 x 2 x 2000), of one long row each (300 x 4 x 5),
  // and a single cell.
  const std::vector<std::pair<std::array<std::size_t, 3>, int>> shapes = {
      {{40, 30, 20}, 3}, {{3, 2, 2000}, 40}, {{300, 4, 5}, 2}, {{1, 1, 1}, 0}};
  for (const auto& [dims, spread] : shapes) {
    detail::Grid g;
    g.dims = dims;
    BroadPhaseScratch s;
    s.grid_vertex_ranges.resize(static_cast<std::size_t>(nv));
    for (detail::GridRange& r : s.grid_vertex_ranges)
      for (std::size_t d = 0; d < 3; ++d) {
        const int n = static_cast<int>(dims[d]);
        const int lo = std::uniform_int_distribution<int>(0, n - 1)(rng);
        const int len = std::uniform_int_distribution<int>(0, spread)(rng);
        r.lo[d] = static_cast<std::uint16_t>(lo);
        r.hi[d] = static_cast<std::uint16_t>(std::min(n - 1, lo + len));
      }
    const detail::GridPrimitives prim{topo, s, static_cast<std::size_t>(nv),
                                      static_cast<std::size_t>(topo.faces.rows())};
    for (const int threads : {1, 3}) {
      tbb::task_arena arena(threads);
      std::uint64_t entries = 0, work = 0;
      arena.execute([&] {
        entries = detail::grid_sort_count(g, prim, nboxes, s);
        work = detail::grid_sort_fill(g, nboxes, entries, s);
      });
      // A box's range: the union of its vertices' ranges.
      std::vector<detail::GridRange> ranges(nboxes);
      for (std::size_t i = 0; i < nboxes; ++i) {
        const std::array<int, 3> v = detail::primitive_vertices(topo, i);
        ranges[i] = s.grid_vertex_ranges[static_cast<std::size_t>(v[0])];
        for (int k = 1; k < detail::primitive_corners(v); ++k)
          for (std::size_t d = 0; d < 3; ++d) {
            const detail::GridRange& q = s.grid_vertex_ranges[static_cast<std::size_t>(v[k])];
            ranges[i].lo[d] = std::min(ranges[i].lo[d], q.lo[d]);
            ranges[i].hi[d] = std::max(ranges[i].hi[d], q.hi[d]);
          }
      }
      const Csr want = by_definition(g, ranges);
      const std::string where = std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" +
                                std::to_string(dims[2]) + ", " + std::to_string(threads) +
                                " threads";
      ASSERT_EQ(entries, want.entries.size()) << where;
      EXPECT_EQ(s.cell_start, want.start) << where;
      EXPECT_EQ(s.cell_entries, want.entries) << where;
      std::uint64_t want_work = 0;
      for (std::size_t c = 0; c + 1 < want.start.size(); ++c) {
        const std::uint64_t k = want.start[c + 1] - want.start[c];
        want_work += k * (k - 1) / 2;
      }
      EXPECT_EQ(work, want_work) << where;
    }
  }
}

}  // namespace
}  // namespace shellcontract
