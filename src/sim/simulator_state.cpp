// The Simulator's state for a checkpoint and its restore (src/sim/checkpoint.cpp): every piece
// that a later step reads, so that a resumed run gives the uninterrupted run's bytes. Apart from
// simulator.cpp, which builds and steps the simulation.
#include <string>
#include <utility>

#include "collision/self_collision.hpp"
#include "shellcontract/error.hpp"
#include "sim/region_dimple.hpp"
#include "sim/simulator.hpp"

namespace shellcontract {

SimulatorState Simulator::state() const {
  SimulatorState s;
  s.frame = frame_;
  s.volume_ratio = volume_ratio_;
  s.stop_volume_reached = stop_volume_reached_;
  s.x = x_;
  s.v = v_;
  s.held_by_contact = held_by_contact_;
  for (const RegionDimple& d : region_dimples_) s.dimple_sizes.push_back(d.size);
  s.has_collision = collision_ != nullptr;
  if (collision_) s.collision = collision_->persistent_state();
  return s;
}

void Simulator::restore(SimulatorState s) {
  const Eigen::Index n = x_.rows();
  const auto bad = [](const std::string& what) {
    throw InputError("the checkpoint does not fit this run: " + what);
  };
  if (s.x.rows() != n || s.x.cols() != 3 || s.v.rows() != n || s.v.cols() != 3)
    bad("it has " + std::to_string(s.x.rows()) + " vertices, the mesh " + std::to_string(n));
  if (!s.held_by_contact.empty() && s.held_by_contact.size() != static_cast<std::size_t>(n))
    bad("its contact marks are not one per vertex");
  if (s.dimple_sizes.size() != region_dimples_.size())
    bad("it has " + std::to_string(s.dimple_sizes.size()) + " region dimples, the run " +
        std::to_string(region_dimples_.size()));
  if (s.has_collision != (collision_ != nullptr)) bad("collisions on in one, off in the other");
  if (s.frame < 0) bad("a negative frame");
  frame_ = s.frame;
  volume_ratio_ = s.volume_ratio;
  stop_volume_reached_ = s.stop_volume_reached;
  x_ = std::move(s.x);
  v_ = std::move(s.v);
  held_by_contact_ = std::move(s.held_by_contact);
  // Through resize_dimple, so that the dimples' rest shapes are those of the run that wrote it.
  for (std::size_t i = 0; i < region_dimples_.size(); ++i) resize_dimple(i, s.dimple_sizes[i]);
  if (collision_) collision_->restore_persistent_state(std::move(s.collision));
}

}  // namespace shellcontract
