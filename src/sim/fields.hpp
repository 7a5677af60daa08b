// Per-vertex fields a user wants to look at (paper Figs. 2, 8, 10): curvature, pressure load and
// elastic energy density, written as a PLY with scalar properties and colours.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "sim/simulator.hpp"

namespace shellcontract {

/// Per-vertex fields at the simulator's current positions (normalized units).
struct VertexFields {
  Eigen::VectorXd mean_curvature;      ///< H, 1/length (> 0 convex), geometry/curvature.hpp
  Eigen::VectorXd gaussian_curvature;  ///< K, 1/length^2
  Eigen::VectorXd pressure;            ///< |f_i| / (one-ring area / 3): pressure load per area
  Eigen::VectorXd energy_density;      ///< elastic (membrane + anisotropic) energy of the one
                                       ///< ring / its rest area, energy per area
};

/// Which field gives the PLY's colours.
enum class FieldColour { MeanCurvature, GaussianCurvature, Pressure, EnergyDensity };

/// Computes the fields of the current state.
VertexFields compute_vertex_fields(const Simulator& sim);

/// Colour map of the fields PLY: the field's values are mapped linearly from its 2nd to its 98th
/// percentile (clamped outside) onto blue (0, 0, 255) -> white (255, 255, 255) -> red
/// (255, 0, 0). Returns r, g, b in 0..255 for t in [0, 1].
Eigen::Vector3i field_colour(double t);

/// The value at fraction q in [0, 1] of the sorted values (nearest rank; 0 for no values): the
/// 2nd and 98th percentiles that the field colours span.
double field_percentile(std::vector<double> values, double q);

/// A fields PLY ready to be written: the mesh at positions x (input units) with per-vertex colour
/// (from `colour`) and the float properties mean_curvature, gaussian_curvature, pressure and
/// energy_density (normalized units), and its header comment. A mesh welded along its seams has
/// its input's vertices, each copy with its vertex's values. Kept apart from the writing so that
/// a run can hold its start fields until it has finished (an interrupted run writes no fields).
struct FieldsPly {
  Mesh mesh;
  std::string comment;
};
FieldsPly fields_ply(const Simulator& sim, const Positions& x, const VertexFields& fields,
                     FieldColour colour);

/// Writes `ply` as ASCII PLY, atomically (temporary file + rename).
/// @throws UsageError if the file cannot be written
void write_fields_ply(const std::string& path, const FieldsPly& ply);

/// fields_ply, then write_fields_ply.
/// @throws UsageError if the file cannot be written
void write_fields_ply(const std::string& path, const Simulator& sim, const Positions& x,
                      const VertexFields& fields, FieldColour colour);

}  // namespace shellcontract
