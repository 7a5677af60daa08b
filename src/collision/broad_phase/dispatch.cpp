// The broad phase's public entry points: find_candidates dispatches to the method asked for
// (and the Grid's fallback), the speculative broad phase's grid calls, the far-pair threshold.

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/broad_phase/boxes.hpp"
#include "collision/broad_phase/grid.hpp"
#include "core/stage_timer.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {

using detail::BroadPhaseBox;
using detail::Grid;
using detail::GRID_ALL_FIRST;
using detail::GridPrimitives;

CandidatePairs::CandidatePairs() : scratch(std::make_unique<BroadPhaseScratch>()) {}
CandidatePairs::~CandidatePairs() = default;
CandidatePairs::CandidatePairs(CandidatePairs&&) noexcept = default;
CandidatePairs& CandidatePairs::operator=(CandidatePairs&&) noexcept = default;

GridPartSeconds grid_part_seconds(const CandidatePairs& pairs) {
  const BroadPhaseScratch& s = *pairs.scratch;
  return {s.grid_build_seconds, s.grid_cell_loop_seconds, s.grid_output_seconds};
}

double far_gap_threshold(const Positions& x0, const Positions& x1, double inflation,
                         double far_distance) {
  // A pair is flagged far if on some axis the gap g between its two (inflated, rounded) boxes
  // exceeds far_gap. Each box bound is fl(c -+ inflation) for an exact coordinate c with
  // |c| <= M, off by at most u (M + inflation), and the computed difference adds u (2M +
  // 2 inflation) (1 + u); so g > far_gap = (far - 2 inflation) + 8 u (M + inflation + far),
  // itself rounded a few times (a few u (far + 2 inflation) more), leaves the exact gap of the
  // boxes before inflation above `far`.
  if (!(far_distance >= 0.0) || !std::isfinite(far_distance))
    return std::numeric_limits<double>::infinity();
  const double m =
      x0.rows() > 0 ? std::max(x0.cwiseAbs().maxCoeff(), x1.cwiseAbs().maxCoeff()) : 0.0;
  return far_gap_threshold_for_magnitude(m, inflation, far_distance);
}

double far_gap_threshold_for_magnitude(double max_abs, double inflation, double far_distance) {
  if (!(far_distance >= 0.0) || !std::isfinite(far_distance))
    return std::numeric_limits<double>::infinity();
  constexpr double u = std::numeric_limits<double>::epsilon() / 2.0;
  return (far_distance - 2.0 * inflation) + 8.0 * u * (max_abs + inflation + far_distance);
}

bool find_candidates_in_vertex_boxes(const std::vector<detail::GridVertexBox>& boxes,
                                     const CollisionTopology& topo, CandidatePairs& out) {
  if (boxes.size() != static_cast<std::size_t>(topo.num_vertices))
    throw UsageError("broad phase: " + std::to_string(boxes.size()) + " vertex boxes for " +
                     std::to_string(topo.num_vertices) + " vertices");
  out.scratch->grid_vertex_boxes = boxes;
  // Sorted, as find_candidates' pairs: the cell order depends on the grid kept from the last
  // call, which a resumed run does not have, and the collision step's result depends on the
  // order (a resume in the sequential order, where this path is on by default, gave other bits).
  if (detail::grid_pairs(topo, std::numeric_limits<double>::infinity(), out,
                         out.scratch->grid_float_superset, /*sorted=*/true) >= 0)
    return true;
  out.scratch->grid_kept = false;
  return false;
}

