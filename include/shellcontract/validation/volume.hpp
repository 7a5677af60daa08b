// Enclosed volume of a closed triangle mesh at given positions (CGAL PMP::volume through an
// EigenPointMap, so that no mesh copy is made; style.md section 3).
#pragma once

#include "shellcontract/core/types.hpp"
#include "shellcontract/mesh/surface_mesh.hpp"

namespace shellcontract {

/// Signed volume enclosed by the mesh when its vertices are at x.
/// PMP::volume only asserts closedness (and the assertion vanishes in release builds), so this
/// wrapper checks the preconditions itself.
/// @param mesh  triangle mesh, connectivity only is used (its own points are ignored)
/// @param x     #V by 3 positions, row i = vertex i, any length unit L
/// @pre !mesh.has_garbage(), x.rows() == number of vertices
/// @return the volume in L^3; positive for outward-oriented faces, negative when inside-out
/// @throws InputError "not a triangle mesh" or "not closed" (with the border edge count)
/// @throws std::invalid_argument if x has the wrong number of rows or the mesh has garbage
double enclosed_volume(const Mesh& mesh, const Positions& x);

/// enclosed_volume without the triangle-mesh and closedness checks, for a caller that measures
/// the same mesh again and again (the simulator, every frame): the checks walk every face and
/// halfedge, which costs more than the volume itself (lab/history.md).
/// @pre enclosed_volume succeeded on this mesh (with any positions), and the mesh's
///      connectivity has not changed since
/// @throws std::invalid_argument if x has the wrong number of rows or the mesh has garbage
double enclosed_volume_unchecked(const Mesh& mesh, const Positions& x);

}  // namespace shellcontract
