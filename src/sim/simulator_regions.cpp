// The Simulator's local contraction (docs/math/region-mirror.md): each step the regions' dimples
// grow with the ramp, take their image's rest state, and are placed on their mirror images (or
// projected onto their volume). The rest of the step is simulator.cpp's.
#include "sim/simulator.hpp"

#include <algorithm>
#include <optional>
#include <vector>

#include "sim/dimple_rest.hpp"
#include "sim/region_dimple.hpp"
#include "sim/region_mirror.hpp"
#include "sim/region_volume.hpp"
#include "sim/target_ramp.hpp"
#include "sim/volume_constraint.hpp"

namespace shellcontract {

void Simulator::apply_region_contraction(Positions& x) {
  if (region_dimples_.empty()) return;
  // The same ramp as a target volume's: the regions start and stop sinking gently.
  const int ramp = target_ramp_used(options_);
  const double t = std::clamp(static_cast<double>(frame_ + 1) / ramp, 0.0, 1.0);
  const double s = t * t * (3.0 - 2.0 * t);
  // The shell's own contraction rho is measured with the caps cut off at their rims: a sinking
  // region lowers V/V0 by itself, and a target scaled by that would chase its own sinking.
  double caps_now = 0.0, caps_rest = 0.0;
  for (const RegionDimple& d : region_dimples_) {
    caps_now += cap_volume(x, d.whole);
    caps_rest += d.whole.rest_volume;
  }
  const double rest_outside = constraint_rest_volume_ - caps_rest;
  const double ratio = rest_outside > 0.0 ? (signed_volume(x, faces_) - caps_now) / rest_outside
                                          : signed_volume(x, faces_) / constraint_rest_volume_;
  if (!(ratio > 0.0)) return;  // a shell turned inside out has no caps to sink
  // The mirrors follow the shell away from the regions (region_mirror.hpp, shell_frame), not
  // their own rims, which their dimples pull in; the rim's fit is the fallback when nothing lies
  // away from the regions.
  std::optional<Similarity> frame;
  if (options_.dimple_shape == DimpleShape::Mirror)
    frame = shell_frame(rest_x_, x, outside_vertices_);
  // Vertices held by the last step's contacts stay (see apply_volume_control) and keep their
  // share of the correction (project_cap_volume_sharing).
  for (std::size_t i = 0; i < region_dimples_.size(); ++i) {
    RegionDimple& d = region_dimples_[i];
    const double strength = options_.region_shrink * dimple_weight_[i];
    const double wanted = dimple_rest_volume(d.whole.rest_volume, strength, s, ratio);
    if (!(wanted > 0.0)) continue;
    resize_dimple(i, dimple_size_for(d, wanted));
    if (!(d.dimple.rest_volume > 0.0)) continue;
    const double target = -ratio * d.dimple.rest_volume;
    // One-sided: a dimple the global contraction has already sunk further is left alone.
    if (!(cap_volume(x, d.dimple) > target)) continue;
    // The mirror (an isometry) where the dimple has one; the volume projection otherwise.
    // resize_dimple made d.mirror for the dimple's current size.
    if (options_.dimple_shape == DimpleShape::Mirror) {
      if (frame ? apply_region_mirror_in(x, d.dimple, d.mirror, *frame, inv_mass_,
                                         held_by_contact_, MirrorStep{1.0, true, true, true})
                : apply_region_mirror(x, d.dimple, d.mirror, inv_mass_, held_by_contact_,
                                      MirrorStep{1.0, false, false, true}))
        continue;
    }
    // No vertex moves farther than the dimple's rest size in one step: the ramp spreads a
    // cap's sinking over frames, and a dimple whose every vertex is on its rim (a coarse mesh's
    // region) would otherwise be thrown through the shell (project_cap_volume's max_move).
    project_cap_volume_sharing(x, d.dimple, inv_mass_, held_by_contact_, target,
                               1e-12 * d.dimple.rest_volume, 4, cap_reach(rest_x_, d.dimple));
  }
}

void Simulator::resize_dimple(std::size_t i, int size) {
  RegionDimple& d = region_dimples_[i];
  const int before = d.size;
  set_dimple_size(d, faces_, size);
  if (options_.dimple_shape != DimpleShape::Mirror || d.size == before) return;
  // The new rim's mirror, made once for both its users: the rest state below and the placement
  // in apply_region_contraction. The Simulator changes a dimple's size only here, so under
  // DimpleShape::Mirror d.mirror is always the current dimple's.
  d.mirror = make_region_mirror(rest_x_, d.dimple);
  if (dimple_rest_.size() != region_dimples_.size()) {
    dimple_rest_.resize(region_dimples_.size());
    std::vector<std::vector<int>> regions;
    for (const RegionDimple& r : region_dimples_) regions.push_back(r.order);
    hinge_index_ = HingeIndex(solver_->constraints().dihedral_hinges, faces_, regions);
  }
  set_dimple_rest(*solver_, hinge_index_, rest_x_, faces_, d, d.mirror, dimple_rest_[i]);
}

}  // namespace shellcontract
