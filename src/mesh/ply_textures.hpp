// The texture files a PLY names in its header, as MeshLab (and the photogrammetry tools that export
// through it) writes them: one `comment TextureFile <path>` line per texture, a face's integer
// `texnumber` property choosing one (docs/design/attributes.md, "Textures of a PLY"). The PLY
// document (ply_document.cpp) reports them as its face materials, for the glTF.
#pragma once

#include <string>
#include <vector>

#include "mesh/obj_material_paths.hpp"
#include "mesh/ply_header.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract::ply {

/// The materials of a PLY's `comment TextureFile` lines, in header order: each one's name is the
/// path as the header writes it (the rest of the line, trimmed: a path may hold spaces), its
/// texture that path as the process finds it (a relative one from the PLY's folder) and the
/// header line; source is the PLY. No face_material (the document sets it per face). Empty names
/// when the header has no such line. The keyword is matched as MeshLab writes it.
/// @param ply_path the PLY file (its folder is where relative paths start; for messages)
FaceMaterials texture_materials(const std::string& ply_path, const std::vector<Comment>& comments);

/// The edits that make the `comment TextureFile` lines of a PLY's header (`bytes`, the file
/// `input_path`) name the same images from the folder of `output_path`, as an OBJ's mtllib lines
/// are rewritten (obj_material_paths.hpp): a relative path becomes the path of the same file
/// from the output's folder; absolute paths stay. A path that is no file from the input's folder
/// stays as written, with a warning "<input>: line <n>: ..." appended to `warnings` (when given).
/// No edits when both files are in one folder, when input_path is empty, or when the header names
/// no texture. The edits lie in the header, which the document writes byte for byte.
std::vector<TextEdit> texture_file_edits(const std::string& bytes, const std::string& input_path,
                                         const std::string& output_path,
                                         std::vector<std::string>* warnings);

}  // namespace shellcontract::ply
