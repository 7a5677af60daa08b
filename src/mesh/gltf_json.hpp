// The JSON of a glTF document written back (gltf_document.cpp): the input's own JSON, with only
// the members the document changes taken from tinygltf's serialization of the changed model.
// tinygltf's writer does not round-trip a document: it writes an element with no members (an
// empty scene or node, {} in extras) as null, which no reader accepts; it writes members the
// input did not have (a perspective camera's zfar as 0, which makes an infinite projection a
// far plane at 0; a sampler's wrap modes); and it drops some (a skin's extras, a sampler's
// extensions, an animation without channels). Starting from the input's JSON keeps every
// element that is not ours to change as the input had it. Private to src/mesh.
#pragma once

#include <string>
#include <vector>

namespace shellcontract::gltf {

/// The JSON text of a glTF file: a .glb's JSON chunk (told by the magic "glTF"; the container is
/// checked by the reader before), otherwise the whole file.
std::string json_text(const std::string& bytes);

/// The file tinygltf wrote (`written`, a .glb when `binary`, else .gltf text), with its JSON
/// replaced by `input_json` updated by what the document changes: each buffer's byteLength and
/// uri; the min and max of the accessors in `bounded`; each node's mesh; each primitive's
/// attributes. Elements the document appended (accessor, buffer view and mesh copies of an
/// instanced mesh) are taken from tinygltf's JSON; an appended mesh is its source mesh's JSON
/// with the copy's name and attributes.
/// @throws std::runtime_error when either JSON does not parse (tinygltf read and wrote both)
std::string restore_input_json(const std::string& input_json, const std::string& written,
                               bool binary, const std::vector<int>& bounded);

/// `input_json` (the JSON of the glTF file `input_path`) with each image's relative URI naming
/// the same file from the folder of `output_path` (docs/design/attributes.md, "glTF inputs"), as
/// an OBJ's mtllib paths are rewritten (obj_material_paths.hpp, path_from_folder): percent-decoded
/// to find the file, the new path percent-encoded where a URI needs it. Data URIs, URIs with a
/// scheme and absolute paths stay. A URI that names no file from the input's folder stays as
/// read, with a warning "<input>: images[<i>].uri '<uri>' ..." appended to `warnings` (when
/// given). The JSON itself when both files are in the same folder or nothing changes.
/// @throws std::runtime_error when the JSON does not parse
std::string relocate_image_uris(const std::string& input_json, const std::string& input_path,
                                const std::string& output_path, std::vector<std::string>* warnings);

}  // namespace shellcontract::gltf
