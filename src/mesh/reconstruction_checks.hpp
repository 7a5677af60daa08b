// Checks of a Poisson reconstruction against the oriented points it came from: CGAL's surface
// mesher starts from one inner point and meshes the part of the implicit surface around it, so
// separate objects came out as one of them, and inconsistently oriented normals as a garbage
// surface, both with no error.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "mesh/point_set_checks.hpp"
#include "shellcontract/mesh.hpp"

namespace shellcontract {

/// Refuses a reconstructed surface (closed, outward oriented) that does not fit its points.
/// `points` are the points the solve used, `kept` their indices in `input.points` (for the lines
/// named), `spacing` their average spacing, `distance` the mesher's approximation error in
/// spacings (ReconstructionOptions::distance).
/// @throws InputError naming input.path if the surface misses more points than a scan's outliers
///         explain (how many, the farthest one's line; separate objects or bad normals?), or if a
///         substantial share of the normals point into it (the normals are not consistently
///         oriented, with one example line)
void check_surface_fits_points(const OrientedPoints& input, const std::vector<std::size_t>& kept,
                               const std::vector<PointWithNormal>& points, const Mesh& surface,
                               double spacing, double distance);

/// For a failed reconstruction: ": N of M points' normals point against most of their nearest
/// neighbours' ... not consistently oriented" when more than `share` of them do (by default a
/// substantial share), "" otherwise.
std::string inconsistent_normals_hint(const OrientedPoints& input,
                                      const std::vector<std::size_t>& kept,
                                      const std::vector<PointWithNormal>& points, int neighbours,
                                      double share = -1.0);

/// The share of points against most of their neighbours above which no reconstruction is tried:
/// a consistently oriented scan has almost none, half the normals flipped at random about a
/// third (a point with as many neighbours each way counts for neither), a thin
/// part whose two sides' points are each other's neighbours some; inconsistent_normals_hint's
/// default share, below this, only explains a failed or refused reconstruction.
constexpr double REFUSED_AGAINST_NEIGHBOURS_SHARE = 0.3;

}  // namespace shellcontract
