// The bytes the glTF document rewrites (gltf_document.cpp): the accessors of each drawn
// primitive whose elements get new values, and the check that no other data the file reads
// lies in those bytes. Private to src/mesh, like gltf_model.hpp.
#pragma once

#include <string>
#include <vector>

#include "mesh/gltf_model.hpp"

namespace shellcontract::gltf {

/// An accessor whose elements the document rewrites, with the primitive it was read for.
struct Written {
  ElementView view;
  int accessor = -1;  ///< -1: none is written
};

/// Refuses a file whose bytes that the document rewrites (its drawn primitives' POSITION and
/// float NORMAL elements) are also read as something else: a NORMAL that is the POSITION
/// accessor, or whose elements share bytes with POSITION's, would overwrite the new positions
/// with the new normals; another attribute, indices or a morph target there would change in
/// the result without a word. Two POSITION (or two NORMAL) accessors are not compared: their
/// copies at one position move together.
/// @param positions, normals per drawn primitive (parallel to soup.drawn): the written accessors
/// @throws InputError naming the two uses of the shared bytes
void check_written_bytes_alone(const std::string& path, const tinygltf::Model& model,
                               const GltfSoup& soup, const std::vector<Written>& positions,
                               const std::vector<Written>& normals);

}  // namespace shellcontract::gltf
