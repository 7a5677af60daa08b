// Reading a mesh file into a polygon soup, before any check (read_input_mesh's first step).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "mesh/formats.hpp"
#include "mesh/off_scan.hpp"
#include "shellcontract/mesh.hpp"

namespace shellcontract {

/// The whole file's bytes. @throws InputError naming the file if it is missing, a folder or unreadable
std::string read_file_bytes(const std::string& path);

/// The row of MESH_FORMATS of `ext` (lower_extension(path)). A file that is not one is refused
/// as read_input_mesh refuses it: for what the path is when it is no regular file, else for its
/// extension (none, or one not in the table), with the table's list.
/// @throws InputError "<path>: unknown extension: '.EXT' (expected .off, ...)"
const MeshFormat& require_mesh_extension(const std::string& path, const std::string& ext);

/// Reads the points and polygons of an OFF, OBJ, PLY, STL or glTF (.glb, .gltf) file in file
/// order, with the line of each vertex and face where the format and reader know it (OBJ, ascii
/// OFF and PLY). OFF is read by scan_off (ascii and binary), OBJ by scan_obj, PLY by read_ply, STL
/// by CGAL (a file it refuses by diagnose_stl, for the message's line or byte), glTF by read_gltf
/// (world positions, seam copies left split); OFF and OBJ may start with a UTF-8 byte-order mark
/// and use "\r" line ends. Nothing is allocated from a declared count that the
/// file's size does not bound.
/// @param ext lower-case extension without the dot, a row of MESH_FORMATS (else refused as by
///        require_mesh_extension, before the file is read)
/// @param warnings  if given, gets what was read past (an OFF's lines after its declared faces)
/// @param missing  MissingVertices::Keep (repair's read): an OFF's or OBJ's face that names a
///        vertex the file lacks is read with that index, not refused. A PLY's indices are never
///        checked here (check_input_soup does); a glTF's are always (its accessor is corrupt).
/// @param notes  if given, gets what the reader read but did not apply (a glTF's morph targets)
/// @throws InputError "<path>: <problem>: <where>" if the file cannot be read as such
void read_polygon_soup(const std::string& path, const std::string& ext, std::vector<Point3>& points,
                       std::vector<std::vector<std::size_t>>& polygons, SourceLines& lines,
                       std::vector<std::string>* warnings = nullptr,
                       MissingVertices missing = MissingVertices::Refuse,
                       std::vector<std::string>* notes = nullptr);

}  // namespace shellcontract
