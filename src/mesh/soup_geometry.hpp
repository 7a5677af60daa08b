// The steps that read_input_mesh (io.cpp) and mesh_from_arrays (from_arrays.cpp) take on a
// triangle soup whose faces have passed their own checks (private to src/mesh): the connectivity
// checks (soup_checks.hpp), its points at a unit bounding-box diagonal, the CGAL mesh with each
// face's corners as the soup lists them, the orientation of its components, its zero-area faces
// and its volume (accept_triangles runs them all). One implementation, so that a file and the
// same arrays from Python are accepted or refused alike, with the same mesh, warnings and report.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "mesh/soup_checks.hpp"
#include "shellcontract/mesh.hpp"

namespace shellcontract {
struct InputReport;  // shellcontract/mesh_io.hpp
}  // namespace shellcontract

namespace shellcontract::soup {

inline Vec3 to_vec(const Point3& p) { return Vec3(p.x(), p.y(), p.z()); }

/// Faces with 2A below this fraction of the squared mean edge length count as zero-area
/// (relative, so that the test does not depend on the mesh's units).
constexpr double ZERO_AREA_RELATIVE = 1e-10;

/// The points moved to the bounding-box centre and divided by the diagonal, as
/// compute_normalization gives the simulator: every geometric test of the readers (fan
/// triangulation, orientation, volume, zero area) runs on them, so that meshes from 1e-150 to
/// 1e150 get the answers they get at unit scale (no overflow or underflow in products of three
/// coordinates).
struct UnitPoints {
  std::vector<Point3> unit;
  double diagonal = 0.0;  ///< of the input; 0 or not finite for a mesh the caller must refuse
  double scale = 1.0;     ///< the diagonal where it is finite and > 0, else 1 (then `unit` is only shifted)
  bool usable() const;
};
UnitPoints unit_points(const std::vector<Point3>& points);

/// The mesh of a checked triangle soup, each face's halfedge set so that vertices_around_face
/// starts at the soup's first corner: a written face then lists its corners exactly as the input
/// did (per-corner data such as UVs stay aligned). Throws std::logic_error (naming `who`) if the
/// conversion dropped a face or lost a face's corner order, which the checks exclude.
Mesh soup_mesh(const std::vector<Point3>& points, const std::vector<Polygon>& tris, const std::string& who);

/// A closed component whose |volume| is below this times the cube of its own bounding-box diagonal
/// encloses nothing: a flat (or collapsed) shell, whose two sides the outside pressure would push
/// through each other. Far below any thin part a simulation could hold (a sheet of relative
/// thickness t has about t), and far above the rounding of the volume's sum.
constexpr double FLAT_COMPONENT_VOLUME = 1e-9;

struct Orientation {
  std::size_t components = 0;
  bool reoriented = false;  ///< a component was flipped (and `mesh` rebuilt)
  /// With `reorient`: the first component that encloses no volume (FLAT_COMPONENT_VOLUME), as
  /// "component C (N faces, starting at face F) ..." for a message, and all its faces; else empty.
  std::string flat;
  std::vector<std::size_t> flat_faces;
};

/// Components (PMP::connected_components, numbered in order of their first face) and their
/// orientation: with `reorient`, a component with negative signed volume (on `unit`) is inside
/// out and gets flipped (swapping corners 1 and 2 keeps corner 0 first), named in `warnings`
/// with its volume in input units (`scale` cubed), and `mesh` is rebuilt from the flipped soup,
/// so that it is the one a correctly oriented input gives, halfedge for halfedge. A component
/// that encloses no volume is not flipped (it has no inside) nor refused here: the first is
/// returned in `flat`, for the reader to refuse after its own checks. Each component
/// is taken as its own shell: a nested inner wall of a hollow solid is flipped outward too
/// (PMP::orient_to_bound_a_volume would orient it inward).
/// A flat component's text ends with stray_vertices_note on its vertices.
/// @param mesh  soup_mesh(points, tris)
/// @param number  as stray_vertices_note's
Orientation orient_components(Mesh& mesh, const std::vector<Point3>& points,
                              std::vector<Polygon>& tris, const std::vector<Point3>& unit,
                              double scale, bool reorient, const std::string& who,
                              std::vector<std::string>& warnings,
                              const std::vector<std::size_t>* number = nullptr);

/// Vertices (at most STRAY_VERTICES_MAX of `ids`) lying so far from the others that those others'
/// bounding box has under STRAY_VERTICES_EXTENT of the whole's diagonal: a scan outlier, or an
/// exporter's vertex left at the origin of a georeferenced mesh. The no-volume tests are relative
/// to the diagonal, which such vertices hold, so a full sphere is refused as flat; the refusal
/// names them with this text ("; vertex 5 at (0, 0, 0) lies 5.0e+06 from the other vertices, whose
/// bounding box has a diagonal of 1.9: ..."), else it is empty.
constexpr std::size_t STRAY_VERTICES_MAX = 3;
constexpr double STRAY_VERTICES_EXTENT = 0.5;
/// @param number  per vertex of `points`, its number in the input (a welded soup's first copy);
/// none: the same
std::string stray_vertices_note(const std::vector<Point3>& points, std::vector<std::size_t> ids,
                                const std::vector<std::size_t>* number = nullptr);
/// The same over every point of `points` (the whole mesh's no-volume refusals).
std::string stray_vertices_note(const std::vector<Point3>& points,
                                const std::vector<std::size_t>* number = nullptr);

/// Faces with (nearly) zero area on `unit`, ascending: 2A below ZERO_AREA_RELATIVE times the
/// squared mean edge length. Reported, not refused (the rest state gives them no membrane
/// energy).
std::vector<std::size_t> zero_area_faces(const std::vector<Polygon>& tris, const std::vector<Point3>& unit);

/// What accept_triangles takes from its caller besides the soup.
struct AcceptOptions {
  std::string who;  ///< the caller, named by the logic errors of soup_mesh and orient_components
  /// mesh_from_arrays' `reorient`: false keeps every component's winding and refuses no volume.
  bool reorient = true;
  bool gltf = false;  ///< the input is a glTF (weld_note)
  /// The reader's warning for the polygons it split into triangles (empty: none split), after
  /// the orientation's warnings; InputReport::triangulated_faces.
  std::string split_warning;
  std::size_t triangulated = 0;
};

/// The acceptance rule after each face's own checks (its corners in range and distinct), one
/// implementation for read_input_mesh and mesh_from_arrays, so that a file and the same arrays
/// are accepted or refused alike: the connectivity checks in the order of the problems'
/// importance (duplicate faces, edges, isolated vertices, vertex fans), a soup open only along
/// split seams welded instead (seam_weld.hpp); a usable bounding box; the mesh, its orientation
/// and zero-area faces; a positive volume and no flat component. Fills `report` (not its reading
/// times).
/// @param points  the soup's points, replaced by the welded ones when it is welded
/// @param tris  its triangles, replaced by the welded ones (and reoriented)
/// @param normalized  unit_points(points), replaced after a weld
/// @param name  names faces and vertices in the refusals; its `points` is `points`
/// @throws InputError (FaceListError for problems of faces) naming `path` and the problem
Mesh accept_triangles(const std::string& path, std::vector<Point3>& points,
                      std::vector<Polygon>& tris, UnitPoints& normalized, const Namer& name,
                      const AcceptOptions& options, InputReport* report);

}  // namespace shellcontract::soup
