// Welding the vertices that a UV seam split (private to src/mesh; docs/design/attributes.md,
// "Seams"). Exporters of textured meshes (Blender's PLY exporter, its glTF importer) give every
// vertex one copy per texture coordinate it has, at the same position: the triangles as given
// then meet along the seams without sharing vertices, and the mesh reads as open. read_input_mesh
// and mesh_from_arrays call weld_seams when the soup as given fails their connectivity checks:
// if it is open and welding the copies that sit at bitwise-identical positions (nothing else is
// merged, nothing moves) makes it a closed manifold, the mesh is built from the welded soup and
// keeps, in its f:input_corners map, each face's corners as the input numbered them, so that
// every output can give the input's vertices back (input_positions, input_faces: mesh_io.hpp).
// A mesh that passes the checks as given is never welded.
//
// Why not CGAL's PMP::merge_duplicate_points_in_polygon_soup: it merges points that the kernel's
// Less_xyz_3 finds equal (0.0 and -0.0 too, which are not the same bits), returns only how many
// it removed, and renumbers the points, so the copies and their order are lost; stitch_borders
// works on a mesh and removes vertices (garbage, then renumbering) likewise. Which copies belong
// together is what the outputs need, so the grouping is done here; CGAL still validates the soup
// as given (PMP::is_polygon_soup_a_polygon_mesh: an open surface the outputs can rebuild).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "mesh/soup_checks.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh.hpp"

namespace shellcontract::soup {

/// A soup with its copies welded: welded vertex j is the j-th distinct position in the order of
/// its first copy, so a soup without copies keeps its numbering.
struct SeamWeld {
  std::vector<std::size_t> welded_of;  ///< per input vertex: the welded vertex it became
  std::vector<Point3> points;          ///< the welded vertices' positions
  std::vector<Polygon> tris;           ///< the triangles on welded vertices, same order and corners
  std::size_t copies() const { return welded_of.size() - points.size(); }
};

/// Groups the vertices at bitwise-identical positions (all three coordinates the same bits).
SeamWeld weld_identical_positions(const std::vector<Point3>& points, const std::vector<Polygon>& tris);

/// Per vertex of x, the first vertex at a bitwise-identical position (itself when it has no
/// copy): how the outputs give a seam's copies, which the simulation moved together, one normal.
std::vector<std::size_t> first_at_same_position(const Positions& x);

/// Whether some edge of the triangles belongs to one triangle only (an open boundary).
bool has_boundary_edge(const std::vector<Polygon>& tris, std::size_t nv);

/// The soup (triangles on `points`, indices in range, no repeated corner) of the file `path`
/// failed a connectivity check with `refusal`. Returns the weld when the soup as given is open,
/// some of its vertices share their position, and the welded soup passes every connectivity check
/// (no duplicate face, closed, manifold, oriented, no isolated vertex, one fan per vertex) while
/// the soup as given is a polygon mesh with boundary (CGAL's test; the outputs rebuild it).
/// Otherwise throws: `refusal` when no vertices share a position; else an error that names the
/// refusal's problem and then what is left after welding, named as `name` names the soup's
/// faces and vertices (a welded vertex by its first copy), with the faces left after welding
/// (a FaceListError) and not the refusal's.
SeamWeld weld_seams(const std::string& path, const std::vector<Point3>& points,
                    const std::vector<Polygon>& tris, const InputError& refusal, const Namer& name);

/// The note read_input_mesh and mesh_from_arrays report for a welded input (InputReport::notes).
/// @param gltf the input is a glTF, whose vertices are counted as gltf_reader.hpp reads them
std::string weld_note(const SeamWeld& weld, bool gltf = false);

/// The mesh's f:input_corners map: per face, its corners as the input numbered them, in the
/// order vertices_around_face lists the face's corners from its halfedge.
/// @param mesh       the mesh of the welded soup (face f is weld.tris[f], maybe reoriented)
/// @param input_tris the soup's triangles on input vertices, as weld_seams got them
/// @throws std::logic_error if a face of the mesh is not its welded triangle
void store_input_corners(Mesh& mesh, const SeamWeld& weld, const std::vector<Polygon>& input_tris);

}  // namespace shellcontract::soup
