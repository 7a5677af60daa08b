// Reading, checking and writing meshes (design.md, data flow: read -> check input).
#pragma once

#include <cstddef>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "shellcontract/core/types.hpp"
#include "shellcontract/mesh/surface_mesh.hpp"

namespace shellcontract {

/// What the input check found and did. Warnings are for the user (printed on stderr by the CLI).
struct InputReport {
  std::size_t vertices = 0;
  std::size_t faces = 0;            ///< after triangulation
  std::size_t triangulated_faces = 0;  ///< input polygons with more than 3 vertices that were split
  std::vector<std::size_t> zero_area_faces;  ///< face indices (output order) with ~zero area
  bool reoriented = false;          ///< the mesh was inside-out and its faces were flipped
  std::size_t components = 0;       ///< connected components
  double volume = 0.0;              ///< enclosed volume after reorientation (input units; inf beyond ~1e102 per coordinate)
  std::vector<std::string> warnings;
  double read_seconds = 0.0;   ///< read_input_mesh: reading the file into a polygon soup
  double check_seconds = 0.0;  ///< read_input_mesh: checking it and building the mesh
};

/// Reads OFF/OBJ/PLY/STL (by extension; read_polygon_soup) and checks that the mesh is a
/// closed, manifold triangle mesh with finite coordinates, a nonzero finite bounding-box diagonal
/// and a positive enclosed volume (measured as the simulator measures it): the one decision of
/// what `check`, `run` and `regions` can use. Polygons are triangulated (with a warning); an
/// inside-out mesh is reoriented (with a warning); zero-area faces are reported. Geometric tests
/// run on coordinates normalized to a unit bounding-box diagonal, so any scale from 1e-150 to
/// 1e150 gives the same answers.
/// @throws InputError naming the file and the problem (and the face, vertex or line where known),
///         for any file whatever its bytes (also when memory runs out while reading it)
Mesh read_input_mesh(const std::string& path, InputReport* report = nullptr);

/// read_input_mesh's checks on a polygon soup already in memory (points in input units): the
/// same decision, for a mesh built by the program (repair_input_mesh). Messages start with `name`.
/// @throws InputError as read_input_mesh
Mesh check_input_soup(const std::string& name, std::vector<Point3> points,
                      const std::vector<std::vector<std::size_t>>& polygons, InputReport* report = nullptr);

/// Writes the mesh connectivity with the vertex positions x (row i = vertex i, input units),
/// keeping vertex and face order and each face's first corner, with CGAL's writer for the
/// extension (OFF, OBJ, STL ASCII; PLY through write_ply_atomic) at 17 significant digits, so
/// that the doubles read back bitwise. Written to a temporary file in the same folder, then
/// renamed, so a failure never leaves a partial file.
/// @throws UsageError if the file cannot be written or the extension is unknown
/// @throws std::invalid_argument if x.rows() != number of vertices or the mesh has garbage
void write_mesh_atomic(const std::string& path, const Mesh& mesh, const Positions& x);

/// The mesh to give write_ply_atomic: a copy of `mesh` (vertex and face order and each face's
/// first corner kept) with its points set to x and no property maps, to which the caller
/// attaches the properties to write.
/// @param x #V by 3 positions, row i = vertex i
/// @throws std::invalid_argument if x.rows() != number of vertices or the mesh has garbage
Mesh mesh_for_output(const Mesh& mesh, const Positions& x);

/// The one PLY writer (plain meshes, regions, fields): CGAL's Surface_mesh PLY writer, ASCII, 17
/// significant digits, atomically (temporary file + rename). Every vertex and face property map
/// of `mesh` with a simple type (int8..int64, float, double) is written as a property of its
/// element, named without the "v:"/"f:" prefix, in the order the maps were attached;
/// "v:color" / "f:color" (CGAL::IO::Color) become red, green, blue, alpha (uchar). Vertex
/// properties follow x, y, z; face properties follow vertex_indices.
/// @param mesh     usually built by mesh_for_output, so that only the maps meant for the file are on it
/// @param comments written as "comment" lines of the header, one per line of the string
/// @throws UsageError if the file cannot be written
void write_ply_atomic(const std::string& path, const Mesh& mesh, const std::string& comments = "");

/// Writes text to path atomically (temporary file + rename). @throws UsageError on failure
void write_text_atomic(const std::string& path, const std::string& text);

/// Writes a file atomically through `write`, which writes straight into a temporary file next to
/// `path` (no copy in memory: for large binary files written in a few large pieces, the .glb);
/// then renames it over `path`. If `write` throws, no file is left and the exception passes.
/// @throws UsageError if the file cannot be created or written
void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace shellcontract
