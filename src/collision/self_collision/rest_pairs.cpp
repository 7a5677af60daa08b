// The rest state's excluded and near pairs, and the pair records with their rest-state roles.
#include "collision/self_collision/rest_pairs.hpp"

#include <algorithm>

#include "core/cancellation.hpp"

namespace shellcontract::collision_pipeline {

// A run's cancel (core/cancellation.hpp) is heard around the broad phase and per chunk of pairs:
// the Simulator classifies a large mesh's rest pairs while the run is prepared.
RestPairs::RestPairs(const Positions& rest, const CollisionTopology& topo,
                     const CollisionOptions& options, CandidatePairs& scratch) {
  // Pairs that touch (distance 0) in the rest state cannot be separated by a response that
  // keeps each pair on its starting side: exclude them for the whole run. Pairs closer than
  // delta (but not touching) are the input's own thin features: the response leaves them at
  // their rest distance (a shell at rest stays at rest), but the fail-safe still keeps them
  // from crossing.
  cancellation_point();
  find_candidates(rest, rest, topo, options.delta, scratch, nullptr, options.method);
  cancellation_point();
  CcdOptions touch, near;
  touch.tolerance = 0.0;
  near.tolerance = options.delta;
  std::size_t classified = 0;
  auto classify = [&](CcdPrimitive kind, const std::array<int, 2>& pair) {
    if (++classified % CANCELLATION_CHUNK == 0) cancellation_point();
    CcdStencil s0, s1;
    gather(rest, rest, stencil(kind, pair, topo), s0, s1);
    const bool vf = kind == CcdPrimitive::VertexFace;
    // Apart beyond delta: neither touching nor near (the cull never culls a pair the interval
    // search reports, ccd.hpp), without the interval search's setup.
    if (separating_axis_culls(kind, s0, s1, options.delta)) return;
    if (primitive_ccd(kind, s0, s1, touch).hit)
      (vf ? excluded_vf_ : excluded_ee_).push_back(pair);
    else if (primitive_ccd(kind, s0, s1, near).hit)
      (vf ? near_vf_ : near_ee_).push_back(pair);
  };
  for (const auto& p : scratch.vertex_face) classify(CcdPrimitive::VertexFace, p);
  for (const auto& p : scratch.edge_edge) classify(CcdPrimitive::EdgeEdge, p);
  // Sorted for the binary searches of role() (the Grid's candidates are in cell order).
  for (auto* list : {&excluded_vf_, &excluded_ee_, &near_vf_, &near_ee_})
    std::sort(list->begin(), list->end());
}

PairRole RestPairs::role(CcdPrimitive kind, const std::array<int, 2>& pair) const {
  auto listed = [&](const std::vector<std::array<int, 2>>& list) {
    return !list.empty() && std::binary_search(list.begin(), list.end(), pair);
  };
  const bool vf = kind == CcdPrimitive::VertexFace;
  if (listed(vf ? excluded_vf_ : excluded_ee_)) return EXCLUDED;
  if (listed(vf ? near_vf_ : near_ee_)) return NEAR;
  return NORMAL;
}

void RestPairs::fill_records(const CandidatePairs& c, const CollisionTopology& topo,
                             std::size_t begin, std::size_t end, std::size_t nvf,
                             PairRecord* records, std::uint8_t* roles) const {
  // One loop per kind over raw pointers, and the rest-state lists searched only if the kind has
  // any (none on bear): the per-pair call with its member reloads was a visible share of the
  // background task's thread at strong pressure (perf; lab/history.md).
  PairRecord* const rec = records;
  const std::size_t split = std::clamp(nvf, begin, end);
  const bool vf_listed = !excluded_vf_.empty() || !near_vf_.empty();
  const bool ee_listed = !excluded_ee_.empty() || !near_ee_.empty();
  const std::array<int, 2>* const vf = c.vertex_face.data();
  const std::array<int, 2>* const ee = c.edge_edge.data();
  for (std::size_t i = begin; i < split; ++i) {
    PairRecord& p = rec[i];
    p.kind = CcdPrimitive::VertexFace;
    p.pair = vf[i];
    p.v = stencil(p.kind, p.pair, topo);
    roles[i] = vf_listed ? role(p.kind, p.pair) : NORMAL;
  }
  for (std::size_t i = split; i < end; ++i) {
    PairRecord& p = rec[i];
    p.kind = CcdPrimitive::EdgeEdge;
    p.pair = ee[i - nvf];
    p.v = stencil(p.kind, p.pair, topo);
    roles[i] = ee_listed ? role(p.kind, p.pair) : NORMAL;
  }
}

}  // namespace shellcontract::collision_pipeline
