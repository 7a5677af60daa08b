// Realizing instanced meshes for the glTF document (gltf_document.cpp; docs/design/attributes.md,
// "glTF inputs"): a mesh drawn by several nodes is simulated once per node, and those copies move
// apart, so each node after the first gets its own positions (and normals) to hold them.
// Private to src/mesh, like gltf_model.hpp.
#pragma once

#include <string>
#include <vector>

#include "mesh/gltf_model.hpp"

namespace shellcontract::gltf {

/// The accessors a drawn primitive's new positions and normals are written to.
struct WrittenAccessors {
  int position = -1;
  int normal = -1;  ///< -1: its normals are not written
};

/// Gives every node whose drawn POSITION (or written NORMAL) accessors an earlier node of the
/// soup already draws its own copies of them, so that each drawing can hold its own values:
/// - the first node to draw an accessor keeps it (a file without instancing is left unchanged);
/// - a later node gets a new mesh, a copy of its mesh named "<mesh name> (node <node name>)"
///   (a missing name is written "mesh <index>", "<index>"), whose primitives name new POSITION
///   and NORMAL accessors in place of the shared ones; every other attribute, the indices, the
///   material, the morph targets and the extras keep naming the original accessors and values.
///   Where the node is the first to draw its mesh (a POSITION accessor shared by two meshes),
///   that mesh's primitives are changed in place instead;
/// - a new accessor is a copy of the old one (type, count, bounds, values) in a new buffer view
///   appended to the old one's buffer, tightly packed, at a 4-byte boundary.
/// @param normal per drawn primitive (parallel to soup.drawn): whether its NORMAL is written
/// @return per drawn primitive: the accessors its positions and normals go to
/// @throws InputError as element_view, for an accessor that is copied
std::vector<WrittenAccessors> realize_instances(const std::string& path, tinygltf::Model& m,
                                                const GltfSoup& soup,
                                                const std::vector<bool>& normal);

}  // namespace shellcontract::gltf
