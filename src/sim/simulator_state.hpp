// What a Simulator carries from one step to the next besides its rest state: everything a later
// step depends on, so that a run continued from it (sim/checkpoint.hpp) takes the same steps,
// to the bit, as the run that saved it (docs/design/sweeps.md, "What a checkpoint holds").
#pragma once

#include <vector>

#include "collision/self_collision.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

struct SimulatorState {
  int frame = 0;
  double volume_ratio = 1.0;
  bool stop_volume_reached = false;
  Positions x;  ///< normalized positions
  Positions v;  ///< velocities
  /// Vertices the last step's collision response moved: the volume control leaves them alone
  /// in the next step.
  std::vector<char> held_by_contact;
  /// Faces in each region's dimple (RegionDimple::size), in region order: the dimple's cap is
  /// rebuilt from it.
  std::vector<int> dimple_sizes;
  bool has_collision = false;
  SelfCollision::PersistentState collision;
};

}  // namespace shellcontract
