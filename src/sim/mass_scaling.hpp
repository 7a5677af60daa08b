// Mass scaling for the explicit pressure load (docs/design/defaults.md, "Mass scaling").
// The pressure force is integrated explicitly, while the PBD membrane resists a displacement
// with an effective stiffness of about m_i / dt^2 per vertex. Where the lumped mass is tiny next
// to the pressure's stiffness around a vertex (finely meshed detail, slivers), the pressure
// wins: the repaired mannequin-devil.off of CGAL's demo data blew up at step 16 of a default run
// (lab/scripts/corpus_run.py), and at dt / 4 it did not. Raising those masses removes that
// without touching the time step of the whole mesh. "Too light" is relative to P dt^2, not to
// the other vertices: on a mesh as fine as the paper's bear it is about half of them.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>

#include "shellcontract/types.hpp"

namespace shellcontract {

/// The largest omega * dt that the mass scaling leaves to a vertex, where omega^2 = K_i / m_i and
/// K_i = |P| / 3 * (perimeter of the vertex's one-ring) bounds the stiffness of the pressure
/// force f_i = -P / 6 sum_j N_j with respect to the ring's vertices. Calibrated on the repaired
/// mannequin-devil.off (lab/scripts/corpus_run.py; collisions off, default options otherwise): with
/// no scaling it blew up at step 9, with a bound of 0.7 at step 17, 0.4 at step 51, and with
/// 0.25 it ran (docs/design/defaults.md, "Mass scaling").
inline constexpr double MAX_PRESSURE_OMEGA_DT = 0.25;

/// What scale_masses_for_pressure did.
struct MassScaling {
  std::size_t raised = 0;       ///< vertices whose mass was raised
  double largest_factor = 1.0;  ///< the largest raised mass over its mass before (1: none raised)
  /// The largest time step at which no vertex would be raised at this pressure: the masses then
  /// are the lumped ones (+infinity at P = 0 or with no vertex below the mean mass).
  double largest_unscaled_dt = 0.0;
};

/// Raises the mass of every vertex whose omega * dt (see MAX_PRESSURE_OMEGA_DT) exceeds the
/// bound to the mass that meets it, m_i = K_i (dt / MAX_PRESSURE_OMEGA_DT)^2, but never above the
/// mean vertex mass: the scaling evens out light vertices, and a pressure or time step too large
/// for the whole mesh still blows up and is reported. The other masses, and every mass when
/// P = 0, are unchanged. The required mass grows with P dt^2 and shrinks with the one-ring's
/// size, so on a finely meshed shell it is above the lumped mass of most vertices lighter than
/// the mean (about half of bear's and elk's at the defaults; docs/design/defaults.md), and which
/// vertices are raised depends on dt.
/// @param x         #V by 3 rest positions (normalized)
/// @param faces     #F by 3 vertex indices
/// @param pressure  the run's pressure P (its magnitude is used)
/// @param dt        the time step the masses are for
/// @param inv_mass  #V inverse masses, changed in place (a zero, pinned, stays zero)
MassScaling scale_masses_for_pressure(const Positions& x, const Faces& faces, double pressure,
                                      double dt, Eigen::VectorXd& inv_mass);

/// A run reports its mass scaling (a warning) when it raised more than this share of the vertices:
/// then the masses, and so the motion, are not the area-lumped ones of docs/math/spec.md 1.4.
inline constexpr double MASS_SCALING_NOTE_SHARE = 0.05;

/// What a run says of its mass scaling `m` when it raised more than MASS_SCALING_NOTE_SHARE of
/// the `vertices`: the masses are then not the lumped ones the docs describe, and they, and so
/// the motion, change with the step `dt`. Empty below that share (options named as `field`).
std::string mass_scaling_warning(const MassScaling& m, std::size_t vertices, double dt);

}  // namespace shellcontract
