// Distance between two states of one mesh (same connectivity, two position arrays): the error
// measure of the speed-against-error bench (design.md "Speed against error").
#pragma once

#include "shellcontract/core/types.hpp"
#include "shellcontract/mesh/surface_mesh.hpp"

namespace shellcontract {

/// Default absolute error bound of symmetric_hausdorff_distance (units of the positions). The
/// bench works in normalized units (bounding-box diagonal 1), where 1e-7 is far below any error
/// it reports.
inline constexpr double DEFAULT_HAUSDORFF_ERROR_BOUND = 1e-7;

/// Symmetric Hausdorff distance between the surface of `mesh` with vertex positions `a` and the
/// same surface with positions `b`: max(h(A, B), h(B, A)), h(A, B) = max over points p of A of
/// the distance from p to B (whole triangles, not only vertices).
///
/// Computed with CGAL PMP::bounded_error_symmetric_Hausdorff_distance (Sequential_tag), so the
/// result is within `error_bound` of the true distance and deterministic; identical positions
/// give exactly 0 (every face matches).
/// @param mesh  a garbage-free triangle mesh; its own points are not used
/// @param a, b  one row per vertex (row i = vertex i)
/// @param error_bound  absolute bound on the error of the estimate, > 0
/// @throws std::invalid_argument if the row counts do not match the mesh or the bound is not > 0
double symmetric_hausdorff_distance(const Mesh& mesh, const Positions& a, const Positions& b,
                                    double error_bound = DEFAULT_HAUSDORFF_ERROR_BOUND);

/// max_i |a_i - b_i|: the distance with vertex correspondence. An upper bound of the Hausdorff
/// distance; larger when vertices slide along the surface.
/// @throws std::invalid_argument if the row counts differ
double max_vertex_distance(const Positions& a, const Positions& b);

}  // namespace shellcontract
