// The .glb's one buffer as it is filled: views and accessors on arrays appended to it, and the
// one node and scene that draw its mesh. Shared by the writer of the animation
// (gltf_animation.cpp), of its primitives' materials (gltf_primitives.cpp) and of repair's bare
// glTF (src/mesh/gltf_mesh_writer.cpp).
#pragma once

#include <tiny_gltf.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "shellcontract/types.hpp"

namespace shellcontract::gltf {

using Floats3 = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Floats2 = Eigen::Matrix<float, Eigen::Dynamic, 2, Eigen::RowMajor>;

/// Appends arrays to the model's one buffer and makes views and accessors on them.
class BufferBuilder {
 public:
  /// `capacity`: the bytes the buffer will hold (its growth by doubling would hold up to twice
  /// as many for a moment, hundreds of MB for a large mesh's frames).
  BufferBuilder(tinygltf::Model& model, std::size_t capacity) : model_(model) {
    model_.buffers.resize(1);
    model_.buffers[0].data.reserve(capacity);
  }

  /// A view on a copy of `bytes` bytes at `data` (4-byte aligned); target 0 means none.
  int add_view(const void* data, std::size_t bytes, int target) {
    std::vector<unsigned char>& buf = model_.buffers[0].data;
    while (buf.size() % 4 != 0) buf.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buf.size();
    view.byteLength = bytes;
    view.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    buf.insert(buf.end(), p, p + bytes);
    model_.bufferViews.push_back(view);
    return static_cast<int>(model_.bufferViews.size()) - 1;
  }

  /// A float VEC3 vertex attribute; with_bounds adds min/max (required for POSITION).
  int add_vec3(const Floats3& a, bool with_bounds) {
    tinygltf::Accessor acc;
    acc.bufferView = add_view(a.data(), sizeof(float) * static_cast<std::size_t>(a.size()),
                              TINYGLTF_TARGET_ARRAY_BUFFER);
    acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    acc.count = static_cast<std::size_t>(a.rows());
    acc.type = TINYGLTF_TYPE_VEC3;
    if (with_bounds) {
      const Eigen::RowVector3f lo = a.colwise().minCoeff(), hi = a.colwise().maxCoeff();
      acc.minValues = {lo(0), lo(1), lo(2)};
      acc.maxValues = {hi(0), hi(1), hi(2)};
    }
    return push(acc);
  }

  /// A float VEC2 vertex attribute (texture coordinates).
  int add_vec2(const Floats2& a) {
    tinygltf::Accessor acc;
    acc.bufferView = add_view(a.data(), sizeof(float) * static_cast<std::size_t>(a.size()),
                              TINYGLTF_TARGET_ARRAY_BUFFER);
    acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    acc.count = static_cast<std::size_t>(a.rows());
    acc.type = TINYGLTF_TYPE_VEC2;
    return push(acc);
  }

  /// A float VEC3 or VEC4 vertex attribute (colours: 3 or 4 columns).
  int add_colours(const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& a) {
    tinygltf::Accessor acc;
    acc.bufferView = add_view(a.data(), sizeof(float) * static_cast<std::size_t>(a.size()),
                              TINYGLTF_TARGET_ARRAY_BUFFER);
    acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    acc.count = static_cast<std::size_t>(a.rows());
    acc.type = a.cols() == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4;
    return push(acc);
  }

  /// A float SCALAR vertex attribute (a field's values).
  int add_vertex_scalars(const Eigen::VectorXf& a) {
    tinygltf::Accessor acc;
    acc.bufferView = add_view(a.data(), sizeof(float) * static_cast<std::size_t>(a.size()),
                              TINYGLTF_TARGET_ARRAY_BUFFER);
    acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    acc.count = static_cast<std::size_t>(a.size());
    acc.type = TINYGLTF_TYPE_SCALAR;
    return push(acc);
  }

  /// A float SCALAR array (animation keys and weights); with_bounds adds min/max.
  int add_scalars(const std::vector<float>& a, bool with_bounds) {
    tinygltf::Accessor acc;
    acc.bufferView = add_view(a.data(), sizeof(float) * a.size(), 0);
    acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    acc.count = a.size();
    acc.type = TINYGLTF_TYPE_SCALAR;
    if (with_bounds) {
      acc.minValues = {*std::min_element(a.begin(), a.end())};
      acc.maxValues = {*std::max_element(a.begin(), a.end())};
    }
    return push(acc);
  }

  /// Triangle indices as unsigned 32-bit integers.
  int add_indices(const Faces& faces) {
    std::vector<std::uint32_t> idx(static_cast<std::size_t>(faces.size()));
    for (Eigen::Index i = 0; i < faces.size(); ++i)
      idx[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(faces.data()[i]);
    tinygltf::Accessor acc;
    acc.bufferView = add_view(idx.data(), sizeof(std::uint32_t) * idx.size(),
                              TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    acc.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    acc.count = idx.size();
    acc.type = TINYGLTF_TYPE_SCALAR;
    return push(acc);
  }

 private:
  int push(const tinygltf::Accessor& acc) {
    model_.accessors.push_back(acc);
    return static_cast<int>(model_.accessors.size()) - 1;
  }
  tinygltf::Model& model_;
};

/// The model's one scene (its default) of one node, named `name`, that draws mesh 0, moved by
/// `translation` (none written when it is zero, glTF's default).
inline void add_single_node_scene(tinygltf::Model& model, const std::string& name,
                                  const Vec3& translation = Vec3::Zero()) {
  tinygltf::Node node;
  node.name = name;
  node.mesh = 0;
  if (translation != Vec3::Zero())
    node.translation = {translation.x(), translation.y(), translation.z()};
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
}

}  // namespace shellcontract::gltf
