// The parsed glTF model behind read_gltf, for the glTF document (gltf_document.cpp), which
// writes the file back with new positions. Private to src/mesh: it includes tinygltf, whose
// compile definitions (no image decoding) only the files that include it get (CMakeLists.txt).
#pragma once

#include <tiny_gltf.h>

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "mesh/gltf_reader.hpp"

namespace shellcontract::gltf {

/// Parses a .glb or .gltf (told by its first bytes), with its external buffers.
/// @param looked_up when given, gets every path where an external buffer was looked for (found
///        or not, in the file's folder and then in the current one, as tinygltf does), also
///        when the load then fails
/// @throws InputError for a file tinygltf cannot read, or a .glb whose container is malformed;
///         an InputFileError about the buffer's path, with its errno, for an external buffer
///         that is missing or cannot be read (the message names the glTF, as before)
tinygltf::Model load_model(const std::string& path, const std::string& bytes,
                           std::vector<std::string>* looked_up = nullptr);

/// The triangles that the default scene draws (read_gltf's soup), with each drawn primitive's
/// world transform in `world` (parallel to soup.drawn).
/// @param file_bytes the size of the glTF file, which with its buffers' bounds the triangles
///        the scene may draw (64 a byte; "scene too large for its file")
/// @throws InputError as read_gltf
GltfSoup scene_soup(const std::string& path, const tinygltf::Model& m, std::size_t file_bytes,
                    std::vector<Eigen::Matrix4d>* world = nullptr);

/// An accessor's elements: element i starts at byte offset + i * stride of buffer `buffer`,
/// and every element lies inside the buffer (checked).
struct ElementView {
  std::size_t buffer = 0;
  std::size_t offset = 0;
  std::size_t stride = 0;
  std::size_t count = 0;
  const unsigned char* at(const tinygltf::Model& m, std::size_t i) const {
    return m.buffers[buffer].data.data() + offset + i * stride;
  }
};

/// The checked view of accessor `index`, whose elements are `element_size` bytes.
/// @param what names the accessor's use in messages ("mesh 0 primitive 1 POSITION")
/// @throws InputError for an index out of range, a sparse accessor, one without a buffer view,
///         a stride below the element size, or an element outside its buffer view or buffer
ElementView element_view(const std::string& path, const tinygltf::Model& m, int index,
                         const std::string& what, std::size_t element_size);

}  // namespace shellcontract::gltf
