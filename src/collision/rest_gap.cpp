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
  std::vector<char> touching(held.size(), 0), touching_ee(held.size(), 0);
  std::size_t visited = 0;
  auto visit = [&](CcdPrimitive kind, const std::array<int, 2>& pair) {
    if (++visited % CANCELLATION_CHUNK == 0) cancellation_point();
    CcdStencil s0, s1;
    gather(rest, rest, stencil(kind, pair, topo), s0, s1);
    const bool vf = kind == CcdPrimitive::VertexFace;
    // Apart beyond the larger reach: neither touching, nor within `inner`, nor near (the cull
    // never culls a pair the interval search reports, ccd.hpp, and its gaps grow with the
    // tolerance). Only its distance counts, for `smallest`; the interval search's setup is
    // what the broad phase's many far pairs of long thin triangles cost.
    if (separating_axis_culls(kind, s0, s1, std::max(reach, inner))) {
      out.smallest =
          std::min(out.smallest, vf ? point_triangle_distance(s0[0], s0[1], s0[2], s0[3])
                                    : segment_segment_distance(s0[0], s0[1], s0[2], s0[3]));
      return;
    }
    if (primitive_ccd(kind, s0, s1, touch).hit) {
      ++(vf ? out.touching_vertex_face : out.touching_edge_edge);
      // A VF pair touches at its vertex; an EE pair somewhere on its edges, named by their ends
      // only where no VF pair names a vertex (edges that cross, not meeting at a vertex).
      const auto v = stencil(kind, pair, topo);
      for (std::size_t k = 0; k < (vf ? 1u : v.size()); ++k)
        (vf ? touching : touching_ee)[static_cast<std::size_t>(v[k])] = 1;
      return;
    }
    if (inner > 0.0 && primitive_ccd(kind, s0, s1, within_inner).hit) return;
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
  // The smallest indices, not the first found: the same names whatever the candidates' order.
  if (out.touching_vertex_face == 0) touching.swap(touching_ee);
  for (std::size_t v = 0; v < touching.size(); ++v) {
    if (touching[v] == 0) continue;
    ++out.touching_vertices;
    if (out.touching_sample.size() < TOUCHING_SAMPLE)
      out.touching_sample.push_back(static_cast<int>(v));
  }
  return out;
}

}  // namespace shellcontract
