// Every property-map name of the project, with CGAL's prefix convention (v:, e:, h:, f:), and
// the one helper that attaches a map (house-style.md section 3).
#pragma once

#include <string>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh.hpp"

namespace shellcontract::property {

inline constexpr const char* INV_MASS = "v:inv_mass";               ///< double, 1/m_i
inline constexpr const char* MEAN_CURVATURE = "v:mean_curvature";   ///< double
inline constexpr const char* GAUSSIAN_CURVATURE = "v:gaussian_curvature";  ///< double
inline constexpr const char* TRIANGLE_REST = "f:triangle_rest";     ///< TriangleRest (Dm^-1, area)
inline constexpr const char* FIBER_DIR = "f:fiber_dir";             ///< Vec2, rest frame
inline constexpr const char* REGION = "f:region";                   ///< int, -1 = none
inline constexpr const char* ISOMETRIC_BENDING = "e:isometric_bending";  ///< IsometricBendingRest
inline constexpr const char* DIHEDRAL_BENDING = "e:dihedral_bending";    ///< DihedralBendingRest
inline constexpr const char* HINGE = "e:hinge";                     ///< HingeVertices stencil
/// std::array<std::size_t, 3>: a welded input's face corners as the input numbered them
/// (src/mesh/seam_weld.hpp); absent on a mesh whose input was closed as given.
inline constexpr const char* INPUT_CORNERS = "f:input_corners";
/// Output only (write_ply_atomic): CGAL's PLY writer turns these exact names, of type
/// CGAL::IO::Color, into red, green, blue, alpha columns.
inline constexpr const char* VERTEX_COLOR = "v:color";
inline constexpr const char* FACE_COLOR = "f:color";  ///< see VERTEX_COLOR
/// Output only (write_fields_ply): per-vertex fields of sim/fields.hpp.
inline constexpr const char* PRESSURE_LOAD = "v:pressure";
inline constexpr const char* ENERGY_DENSITY = "v:energy_density";  ///< see PRESSURE_LOAD

/// Adds a new property map named `name` to the mesh. CGAL 5.5 returns (map, created); a map of
/// that name that already exists would be stale rest data, so that is an error here.
/// (A newer CGAL returns an optional-like object: only this function changes then.)
template <class Key, class T>
typename Mesh::template Property_map<Key, T> add_map(Mesh& mesh, const std::string& name,
                                                     const T& default_value = T()) {
  auto [map, created] = mesh.template add_property_map<Key, T>(name, default_value);
  if (!created) throw UsageError("property map '" + name + "' is already attached to the mesh");
  return map;
}

/// Looks up an existing property map. @throws UsageError if it is missing.
template <class Key, class T>
typename Mesh::template Property_map<Key, T> get_map(const Mesh& mesh, const std::string& name) {
  auto [map, found] = mesh.template property_map<Key, T>(name);
  if (!found) throw UsageError("property map '" + name + "' is missing (rest state not built?)");
  return map;
}

}  // namespace shellcontract::property
