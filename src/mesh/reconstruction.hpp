// Closed surface from an oriented point set (points with normals), for the paper's kitten, which
// CGAL's data ships only as points (data/points_3/kitten.xyz).
#pragma once

#include <string>

#include "shellcontract/mesh.hpp"

namespace shellcontract {

/// Options of the reconstruction (CGAL's Poisson surface reconstruction; its defaults).
/// The ranges (check_reconstruction_options) are those in which CGAL's surface mesher ends.
struct ReconstructionOptions {
  double angle = 20.0;     ///< minimum triangle angle of the surface mesher, degrees, in [0, 30]
  double radius = 30.0;    ///< maximum triangle size, x the average point spacing, in [0.5, 1e6]
  double distance = 0.375; ///< surface approximation error, x the point spacing, in [0.1, 1e6]
  int spacing_neighbours = 6;  ///< neighbours for the average spacing estimate, >= 1
};

/// The smallest and largest values of the options (reconstruction.cpp says why).
inline constexpr double RECONSTRUCTION_MAX_ANGLE = 30.0;
inline constexpr double RECONSTRUCTION_MIN_RADIUS = 0.5;
inline constexpr double RECONSTRUCTION_MIN_DISTANCE = 0.1;
inline constexpr double RECONSTRUCTION_MAX_SPACINGS = 1e6;

/// Checks that every option is in its range, so that the surface mesher ends.
/// @param prefix  put before each option's name in the message ("--" for the command line)
/// @throws UsageError naming the first option out of range, its value and the range
void check_reconstruction_options(const ReconstructionOptions& options, const std::string& prefix = "");

/// Reads an oriented point set ("x y z nx ny nz" per line, .xyz / .pwn) and reconstructs a closed
/// surface with CGAL::poisson_surface_reconstruction_delaunay (Kazhdan et al. 2006).
/// A position given on several lines counts once (its first line's normal); at least 10 positions.
/// The faces come in a canonical order, whatever the allocator did: each face starts at its
/// smallest vertex index (orientation kept) and the faces are sorted by their indices.
/// @throws UsageError if an option is out of range (check_reconstruction_options), before reading
/// @throws InputError if the file cannot be read, its points fail checked_points
///         (mesh/point_set_checks.hpp: too few, huge coordinates, a stray point, no volume...),
///         or the reconstruction fails or is not a closed triangle mesh, or the surface does not fit
///         the points (check_surface_fits_points: it misses points, as of a separate object, or
///         many normals point into it)
Mesh reconstruct_from_oriented_points(const std::string& path, const ReconstructionOptions& options = {});

}  // namespace shellcontract
