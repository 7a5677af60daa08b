// The rest state's gaps between primitives that are not neighbours: what a contact distance can be
// without putting pairs in contact at rest (docs/design/self-collision.md, "Rest state").
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "collision/topology.hpp"
#include "shellcontract/simulation_options.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// The VF and EE pairs of a rest state that lie within a reach of each other without touching,
/// and those that touch (the collision step's excluded pairs: RestPairs).
struct RestGapSurvey {
  /// Smallest distance between the primitives of a pair that does not touch at rest (the
  /// collision step's NEAR or NORMAL pairs), among the pairs within `reach`; +infinity if none.
  double smallest = std::numeric_limits<double>::infinity();
  std::size_t near_vertex_face = 0;  ///< pairs closer than `reach` at rest, not touching
  std::size_t near_edge_edge = 0;
  std::size_t near_vertices = 0;  ///< distinct vertices of those pairs
  std::size_t near_pairs() const { return near_vertex_face + near_edge_edge; }
  /// Pairs that touch at rest (distance 0; counted whatever `reach` and `inner`): the collision
  /// step excludes them for the whole run, so nothing keeps them on their sides.
  std::size_t touching_vertex_face = 0;
  std::size_t touching_edge_edge = 0;
  /// Distinct vertices where they touch: the VF pairs' vertices (or, without a VF pair, the EE
  /// pairs' ends).
  std::size_t touching_vertices = 0;
  /// The smallest of those vertices' indices (at most TOUCHING_SAMPLE), for a message to name.
  std::vector<int> touching_sample;
  std::size_t touching_pairs() const { return touching_vertex_face + touching_edge_edge; }
};

/// How many of the touching vertices a survey keeps in touching_sample.
inline constexpr std::size_t TOUCHING_SAMPLE = 4;

/// Surveys the pairs of `rest` within `reach` (> 0) as the collision step classifies them
/// (SelfCollision: touching pairs are excluded, pairs closer than delta are NEAR): with
/// reach == delta, near_pairs() is the number of pairs the step holds at their rest distance.
/// A contact distance below `smallest` leaves no pair near at rest.
/// With `inner` > 0, the pairs near at `inner` (the ones a contact distance of `inner` holds) are
/// left out altogether, and the others count when their distance is below `reach`: with
/// inner == delta and reach == 2 delta (the response's target), the pairs that a contact pushes
/// apart beyond their rest gap; `smallest` is then the smallest gap among the pairs not left out.
RestGapSurvey survey_rest_gaps(const CollisionTopology& topo, const Positions& rest, double reach,
                               BroadPhaseMethod method = DEFAULT_BROAD_PHASE_METHOD,
                               double inner = 0.0);

}  // namespace shellcontract
