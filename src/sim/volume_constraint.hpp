// The global volume constraint of a target-volume run (docs/math/volume-control.md): one scalar
// constraint C(x) = V(x) - V_t projected like any PBD constraint, with the vertices' inverse
// masses. Eigen only.
#pragma once

#include <limits>

#include "shellcontract/types.hpp"

namespace shellcontract {

/// Signed volume enclosed by a closed, outward-oriented triangle mesh: sum over faces of
/// x_a . (x_b x x_c) / 6 (divergence theorem; the same value as CGAL PMP::volume up to rounding).
double signed_volume(const Positions& x, const Faces& faces);

/// dV/dx_i = (1/6) sum over the faces (a, b, c) around vertex i of the cross product of the other
/// two corners in order (for i = a: x_b x x_c). g is resized to #V by 3.
void volume_gradient(const Positions& x, const Faces& faces, Positions& g);

/// Moves x onto V(x) = target: Newton steps dx_i = -w_i lambda dV/dx_i with
/// lambda = (V - target) / sum_i w_i |dV/dx_i|^2, until |V - target| <= tolerance or
/// max_steps steps (V is cubic in x, so a few steps reach rounding level).
/// @param w  inverse masses (#V); a vertex with w = 0 does not move
/// @param max_move  the farthest a vertex may move in this call: a step that would move one
///                  farther is scaled down to it and ends the call, short of the target. When the
///                  contacts hold most vertices, the few free ones take the whole correction, and
///                  a target the shell cannot reach without passing through itself sent them
///                  beyond the mesh in one step (a blow-up); capped, the run ends short of it.
/// @param smooth_moves  if > 0, the cap is at least this many times |V - target| / A (A the
///                  surface area): the move that a smooth shell of that area needs for that
///                  volume. The caller gives it when no contact holds a vertex: the cap is for the
///                  few free vertices of a held shell, and it held a free shell asked to change
///                  fast (a short ramp) short of pulling back the momentum that carried it past
///                  its target. A crumpled shell, whose gradient is far weaker than a smooth
///                  one's, stays capped by the smaller bound.
/// @return the steps taken; x is unchanged when the constraint has no gradient (all w = 0)
int project_volume(Positions& x, const Faces& faces, const Eigen::VectorXd& w, double target,
                   double tolerance, int max_steps = 4,
                   double max_move = std::numeric_limits<double>::infinity(),
                   double smooth_moves = 0.0);

/// Surface area of a triangle mesh: the sum of its faces' areas.
double surface_area(const Positions& x, const Faces& faces);

/// The target volume of frame n of a ramp from V0 to R V0 over `ramp` frames, with the smoothstep
/// s(t) = 3t^2 - 2t^3 (zero rate at both ends, so the shell starts and stops gently):
/// V_t(n) = V0 (1 - (1 - R) s(min(n / ramp, 1))).
double target_volume_at(int n, int ramp, double v0, double ratio);

}  // namespace shellcontract