void query_kept_grid(const CandidatePairs& pairs, const CollisionTopology& topo,
                     const detail::GridVertexBox& box, std::vector<std::uint32_t>& out,
                     std::uint32_t first_id, std::uint32_t end_id) {
  const BroadPhaseScratch& s = *pairs.scratch;
  if (!s.grid_kept) throw UsageError("query_kept_grid: no grid is kept");
  Grid g;
  g.origin = s.grid_origin;
  g.inv_h = s.grid_inv_h;
  g.dims = s.grid_dims;
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  const GridPrimitives prim{topo, s, nv, static_cast<std::size_t>(topo.faces.rows())};
  std::array<std::size_t, 3> lo{}, hi{};
  for (std::size_t d = 0; d < 3; ++d) {
    lo[d] = g.coord(box.lo[d], d);
    hi[d] = g.coord(box.hi[d], d);
  }
  // A stored box meets the query in every cell of the intersection of their cell ranges (coord
  // is monotone); it is reported in the first of them, where on each axis the cell is the stored
  // box's first (its entry flag) or the query's first.
  const std::size_t sy = g.dims[0], sz = g.dims[0] * g.dims[1];
  for (std::size_t z = lo[2]; z <= hi[2]; ++z)
    for (std::size_t y = lo[1]; y <= hi[1]; ++y)
      for (std::size_t x = lo[0]; x <= hi[0]; ++x) {
        const std::size_t c = z * sz + y * sy + x;
        const std::uint32_t query_first =
            (x == lo[0] ? 1u : 0u) | (y == lo[1] ? 2u : 0u) | (z == lo[2] ? 4u : 0u);
        // The cell's entries are in increasing id order (the counting sort's), so the ids
        // asked for are one run of them: found by binary search, the rest never touched (a
        // vertex's query asks for the faces only, about a third of a cell's entries; a face's
        // for the vertices, about a sixth).
        const std::uint32_t* const cell_begin = s.cell_entries.data() + s.cell_start[c];
        const std::uint32_t* const cell_end = s.cell_entries.data() + s.cell_start[c + 1];
        const std::uint32_t* k = std::partition_point(
            cell_begin, cell_end, [&](std::uint32_t tag) { return (tag >> 3) < first_id; });
        for (; k != cell_end; ++k) {
          const std::uint32_t tag = *k;
          const std::uint32_t gid = tag >> 3;
          if (gid >= end_id) break;
          if (((tag | query_first) & GRID_ALL_FIRST) != GRID_ALL_FIRST) continue;
          if (detail::overlap(box, prim.box(prim.ids(gid)))) out.push_back(gid);
        }
      }
}

void find_candidates(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                     double inflation, CandidatePairs& out, BroadPhaseStats* stats,
                     BroadPhaseMethod method, double far_distance) {
  const StageTimer start;
  detail::check_inputs(x0, x1, topo, inflation);
  const double far_gap = far_gap_threshold(x0, x1, inflation, far_distance);
  // Grid keeps only vertex boxes (GridVertexBox); the others share BroadPhaseBox.
  if (method == BroadPhaseMethod::Grid)
    detail::build_grid_vertex_boxes(x0, x1, inflation, out.scratch->grid_vertex_boxes);
  else
    detail::build_boxes(x0, x1, topo, inflation, *out.scratch, true, true);
  std::int64_t reported = 0;
  BroadPhaseMethod ran = method;
  switch (method) {
    case BroadPhaseMethod::PrimitiveBoxes:
      reported = detail::primitive_boxes(topo, out);
      break;
    case BroadPhaseMethod::FacePairs:
      reported = detail::face_pairs(topo, out);
      break;
    case BroadPhaseMethod::Bvh:
      reported = detail::bvh_pairs(topo, out);
      break;
    case BroadPhaseMethod::Grid:
      // Sorted: the grid emits in the order of its cells, and a call may keep the last call's
      // grid (its origin and cell size), which a fresh CandidatePairs (a resumed run's) does not
      // have; the collision step's result depends on the pairs' order, so the order must come
      // from the pairs alone: the same for any grid, any thread count and after a resume.
      reported = detail::grid_pairs(topo, far_gap, out, false, true);
      if (reported < 0) {
        ran = BroadPhaseMethod::PrimitiveBoxes;
        detail::build_boxes(x0, x1, topo, inflation, *out.scratch, true, true);
        reported = detail::primitive_boxes(topo, out);
      }
      break;
  }
  if (ran != BroadPhaseMethod::Grid) {
    // Only the grid has the exact boxes at hand when it emits a pair: the others flag none far.
    out.vertex_face_close.assign(out.vertex_face.size(), 1);
    out.edge_edge_close.assign(out.edge_edge.size(), 1);
  }
  if (stats) {
    stats->no_culling_vertex_face = topo.all_vertex_face_pairs;
    stats->no_culling_edge_edge = topo.all_edge_edge_pairs;
    stats->box_overlaps = reported;
    stats->method_run = ran;
    stats->vertex_face = static_cast<std::int64_t>(out.vertex_face.size());
    stats->edge_edge = static_cast<std::int64_t>(out.edge_edge.size());
    stats->seconds = start.elapsed();
  }
}

}  // namespace shellcontract
