// The local contraction's force (math-spec 9.2 R): an extra pressure on the region faces that
// acts as an internal actuation, with no net force and no net torque on the shell. Eigen only.
#pragma once

#include "shellcontract/core/types.hpp"

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

/// Region pressure P_A at full strength (region shrink 1), normalized units: the bumps of
/// meshes/bumpy_sphere.off cave in (docs/design/anisotropy.md).
inline constexpr double FULL_REGION_PRESSURE = 10.0;

/// The region pressure P_A of a local contraction of strength S in [0, 1]: S * FULL_REGION_PRESSURE,
/// so that the sink grows monotonically with S (tested).
inline double region_pressure(double shrink) { return shrink * FULL_REGION_PRESSURE; }

}  // namespace shellcontract
