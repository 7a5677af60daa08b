// The Grid method's vertex boxes and the patch of a kept grid's counting sort (temporal
// coherence: between steps only a few boxes change their cell range).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "collision/broad_phase/grid.hpp"

namespace shellcontract {
namespace detail {

void build_grid_vertex_boxes(const Positions& x0, const Positions& x1, double inflation,
                             std::vector<detail::GridVertexBox>& boxes) {
  boxes.resize(static_cast<std::size_t>(x0.rows()));
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, x0.rows(), GRID_VERTEX_GRAIN),
                    [&](const tbb::blocked_range<Eigen::Index>& r) {
                      for (Eigen::Index v = r.begin(); v < r.end(); ++v) {
                        detail::GridVertexBox& b = boxes[static_cast<std::size_t>(v)];
                        for (Eigen::Index d = 0; d < 3; ++d) {
                          const double a = x0(v, d), c = x1(v, d);
                          b.lo[static_cast<std::size_t>(d)] = std::min(a, c) - inflation;
                          b.hi[static_cast<std::size_t>(d)] = std::max(a, c) + inflation;
                        }
                      }
                    });
}

namespace {

/// Builds s.grid_vertex_prims (per vertex, the grid ids of the faces and edges it is a corner
/// of) and keeps a copy of the topology it was built for, unless that copy equals `topo`
/// already. Returns whether it was rebuilt.
bool update_vertex_prims(const CollisionTopology& topo, BroadPhaseScratch& s) {
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  const std::size_t nf = static_cast<std::size_t>(topo.faces.rows());
  const std::size_t ne = static_cast<std::size_t>(topo.edges.rows());
  const std::size_t face_ints = 3 * nf, edge_ints = 2 * ne;
  if (s.grid_topology_vertices == nv && s.grid_topology.size() == face_ints + edge_ints &&
      std::equal(topo.faces.data(), topo.faces.data() + face_ints, s.grid_topology.begin()) &&
      std::equal(topo.edges.data(), topo.edges.data() + edge_ints,
                 s.grid_topology.begin() + static_cast<std::ptrdiff_t>(face_ints)))
    return false;
  s.grid_topology_vertices = nv;
  s.grid_topology.assign(topo.faces.data(), topo.faces.data() + face_ints);
  s.grid_topology.insert(s.grid_topology.end(), topo.edges.data(), topo.edges.data() + edge_ints);
  // Counting sort of (vertex, primitive) by vertex: faces first, then edges, each by id, so
  // each vertex lists its primitives in increasing grid id.
  std::vector<std::uint32_t>& start = s.grid_vertex_prims_start;
  start.assign(nv + 1, 0);
  for (std::size_t k = 0; k < face_ints + edge_ints; ++k)
    ++start[static_cast<std::size_t>(s.grid_topology[k]) + 1];
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  s.grid_vertex_prims.resize(start[nv]);
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t k = 0; k < face_ints + edge_ints; ++k) {
    const std::size_t gid = k < face_ints ? nv + k / 3 : nv + nf + (k - face_ints) / 2;
    s.grid_vertex_prims[fill[static_cast<std::size_t>(s.grid_topology[k])]++] =
        static_cast<std::uint32_t>(gid);
  }
  return true;
}

}  // namespace

