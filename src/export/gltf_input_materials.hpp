// The --gltf animation's materials of a glTF input (docs/design/export.md, "Name and material"):
// the input's own materials, textures, samplers and images, carried as they are, the images'
// bytes embedded in the .glb's buffer.
#pragma once

#include <tiny_gltf.h>

#include <string>
#include <vector>

#include "export/gltf_buffer.hpp"
#include "export/gltf_material.hpp"

namespace shellcontract::gltf {

/// gltf_materials for a glTF input (materials.gltf set): one GltfMaterial per input material
/// (source_material: its index), each face with its primitive's, and in `source` a model holding
/// only the input's materials, textures, samplers and images, each image's bytes in
/// Image::image (from its buffer view, data URI or file beside the input). What cannot be
/// carried is a warning naming the input and the element: an image that cannot be read or is of
/// an unknown type (kept as the input names it), a texture on another set of texture
/// coordinates than TEXCOORD_0 or on a mesh without them (left out of the material).
/// @pre materials.gltf != nullptr
GltfFaceMaterials gltf_input_materials(const FaceMaterials& materials, bool has_texcoords,
                                       std::vector<std::string>& warnings);

/// Copies `source` (gltf_input_materials') into the model, which has none of its own: the
/// images with bytes go into the buffer as views, and the extensions they use are declared.
void add_source_materials(tinygltf::Model& model, BufferBuilder& bb, const tinygltf::Model& source);

/// The bytes add_source_materials puts in the buffer at most (with alignment padding).
std::size_t source_material_bytes(const tinygltf::Model* source);

}  // namespace shellcontract::gltf
