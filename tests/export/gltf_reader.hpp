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

/// Node `node`'s translation (zero without one): write_gltf_animation stores positions relative
/// to the rest mesh's bounding-box centre and moves its node there.
inline Eigen::RowVector3d node_translation(const tinygltf::Model& m, std::size_t node = 0) {
  const std::vector<double>& t = m.nodes.at(node).translation;
  if (t.empty()) return Eigen::RowVector3d::Zero();
  EXPECT_EQ(t.size(), 3u);
  return Eigen::RowVector3d(t.at(0), t.at(1), t.at(2));
}

/// POSITION accessor `index` where node 0 places it (its translation added, in float as a
/// renderer does): the input's coordinates to float precision.
inline Floats read_positions(const tinygltf::Model& m, int index) {
  Floats x = read_floats(m, index);
  const Eigen::RowVector3f t = node_translation(m).cast<float>();
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (int k = 0; k < 3 && k < x.cols(); ++k) x(i, k) += t(k);
  return x;
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
