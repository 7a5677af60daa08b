// The rest state's classification of the pairs (part of the broad phase): pairs that touch at rest
// are excluded for the whole run, pairs closer than delta at rest get no response push.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/self_collision/common.hpp"
#include "shellcontract/simulation_options.hpp"

namespace shellcontract::collision_pipeline {

/// The excluded and near pairs of the rest state, and the records of a broad phase's pairs with
/// their rest-state roles.
class RestPairs {
 public:
  /// Classifies the pairs of `rest` (find_candidates with inflation delta, run in `scratch`, the
  /// broad phase's buffers).
  RestPairs(const Positions& rest, const CollisionTopology& topo, const CollisionOptions& options,
            CandidatePairs& scratch);

  /// The rest-state role of a VF or EE pair (NORMAL, NEAR or EXCLUDED).
  PairRole role(CcdPrimitive kind, const std::array<int, 2>& pair) const;

  /// Whether no pair is excluded (then every candidate is live).
  bool none_excluded() const { return excluded_vf_.empty() && excluded_ee_.empty(); }
  std::size_t excluded_pairs() const { return excluded_vf_.size() + excluded_ee_.size(); }

  /// records[i] from the candidate i of `c` (VF first, nvf of them) and roles[i] its rest-state
  /// role, for i in [begin, end).
  void fill_records(const CandidatePairs& c, const CollisionTopology& topo, std::size_t begin,
                    std::size_t end, std::size_t nvf, PairRecord* records,
                    std::uint8_t* roles) const;

 private:
  std::vector<std::array<int, 2>> excluded_vf_;  ///< sorted
  std::vector<std::array<int, 2>> excluded_ee_;  ///< sorted
  std::vector<std::array<int, 2>> near_vf_;      ///< closer than delta at rest, sorted
  std::vector<std::array<int, 2>> near_ee_;      ///< closer than delta at rest, sorted
};

}  // namespace shellcontract::collision_pipeline
