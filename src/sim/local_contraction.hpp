// The local contraction's force (math-spec 9.2 R): an extra pressure on the region faces that
// acts as an internal actuation, with no net force and no net torque on the shell. Eigen only.
#pragma once

#include "shellcontract/types.hpp"

namespace shellcontract {

/// Removes the rigid-body part of a force field: afterwards sum_i f_i = 0 and
/// sum_i (x_i - c) x f_i = 0 about the centre of mass c, while a field that already has neither
/// is unchanged. The removed part is m_i (a + omega x (x_i - c)), the force that would give the
/// shell (mass m_i per vertex) the same rigid acceleration as f.
/// @param x         #V by 3 positions
/// @param inv_mass  #V inverse masses; a vertex with inverse mass 0 (pinned) takes no share
/// @param f         #V by 3 forces, changed in place
/// \note When the shell's inertia tensor is singular (all massive vertices on one line) only
///       the net force is removed.
void remove_rigid_body_force(const Positions& x, const Eigen::VectorXd& inv_mass, Positions& f);

/// The local contraction's force: the energy-consistent pressure P_A on the region faces,
/// f_i = -(P_A / 6) sum_{region faces j around i} N_j, without its rigid-body part
/// (remove_rigid_body_force). An open patch of faces has a net area vector, so the bare pressure
/// would push the whole shell sideways and spin it; a region that sinks in by its own actuation
/// (a muscle, a drying skin) moves nothing else but through the shell's elasticity.
/// @param x             #V by 3 positions
/// @param region_faces  #F_A by 3 faces of the regions, counter-clockwise from outside
/// @param P_A           region pressure (normalized units); > 0 sinks the regions in
/// @param inv_mass      #V inverse masses
/// @param f             #V by 3 output forces (resized and overwritten)
void local_contraction_forces(const Positions& x, const Faces& region_faces, double P_A,
                              const Eigen::VectorXd& inv_mass, Positions& f);

/// local_contraction_forces with a weight per region face (sim/region_weights.hpp): face j
/// pushes with P_A * weight(j), f_i = -(1 / 6) sum_j P_A weight(j) N_j, then the rigid-body part
/// is removed.
/// @param weight  #F_A weights in [0, 1], one per row of region_faces
void local_contraction_forces(const Positions& x, const Faces& region_faces, double P_A,
                              const Eigen::VectorXd& weight, const Eigen::VectorXd& inv_mass,
                              Positions& f);

/// Region pressure P_A at full strength (region shrink 1), normalized units: the bumps of
/// meshes/bumpy_sphere.off cave in (docs/design/anisotropy.md).
inline constexpr double FULL_REGION_PRESSURE = 10.0;

/// The region pressure P_A of a local contraction of strength S in [0, 1]: S * FULL_REGION_PRESSURE,
/// so that the sink grows monotonically with S (tested).
inline double region_pressure(double shrink) { return shrink * FULL_REGION_PRESSURE; }

/// Gain of the region load: under a global pressure P (-p > 0, no target volume) the default
/// mechanism (InwardTerm::Volume) adds to each region's dimple the pressure
/// REGION_LOAD_GAIN * S * P on the region's faces, so the regions feel (1 + 2 S) times the
/// shell's load. The dimple alone is a shape, no deeper than the region's own mirror image, while
/// the global pressure moves the whole shell by more than that; the load makes the regions sink
/// with the shell's contraction (a load, so they creep on slowly after the shell has stopped).
/// At -p 0 there is no load and the dimple alone keeps the contraction local. Chosen by
/// measurement (docs/math/local-contraction.md, section 5): with it the regions of bumpy_sphere,
/// the hand, bear, the elk and the kitten sink, in the default run, farther than the 2x the
/// local contraction promises, with a margin.
inline constexpr double REGION_LOAD_GAIN = 2.0;

/// The region load of strength S under the global pressure P: REGION_LOAD_GAIN * S * P.
inline double region_load_pressure(double shrink, double pressure) {
  return REGION_LOAD_GAIN * shrink * pressure;
}

}  // namespace shellcontract
