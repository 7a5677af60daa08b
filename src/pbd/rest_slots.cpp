#include "pbd/rest_slots.hpp"

#include <algorithm>
#include <utility>

namespace shellcontract {

MembraneRestSlots::MembraneRestSlots(const std::vector<MembraneConstraint>& membranes,
                                     std::vector<std::size_t> colour_offsets)
    : colour_offsets_(std::move(colour_offsets)) {
  int faces = 0;
  for (const MembraneConstraint& c : membranes) faces = std::max(faces, c.face + 1);
  record_of_face_.assign(static_cast<std::size_t>(faces), -1);
  for (std::size_t i = 0; i < membranes.size(); ++i)
    if (membranes[i].face >= 0) record_of_face_[static_cast<std::size_t>(membranes[i].face)] = static_cast<int>(i);
}

bool MembraneRestSlots::set(int face, const Mat2& Dm_inv, double rest_area,
                            std::vector<MembraneConstraint>& membranes,
                            std::vector<PackedMembrane>& packed,
                            ColouredBatches<MembraneBatch>& batches) const {
  if (face < 0 || static_cast<std::size_t>(face) >= record_of_face_.size()) return false;
  const int record = record_of_face_[static_cast<std::size_t>(face)];
  if (record < 0) return false;
  const auto i = static_cast<std::size_t>(record);
  MembraneConstraint& c = membranes[i];
  c.Dm_inv = Dm_inv;
  c.Dm_inv(1, 0) = 0.0;  // pack_membrane's precondition (triangle_rest's form)
  c.rest_area = rest_area;
  if (i < packed.size()) packed[i] = pack_membrane(c);
  if (!batches.batches.empty()) {
    const auto [batch, k] = batch_lane(i, colour_offsets_, batches.offsets);
    MembraneBatch& b = batches.batches[batch];
    b.dm00[k] = c.Dm_inv(0, 0);
    b.dm01[k] = c.Dm_inv(0, 1);
    b.dm11[k] = c.Dm_inv(1, 1);
    b.rest_area[k] = c.rest_area;
  }
  return true;
}

void HingeRestSlots::set_angle(std::size_t record, double rest_angle,
                               std::vector<DihedralHingeConstraint>& hinges,
                               ColouredBatches<DihedralBatch>& batches) const {
  if (record >= hinges.size()) return;
  hinges[record].rest.rest_angle = rest_angle;
  if (batches.batches.empty()) return;
  const auto [batch, k] = batch_lane(record, colour_offsets_, batches.offsets);
  batches.batches[batch].rest_angle[k] = rest_angle;
}

std::pair<std::size_t, std::size_t> batch_lane(std::size_t i, const std::vector<std::size_t>& colour_offsets,
                                               const std::vector<std::size_t>& batch_offsets) {
  const auto after = std::upper_bound(colour_offsets.begin(), colour_offsets.end(), i);
  const auto colour = static_cast<std::size_t>(after - colour_offsets.begin()) - 1;
  const std::size_t within = i - colour_offsets[colour];
  return {batch_offsets[colour] + within / BATCH_LANES, within % BATCH_LANES};
}

}  // namespace shellcontract
