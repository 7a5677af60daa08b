// Per-vertex fields a user wants to look at (paper Figs. 2, 8, 10): curvature, pressure load and
// elastic energy density, written as a PLY with scalar properties and colours.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "sim/simulator.hpp"

namespace shellcontract {

/// Per-vertex fields at the simulator's current positions. The curvatures are in the input's
/// units (the fields PLY's positions are); the pressure and the energy density stay in the
/// normalized units the run's options are given in (-p, the material): the tool has no force
/// unit for the file's lengths, and so they compare with -p and the log's energies.
struct VertexFields {
  /// H, 1/length in the input's units (> 0 convex), geometry/curvature.hpp
  Eigen::VectorXd mean_curvature;
  Eigen::VectorXd gaussian_curvature;  ///< K, 1/length^2 in the input's units
  /// The net pressure acting on the state (Simulator::net_pressure: keyed -p with the air, not
  /// the region load): -f_i . n_i / (one-ring area / 3) with f_i the pressure force and n_i the
  /// unit area-weighted normal; > 0 pushes inward. Normalized units.
  Eigen::VectorXd pressure;
  /// Membrane + anisotropic energy (not bending) of the one ring / its rest area, energy per
  /// normalized rest area: sum_i energy_density_i * rest ring area_i / 3 is the log's
  /// energy_membrane + energy_anisotropic.
  Eigen::VectorXd energy_density;
};

/// Which field gives the PLY's colours.
enum class FieldColour { MeanCurvature, GaussianCurvature, Pressure, EnergyDensity };

/// Computes the fields of the current state.
VertexFields compute_vertex_fields(const Simulator& sim);

/// The mean curvature at normalized positions x of sim's mesh, in the input's units (as
/// compute_vertex_fields): the glTF's per-frame field.
Eigen::VectorXd input_unit_mean_curvature(const Simulator& sim, const Positions& x);

/// Colour map of the fields PLY: the field's values are mapped linearly from its 2nd to its 98th
/// percentile (clamped outside) onto blue (0, 0, 255) -> white (255, 255, 255) -> red
/// (255, 0, 0). Returns r, g, b in 0..255 for t in [0, 1].
Eigen::Vector3i field_colour(double t);

/// The value at fraction q in [0, 1] of the sorted values (nearest rank; 0 for no values): the
/// 2nd and 98th percentiles that the field colours span.
double field_percentile(std::vector<double> values, double q);

/// A fields PLY ready to be written: the mesh at positions x (input units) with per-vertex colour
/// (from `colour`) and the float properties mean_curvature, gaussian_curvature, pressure and
/// energy_density (units as VertexFields), and its header comment. A mesh welded along its seams
/// has its input's vertices, each copy with its vertex's values. Kept apart from the writing so
/// that a run can hold its start fields until it has finished (an interrupted run writes no
/// fields).
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
