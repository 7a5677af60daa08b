// The .glb's primitives (docs/design/export.md, "Name and material"): the faces split by material,
// one primitive each, and the glTF materials they reference, images embedded once.
#pragma once

#include <tiny_gltf.h>

#include <vector>

#include "export/gltf_buffer.hpp"
#include "shellcontract/export.hpp"

namespace shellcontract::gltf {

/// The faces of one primitive.
struct PrimitiveFaces {
  int material = -1;  ///< index into GltfAnimation::materials; -1: none (glTF's default)
  Faces faces;        ///< its rows of the faces given, in their order
};

/// `faces` split by `a.face_material` (empty: every face has material 0 when a.materials has
/// one, else none), one entry per material used, in the order of each one's first face.
/// @pre check_materials(a) and faces.rows() == a.faces.rows()
std::vector<PrimitiveFaces> faces_by_material(const GltfAnimation& a, const Faces& faces);

/// @throws std::invalid_argument for face_material of another size than the faces or with an
///         index out of range, a base colour component outside [0, 1], or an image without a
///         mime type or without texture coordinates
void check_materials(const GltfAnimation& a);

/// Adds the materials the primitives use to the model, in the primitives' order, with their
/// images in the buffer (the same bytes once: one image and texture for materials that share
/// them). Returns per primitive its glTF material index; -1 for none.
std::vector<int> add_materials(tinygltf::Model& model, BufferBuilder& bb,
                               const std::vector<GltfMaterial>& materials,
                               const std::vector<PrimitiveFaces>& primitives);

/// The bytes add_materials' images take in the buffer at most (with alignment padding).
std::size_t material_bytes(const std::vector<GltfMaterial>& materials);

}  // namespace shellcontract::gltf
