// External pressure load (math-spec 3). Eigen only (TBB runs the parallel form).
#pragma once

#include <vector>

#include "shellcontract/simulation_options.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// Pressure forces at positions x (math-spec 3). P > 0 with outward normals pushes inward.
/// @param x      #V by 3 current positions
/// @param faces  #F by 3 faces, counter-clockwise from outside
/// @param P      over-pressure (normalized units: force per unit area of the unit-diagonal mesh)
/// @param f      #V by 3 output forces (resized and overwritten)
/// \note In the paper form, a vertex whose summed normal is zero (|sum N| = 0) gets no force.
void pressure_forces(const Positions& x, const Faces& faces, double P, PressureModel model,
                     Positions& f);

/// The faces around each vertex, in increasing face id: faces[start[v], start[v + 1]).
struct VertexFaces {
  std::vector<int> start;
  std::vector<int> faces;
};
/// The faces around each of the vertices 0..num_vertices-1 (ids outside that range are skipped).
VertexFaces vertex_faces(const Faces& faces, Eigen::Index num_vertices);

/// pressure_forces, in parallel over the vertices (in the caller's TBB arena), each vertex
/// summing the terms of its faces in increasing face id, as the face loop of the serial form
/// adds them: the same bits for any thread count and as the serial form. On a 16-core
/// machine the serial form was a noticeable share of the largest meshes' step at 16 threads (a
/// step timer build, not kept; lab/pages/scale.md, "Sixteen cores").
/// @param around  vertex_faces(faces, x.rows())
void pressure_forces(const Positions& x, const Faces& faces, const VertexFaces& around, double P,
                     PressureModel model, Positions& f);

/// Net over-pressure on a shell that encloses isothermal air (Boyle's law,
/// docs/math/air-pressure.md section 1; the load of math-spec 3).
/// The outside pressure is P / (1 - R) and the air's is P R / ((1 - R) v) at volume ratio
/// v = V/V0, so the net pressure is P at the rest volume and vanishes at v = R: the shell slows
/// down and stops near R instead of collapsing until contact. R = 0 is no air: P at any volume.
/// @param P  net over-pressure at the rest volume (the simulator applies the air only for P > 0)
/// @param R  balance volume ratio in [0, 1)
/// @param v  current V/V0; floored at R / 4 so that a shell crushed far below its balance volume
///           (or inverted, with collisions off) gets a bounded outward push, not an infinite one
double air_net_pressure(double P, double R, double v);

}  // namespace shellcontract
