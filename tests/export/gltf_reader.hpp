// Reading a .glb back with tinygltf's own loader, for the export tests.
#pragma once

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <Eigen/Core>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace shellcontract::test {

using Floats = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The float data of accessor `index` (count rows, component-count columns), tightly packed.
inline Floats read_floats(const tinygltf::Model& m, int index) {
  const tinygltf::Accessor& acc = m.accessors.at(static_cast<std::size_t>(index));
  EXPECT_EQ(acc.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  const tinygltf::BufferView& view = m.bufferViews.at(static_cast<std::size_t>(acc.bufferView));
  const int cols = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type));
  EXPECT_EQ(view.byteStride, 0u);
  Floats out(static_cast<Eigen::Index>(acc.count), cols);
  const std::size_t bytes = sizeof(float) * acc.count * static_cast<std::size_t>(cols);
  EXPECT_LE(acc.byteOffset + bytes, view.byteLength);
  std::memcpy(out.data(),
              m.buffers.at(static_cast<std::size_t>(view.buffer)).data.data() + view.byteOffset +
                  acc.byteOffset,
              bytes);
  return out;
}

/// The indices of accessor `index` (unsigned 32-bit, the writer's type).
inline std::vector<std::uint32_t> read_indices(const tinygltf::Model& m, int index) {
  const tinygltf::Accessor& acc = m.accessors.at(static_cast<std::size_t>(index));
  EXPECT_EQ(acc.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
  EXPECT_EQ(acc.type, TINYGLTF_TYPE_SCALAR);
  const tinygltf::BufferView& view = m.bufferViews.at(static_cast<std::size_t>(acc.bufferView));
  std::vector<std::uint32_t> out(acc.count);
  const std::size_t bytes = sizeof(std::uint32_t) * acc.count;
  EXPECT_LE(acc.byteOffset + bytes, view.byteLength);
  if (acc.byteOffset + bytes > view.byteLength) return {};
  std::memcpy(out.data(),
              m.buffers.at(static_cast<std::size_t>(view.buffer)).data.data() + view.byteOffset +
                  acc.byteOffset,
              bytes);
  return out;
}

/// Keeps an embedded image undecoded (the library is built without image support); the tests
/// read its bytes from its bufferView.
inline bool keep_image_undecoded(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                                 const unsigned char*, int, void*) {
  return true;
}

inline tinygltf::Model load_glb(const std::string& path) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&keep_image_undecoded, nullptr);
  std::string err, warn;
  const bool ok = loader.LoadBinaryFromFile(&model, &err, &warn, path);
  EXPECT_TRUE(ok) << path << ": " << err;
  EXPECT_TRUE(err.empty()) << err;
  EXPECT_TRUE(warn.empty()) << warn;
  return model;
}

}  // namespace shellcontract::test
