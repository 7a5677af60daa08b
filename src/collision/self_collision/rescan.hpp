// The rescans of the response: after a push or a revert, the pass over the live pairs that marks
// the moved vertices' pairs stale and collects the next tests (in the zone around the moved
// vertices where that gives the same).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "collision/self_collision/step_pairs.hpp"
#include "shellcontract/observer.hpp"

namespace shellcontract::collision_pipeline {

/// Owns the moved vertices of the step and the zone around them.
class Rescan {
 public:
  /// narrow_rescans: CollisionOptions::narrow_rescans (passes that visit only the zone).
  Rescan(std::size_t vertices, bool narrow_rescans)
      : narrow_rescans_(narrow_rescans), moved_(vertices, 0) {}

  /// A new step's pairs: no zone yet.
  void begin_step();
  /// Vertex v moved (by the response or the fail-safe) since the last collect.
  void mark(int v) {
    std::uint8_t& f = moved_[static_cast<std::size_t>(v)];
    if (f & MOVED) return;
    f |= MOVED;
    moved_list_.push_back(v);
  }

  /// Marks stale every live pair with a vertex marked moved and clears the marks, then sets
  /// pairs.tests to the live pairs to test next, in increasing order, in the same pass over the
  /// pairs: the rounds' (stale and NORMAL) or, with FAILSAFE, the fail-safe's (stale, or not free,
  /// or NEAR). Visits only the zone's pairs where that gives the same; counts the pass in stats.
  template <bool FAILSAFE>
  void collect(tbb::task_arena& arena, StepPairs& pairs, CollisionStepStats& stats);

 private:
  /// Per-vertex flags of moved_.
  static constexpr std::uint8_t MOVED = 1;  ///< moved since the last pass over the pairs
  static constexpr std::uint8_t ZONE = 2;   ///< moved since the step's start: a zone vertex

  bool narrow_rescans_;
  /// per vertex: flags MOVED (by the response or the fail-safe, since the last pass over the
  /// pairs) and ZONE (a zone vertex)
  std::vector<std::uint8_t> moved_;
  std::vector<int> moved_list_;  ///< the vertices with MOVED set
  /// The zone: per live unit, the unit's live pairs that touch a zone vertex or were stale or
  /// not free after the pass that listed them (pair ids and stencils, zone_count_[u] from the
  /// unit's begin).
  PairArray<std::uint32_t> zone_pair_;
  PairArray<std::array<int, 4>> zone_v_;
  std::vector<std::size_t> zone_count_;
  std::vector<int> zone_vertices_;  ///< the vertices with ZONE set
  enum class ZoneState : std::uint8_t { None, Ready, TooLarge };
  ZoneState zone_state_ = ZoneState::None;
  std::vector<std::size_t> block_count_;  ///< tests collected per live unit
};

}  // namespace shellcontract::collision_pipeline
