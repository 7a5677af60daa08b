// The files a mesh file reads or names besides itself (docs/design/output-safety.md, "Files the
// input needs"): an OBJ's material libraries and the images they name, a PLY's texture files, a
// glTF's external buffers and images. No output may be one of them (output_check.cpp): a log
// written over an OBJ's .mtl destroys the user's materials, and a summary over a .gltf's buffer
// leaves the .gltf unreadable, though neither file is the input itself.
#pragma once

#include <string>
#include <vector>

namespace shellcontract {

/// One file the input needs, whether or not it exists.
struct InputDependency {
  std::string path;  ///< as the process finds it: the reader's resolution of the name
  /// What it is to the input, for messages: "the material library that 'c.obj' reads (mtllib,
  /// line 1)".
  std::string role;
};

/// The files that the mesh file `path` reads or names, by its extension, resolved as its readers
/// resolve them (obj_material_paths.hpp, ply_textures.hpp, gltf::load_model, mtl_texture_files):
/// - .obj: each mtllib name (one that names no file too), and the images of each library that
///   can be read (every texture key, not only the map_Kd that the glTF export uses); a library
///   named again (by any spelling of the same file: file_key.hpp) is listed and read once, at
///   its first mtllib line;
/// - .ply: each `comment TextureFile` path;
/// - .gltf, .glb: every path where an external buffer was looked for (the file's folder, then the
///   current one) and each external image URI, percent-decoded, from the file's folder.
/// A file named but missing is listed: an output that created it would change what the input
/// means. Nothing for other formats. Never throws for the files' contents: a file the reader will
/// refuse gives what could be made out before the problem (the command ends at its read, before
/// writing anything).
std::vector<InputDependency> input_dependencies(const std::string& path);

/// A URI reference's path with its %XX escapes decoded, as a viewer finds the file ("a%20b.png"
/// is "a b.png"); other characters as they are.
std::string percent_decoded(const std::string& uri);

}  // namespace shellcontract
