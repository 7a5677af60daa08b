// Repairing a mesh file that read_input_mesh refuses (docs/design/repair.md): CGAL's polygon
// soup repair, orientation, stitching, degenerate removal and hole filling, then the same
// usability check as `check` and `run`.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {

/// What repair changed, counted step by step (docs/design/repair.md). All counts are zero when
/// the input was usable as read (`already_usable`): such a mesh is returned unchanged.
struct RepairReport {
  bool already_usable = false;           ///< read_input_mesh accepted the file: nothing was changed
  std::string input_problem;             ///< why read_input_mesh refused the file ("" if usable)
  std::size_t input_vertices = 0;        ///< points and polygons of the file
  std::size_t input_polygons = 0;
  /// Faces that name a vertex the file lacks (an index out of range), dropped first; `check`
  /// and `run` refuse such a file, repair reads it and drops them.
  std::size_t missing_vertex_faces_dropped = 0;
  /// The first few of them, "face 4, line 15" (the line where the format has lines)
  std::vector<std::string> missing_vertex_faces;
  std::size_t duplicate_points_merged = 0;    ///< points at the same position as an earlier one
  std::size_t soup_polygons_removed = 0;      ///< duplicate and degenerate polygons of the soup (net)
  std::size_t points_duplicated_to_orient = 0;  ///< orient_polygon_soup's splits of non-manifold points
  std::size_t polygons_triangulated = 0;      ///< faces with more than 3 corners split into triangles
  std::size_t border_edges_stitched = 0;      ///< border halfedge pairs that stitch_borders merged
  std::size_t degenerate_faces_removed = 0;   ///< faces removed by remove_degenerate_edges/faces (net)
  std::size_t isolated_vertices_removed = 0;
  std::size_t holes_filled = 0;
  std::size_t hole_faces_added = 0;
  std::size_t hole_vertices_added = 0;        ///< refinement vertices inside the filled holes
  std::size_t largest_hole_edges = 0;         ///< boundary edges of the largest hole filled
  std::size_t holes_not_faired = 0;           ///< filled without fairing (fairing failed)
  std::size_t holes_unfilled = 0;             ///< holes CGAL could not triangulate
  std::size_t hole_self_intersections = 0;    ///< self-intersecting face pairs with a new hole face
  std::size_t components_dropped = 0;         ///< components still open or enclosing no volume
  std::size_t faces_dropped = 0;              ///< faces of those components
  bool usable = false;                        ///< the repaired mesh passed the usability check
  std::string failure;                        ///< why repair could not help ("" if usable)
  InputReport input_report;                   ///< the usability check's report of the result
  /// One line per step that changed something, for the user.
  std::vector<std::string> summary_lines() const;
};

/// Reads `path` and returns a mesh that read_input_mesh's checks accept. A file those checks
/// accept is returned as read (report->already_usable). Otherwise: merge duplicate points,
/// remove duplicate and degenerate polygons (repair_polygon_soup), orient the soup (splitting
/// non-manifold points), build the mesh, triangulate, stitch borders, remove degenerate edges
/// and faces and isolated vertices, fill every hole (triangulate, refine and fair; without
/// fairing where fairing fails), drop components that are still open or enclose no volume,
/// orient each component outward, and run the usability check (check_input_soup) on the result.
/// Geometry runs on coordinates normalized to a unit bounding-box diagonal; the result is in
/// input units, and the input's vertices that it keeps have their input coordinates bit for bit.
/// @param max_hole_edges holes with more boundary edges are left open (so their component is
///        dropped); 0 = no limit
/// @throws InputError "<path>: cannot repair: <why>" when the file cannot be read, or when the
///         repaired mesh is still unusable (the report, if given, is filled in before)
Mesh repair_input_mesh(const std::string& path, RepairReport* report = nullptr,
                       std::size_t max_hole_edges = 0);

}  // namespace shellcontract