bool patch_grid(const Grid& g, const GridPrimitives& prim, std::size_t nboxes,
                BroadPhaseScratch& s) {
  const std::size_t nv = prim.nv;
  const std::vector<detail::GridRange>& vr = s.grid_vertex_ranges;
  const std::vector<detail::GridRange>& vr_prev = s.grid_vertex_ranges_prev;
  auto same = [](const detail::GridRange& a, const detail::GridRange& b) {
    return a.lo[0] == b.lo[0] && a.lo[1] == b.lo[1] && a.lo[2] == b.lo[2] && a.hi[0] == b.hi[0] &&
           a.hi[1] == b.hi[1] && a.hi[2] == b.hi[2];
  };
  // The boxes that may have changed: every one after a change of topology, else those with a
  // vertex whose range changed (a bit per box; a bitset stays in the first-level cache).
  const std::size_t words = (nboxes + 63) / 64;
  std::vector<std::uint64_t>& maybe = s.grid_maybe_bits;
  const bool all = update_vertex_prims(prim.topo, s) || vr_prev.size() != nv;
  maybe.assign(words, all ? ~std::uint64_t{0} : 0);
  if (!all) {
    auto mark = [&](std::size_t id) { maybe[id >> 6] |= std::uint64_t{1} << (id & 63); };
    for (std::size_t v = 0; v < nv; ++v) {
      if (same(vr[v], vr_prev[v])) continue;
      mark(v);
      for (std::uint32_t k = s.grid_vertex_prims_start[v]; k < s.grid_vertex_prims_start[v + 1];
           ++k)
        mark(s.grid_vertex_prims[k]);
    }
  }
  // The changed boxes, in increasing id order, their new ranges, and a bit per changed box for
  // the merge's lookups.
  s.grid_changed_ids.clear();
  s.grid_changed_ranges.clear();
  s.grid_changed_bits.assign(words, 0);
  const std::size_t limit = nboxes / GRID_PATCH_DIVISOR;
  for (std::size_t w = 0; w < words; ++w)
    for (std::uint64_t bits = maybe[w]; bits != 0; bits &= bits - 1) {
      const std::size_t i = 64 * w + static_cast<std::size_t>(__builtin_ctzll(bits));
      if (i >= nboxes) break;
      const detail::GridRange n = prim.range(prim.ids(i));
      if (same(n, s.grid_ranges[i])) continue;
      if (s.grid_changed_ids.size() == limit) return false;
      s.grid_changed_ids.push_back(static_cast<std::uint32_t>(i));
      s.grid_changed_ranges.push_back(n);
      s.grid_changed_bits[i >> 6] |= std::uint64_t{1} << (i & 63);
    }
  // The changed boxes' new entries, counting-sorted by cell (in id order within a cell).
  const std::size_t ncell = g.cells();
  std::vector<std::uint32_t>& add_start = s.grid_add_start;
  add_start.assign(ncell + 1, 0);
  const std::size_t nchanged = s.grid_changed_ids.size();
  for (const detail::GridRange& r : s.grid_changed_ranges)
    for_each_cell(g, r,
                  [&](std::size_t c, std::uint32_t, bool valid) { add_start[c + 1] += valid; });
  for (std::size_t c = 0; c < ncell; ++c) add_start[c + 1] += add_start[c];
  s.grid_adds.resize(add_start[ncell]);
  s.cell_fill.assign(add_start.begin(), add_start.end() - 1);
  for (std::size_t k = 0; k < nchanged; ++k) {
    const std::uint32_t tag = s.grid_changed_ids[k] << 3;
    for_each_cell(g, s.grid_changed_ranges[k], [&](std::size_t c, std::uint32_t flags, bool valid) {
      if (valid) s.grid_adds[s.cell_fill[c]++] = tag | flags;
    });
  }
  // The cells the patch changes: those of the changed boxes' old ranges (entries leave) and
  // new ranges (entries come). The others keep their entries, copied as runs of cells.
  s.grid_dirty.assign(ncell + 1, 0);
  std::uint8_t* const dirty = s.grid_dirty.data();
  for (std::size_t k = 0; k < nchanged; ++k) {
    const auto mark = [&](std::size_t c, std::uint32_t, bool valid) {
      dirty[valid ? c : ncell] = 1;
    };
    for_each_cell(g, s.grid_ranges[s.grid_changed_ids[k]], mark);
    for_each_cell(g, s.grid_changed_ranges[k], mark);
  }
  // Merge cell by cell: the old entries without the changed boxes', and the new ones.
  const std::vector<std::uint32_t>& start = s.cell_start;
  const std::uint32_t* const entry = s.cell_entries.data();
  const std::uint32_t* const adds = s.grid_adds.data();
  const std::uint64_t* const gone = s.grid_changed_bits.data();
  std::vector<std::uint32_t>& next_start = s.cell_start_next;
  std::vector<std::uint32_t>& next_entries = s.cell_entries_next;
  next_start.resize(ncell + 1);
  next_entries.resize(static_cast<std::size_t>(start[ncell]) + s.grid_adds.size());
  std::uint32_t* const next = next_entries.data();
  auto kept = [&](std::uint32_t tag) {
    const std::uint32_t id = tag >> 3;
    return ((gone[id >> 6] >> (id & 63)) & 1u) == 0;
  };
  std::size_t out = 0;
  for (std::size_t c = 0; c < ncell; ++c) {
    if (!dirty[c]) {  // a run of unchanged cells: shifted offsets, one copy of their entries
      const std::size_t run = c;
      const std::uint32_t shift = static_cast<std::uint32_t>(out) - start[run];  // mod 2^32
      for (; c < ncell && !dirty[c]; ++c) next_start[c] = start[c] + shift;
      std::copy(entry + start[run], entry + start[c], next + out);
      out += start[c] - start[run];
      if (c == ncell) break;
    }
    next_start[c] = static_cast<std::uint32_t>(out);
    std::uint32_t k = start[c];
    const std::uint32_t e = start[c + 1];
    for (std::uint32_t a = add_start[c]; a < add_start[c + 1]; ++a) {
      for (; k < e && entry[k] < adds[a]; ++k) {
        next[out] = entry[k];
        out += kept(entry[k]) ? 1 : 0;
      }
      next[out++] = adds[a];
    }
    for (; k < e; ++k) {
      next[out] = entry[k];
      out += kept(entry[k]) ? 1 : 0;
    }
  }
  next_start[ncell] = static_cast<std::uint32_t>(out);
  next_entries.resize(out);
  s.cell_start.swap(next_start);
  s.cell_entries.swap(next_entries);
  for (std::size_t k = 0; k < nchanged; ++k)
    s.grid_ranges[s.grid_changed_ids[k]] = s.grid_changed_ranges[k];
  s.grid_patched_boxes = static_cast<std::int64_t>(nchanged);
  return true;
}

}  // namespace detail
}  // namespace shellcontract
