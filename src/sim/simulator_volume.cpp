// The Simulator's volume goals (sim/simulator.hpp): the target volume of each frame, and the
// global volume constraint of a target volume or a stop ratio that has the last word on V in a
// step (docs/math/volume-control.md).
#include <algorithm>
#include <vector>

#include "sim/simulator.hpp"
#include "sim/target_ramp.hpp"
#include "sim/volume_constraint.hpp"

namespace shellcontract {
namespace {

/// The inverse masses with the vertices the collision response holds set to 0 (not moved by the
/// volume constraint; see Simulator::apply_volume_control). The regions' dimples hold them too,
/// but keep their share of the correction (project_cap_volume_sharing).
Eigen::VectorXd free_inverse_masses(const Eigen::VectorXd& inv_mass,
                                    const std::vector<char>& held) {
  Eigen::VectorXd w = inv_mass;
  for (std::size_t i = 0; i < held.size(); ++i)
    if (held[i]) w(static_cast<Eigen::Index>(i)) = 0.0;
  return w;
}

}  // namespace

double Simulator::volume_target(int n) const {
  if (!options_.target_volume_schedule.empty()) return options_.target_volume_schedule.at(n);
  if (options_.target_volume <= 0.0) return 0.0;
  // A run shorter than twice the ramp still reaches the target at half its frames.
  const int ramp = target_ramp_used(options_);
  return target_volume_at(n, ramp, 1.0, options_.target_volume);
}

void Simulator::apply_volume_control(Positions& x) {
  // Rounding-level tolerance: the constraint is met to ~1e-12 of V0, far below the 0.005 a
  // target-volume run promises, so collisions and rounding alone decide the error.
  const double tolerance = 1e-12 * constraint_rest_volume_;
  // The vertices the collision response moved in the previous step are held by their contacts:
  // the constraint moves only the free ones. Moving the held ones too would make the response
  // push them back every step and undo part of the volume change, so that a shell in wide contact
  // stalls above its target (eight stalled at V/V0 0.3065 for R = 0.3 that way).
  const Eigen::VectorXd w = free_inverse_masses(inv_mass_, held_by_contact_);
  // At most a hundredth of the mesh (the normalized bounding-box diagonal) per step: a ramp
  // spread over the free vertices asks far less, and a volume that the contacts will not let the
  // shell reach then ends short of it ("not reached", exit 5) instead of sending the few free
  // vertices beyond the mesh (project_volume's max_move).
  constexpr double VOLUME_MAX_MOVE = 0.01;
  // With no vertex held, as far as a smooth shell needs, within a factor for the spread of a
  // mesh's vertex areas (project_volume's smooth_moves): a short ramp's free shell is held at
  // its target instead of carried past it.
  constexpr double SMOOTH_SHELL_MOVES = 4.0;
  const bool none_held =
      std::find(held_by_contact_.begin(), held_by_contact_.end(), 1) == held_by_contact_.end();
  const double smooth_moves = none_held ? SMOOTH_SHELL_MOVES : 0.0;
  if (options_.target_volume > 0.0) {
    const double target = constraint_rest_volume_ * volume_target(frame_ + 1);
    project_volume(x, faces_, w, target, tolerance, 4, VOLUME_MAX_MOVE, smooth_moves);
  } else if (options_.stop_volume_ratio > 0.0) {
    // The step that would cross epsilon ends on it: the run stops at the crossing frame with
    // V/V0 = epsilon up to the collision response, instead of one step's change below it. Whether
    // it stops is decided after the response (step), which can push the volume back up. Capped
    // as a target is: on a shell in wide contact the lift would fling the few free vertices (a
    // blow-up), and lifted in full every crossing step went back above epsilon after the
    // response, so that the run never stopped; capped, it ends at or below epsilon there.
    const double floor = constraint_rest_volume_ * options_.stop_volume_ratio;
    if (signed_volume(x, faces_) <= floor) {
      project_volume(x, faces_, w, floor, tolerance, 4, VOLUME_MAX_MOVE, smooth_moves);
      stop_volume_crossed_ = true;
    }
  }
}

}  // namespace shellcontract
