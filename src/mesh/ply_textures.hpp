// The texture files a PLY names in its header, as MeshLab (and the photogrammetry tools that export
// through it) writes them: one `comment TextureFile <path>` line per texture, a face's integer
// `texnumber` property choosing one (docs/design/attributes.md, "Textures of a PLY"). The PLY
// document (ply_document.cpp) reports them as its face materials, for the glTF.
#pragma once

#include <string>
#include <vector>

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

}  // namespace shellcontract::ply
