// Closed surface from an oriented point set (points with normals), for the paper's kitten, which
// CGAL's data ships only as points (data/points_3/kitten.xyz).
#pragma once

#include <string>

#include "shellcontract/mesh.hpp"

namespace shellcontract {

/// Options of the reconstruction (CGAL's Poisson surface reconstruction; its defaults).
struct ReconstructionOptions {
  double angle = 20.0;     ///< minimum triangle angle of the surface mesher, degrees
  double radius = 30.0;    ///< maximum triangle size, in multiples of the average point spacing
  double distance = 0.375; ///< surface approximation error, in multiples of the point spacing
  int spacing_neighbours = 6;  ///< neighbours for the average spacing estimate
};

/// Reads an oriented point set ("x y z nx ny nz" per line, .xyz / .pwn) and reconstructs a closed
/// surface with CGAL::poisson_surface_reconstruction_delaunay (Kazhdan et al. 2006).
/// A position given on several lines counts once (its first line's normal).
/// The faces come in a canonical order, whatever the allocator did: each face starts at its
/// smallest vertex index (orientation kept) and the faces are sorted by their indices.
/// @throws InputError if the file cannot be read, its points fail checked_points
///         (mesh/point_set_checks.hpp: too few, huge coordinates, a stray point, no volume...),
///         or the reconstruction fails or is not a closed triangle mesh
Mesh reconstruct_from_oriented_points(const std::string& path, const ReconstructionOptions& options = {});

}  // namespace shellcontract
