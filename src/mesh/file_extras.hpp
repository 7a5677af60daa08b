// What a mesh file holds besides its vertex positions and polygons (private to src/mesh): the
// things a writer other than the file's own bytes or document leaves out, named for the user, so
// that `repair` can say precisely what its output does not carry.
#pragma once

#include <string>
#include <vector>

namespace shellcontract {

struct FileExtras {
  /// Binary STL, binary PLY (either byte order) or "OFF BINARY".
  bool binary = false;
  /// One phrase per kind of content, with counts where they help: "154 texture coordinates (vt)",
  /// "2 materials (usemtl north, south) and a material library (mtllib sphere.mtl)",
  /// "vertex properties nx, ny, nz (PLY)", "9 comment lines". Empty when the file holds nothing
  /// besides positions and polygons. The encoding is not among them (see `binary`).
  std::vector<std::string> items;
};

/// The extras of a mesh file's bytes, by the lower-case extension (a row of MESH_FORMATS,
/// formats.hpp; none for another). Meant for a file that read_polygon_soup has read: a part it
/// cannot make out is not described rather than refused.
FileExtras describe_file_extras(const std::string& ext, const std::string& bytes);

/// A glTF's (.glb or .gltf, told by the first bytes; gltf_extras.cpp), from its JSON alone: vertex
/// attributes besides POSITION ("vertex attributes NORMAL, TEXCOORD_0"), morph targets, several
/// primitives (a bare mesh has one), nodes and their transforms, node and mesh names, other
/// scenes, materials, textures, images, animations, skins, cameras, extensions, and the objects
/// that carry application data (extras).
/// `binary` stays false: a .glb is a container, and any output keeps the positions' floats.
FileExtras describe_gltf_extras(const std::string& bytes);

/// The uris of a glTF's buffers and images that are not data URIs (files it reads from its
/// folder, as written), each once; none for JSON it cannot parse.
std::vector<std::string> gltf_file_uris(const std::string& bytes);

}  // namespace shellcontract
