// Rest data changed after the solver is built: where each membrane's and each dihedral hinge's
// rest data lives in the solver's arrays (the records in sweep order, the membranes' packed copy,
// the coloured order's batches), so that a run can change it in all of them at once. The local
// contraction's dimples use it: a dimple placed on its mirror image takes that shape as its rest
// state (docs/math/region-mirror.md, section 6).
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "pbd/constraint_batches.hpp"
#include "pbd/constraints.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// Face -> position of its membrane record, and record -> batch lane.
class MembraneRestSlots {
 public:
  MembraneRestSlots() = default;
  /// @param membranes       the records in sweep order
  /// @param colour_offsets  colour c at [colour_offsets[c], colour_offsets[c + 1]) of membranes
  ///                        (as given to make_membrane_batches)
  MembraneRestSlots(const std::vector<MembraneConstraint>& membranes,
                    std::vector<std::size_t> colour_offsets);

  /// Sets face's rest data (Dm^-1 upper triangular, as triangle_rest makes it, and the area) in
  /// the records, in `packed` when it holds them and in `batches` when they do; the step clamp
  /// stays. A face without a membrane record is left alone.
  /// @return whether the face has a record
  bool set(int face, const Mat2& Dm_inv, double rest_area, std::vector<MembraneConstraint>& membranes,
           std::vector<PackedMembrane>& packed, ColouredBatches<MembraneBatch>& batches) const;

 private:
  std::vector<int> record_of_face_;          ///< -1: no record
  std::vector<std::size_t> colour_offsets_;  ///< as in the constructor
};

/// Record -> batch lane of the dihedral hinges.
class HingeRestSlots {
 public:
  HingeRestSlots() = default;
  /// @param colour_offsets  as given to make_dihedral_batches
  explicit HingeRestSlots(std::vector<std::size_t> colour_offsets)
      : colour_offsets_(std::move(colour_offsets)) {}

  /// Sets the rest angle of hinges[record] there and in `batches` when they hold the hinges.
  void set_angle(std::size_t record, double rest_angle, std::vector<DihedralHingeConstraint>& hinges,
                 ColouredBatches<DihedralBatch>& batches) const;

 private:
  std::vector<std::size_t> colour_offsets_;
};

/// Batch index and lane of record i of a coloured layout (make_batches: colour c from batch
/// batch_offsets[c], BATCH_LANES records per batch, in order).
std::pair<std::size_t, std::size_t> batch_lane(std::size_t i, const std::vector<std::size_t>& colour_offsets,
                                               const std::vector<std::size_t>& batch_offsets);

}  // namespace shellcontract
