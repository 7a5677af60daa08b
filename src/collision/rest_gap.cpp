// The rest state's gaps (collision/rest_gap.hpp).
#include "collision/rest_gap.hpp"

#include <algorithm>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/ccd.hpp"
#include "collision/distance.hpp"
#include "collision/self_collision/common.hpp"
#include "core/cancellation.hpp"

namespace shellcontract {

RestGapSurvey survey_rest_gaps(const CollisionTopology& topo, const Positions& rest, double reach,
                               BroadPhaseMethod method, double inner) {
  using collision_pipeline::gather;
  using collision_pipeline::stencil;
  CandidatePairs pairs;
  // A run's cancel (core/cancellation.hpp): before and after the broad phase, and per chunk of
  // pairs below; `delta` auto surveys a large mesh's rest state while the run is prepared.
  cancellation_point();
  find_candidates(rest, rest, topo, reach, pairs, nullptr, method);
  cancellation_point();
  // The same tests as the collision step's rest classification (RestPairs), so that the counts
  // are the pairs it holds: touching is a hit at tolerance 0, near a hit at tolerance reach.
  CcdOptions touch, near, within_inner;
  touch.tolerance = 0.0;
  near.tolerance = reach;
  within_inner.tolerance = inner;
  RestGapSurvey out;
  std::vector<char> held(static_cast<std::size_t>(topo.num_vertices), 0);
  std::size_t visited = 0;
  auto visit = [&](CcdPrimitive kind, const std::array<int, 2>& pair) {
    if (++visited % CANCELLATION_CHUNK == 0) cancellation_point();
    CcdStencil s0, s1;
    gather(rest, rest, stencil(kind, pair, topo), s0, s1);
    if (primitive_ccd(kind, s0, s1, touch).hit) return;
    if (inner > 0.0 && primitive_ccd(kind, s0, s1, within_inner).hit) return;
    const bool vf = kind == CcdPrimitive::VertexFace;
    const double d = vf ? point_triangle_distance(s0[0], s0[1], s0[2], s0[3])
                        : segment_segment_distance(s0[0], s0[1], s0[2], s0[3]);
    out.smallest = std::min(out.smallest, d);
    // Beyond the held pairs, by the distance itself: a pair exactly at `reach` (the response's
    // target under --delta auto's half gap) is pushed to its rest gap, not beyond it.
    if (inner > 0.0 ? !(d < reach) : !primitive_ccd(kind, s0, s1, near).hit) return;
    ++(vf ? out.near_vertex_face : out.near_edge_edge);
    for (const int v : stencil(kind, pair, topo)) {
      out.near_vertices += held[static_cast<std::size_t>(v)] == 0 ? 1 : 0;
      held[static_cast<std::size_t>(v)] = 1;
    }
  };
  for (const auto& p : pairs.vertex_face) visit(CcdPrimitive::VertexFace, p);
  for (const auto& p : pairs.edge_edge) visit(CcdPrimitive::EdgeEdge, p);
  return out;
}

}  // namespace shellcontract
