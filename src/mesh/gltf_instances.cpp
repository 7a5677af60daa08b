// Realizing instanced meshes for the glTF document (gltf_instances.hpp).
#include "mesh/gltf_instances.hpp"

#include <cstring>
#include <map>
#include <set>

namespace shellcontract::gltf {
namespace {

/// A copy of accessor `index` (float VEC3, checked by element_view) whose elements are a copy of
/// its elements, in a new buffer view at the end of the same buffer.
int copy_accessor(const std::string& path, tinygltf::Model& m, int index, const std::string& what,
                  const std::string& suffix) {
  const ElementView v = element_view(path, m, index, what, 12);
  tinygltf::Accessor a = m.accessors[static_cast<std::size_t>(index)];
  tinygltf::BufferView view;
  view.buffer = static_cast<int>(v.buffer);
  view.target = m.bufferViews[static_cast<std::size_t>(a.bufferView)].target;
  std::vector<unsigned char>& data = m.buffers[v.buffer].data;
  while (data.size() % 4 != 0) data.push_back(0);
  view.byteOffset = data.size();
  view.byteLength = v.count * 12;
  data.resize(view.byteOffset + view.byteLength);  // no reallocation below: copy within `data`
  for (std::size_t i = 0; i < v.count; ++i)
    std::memcpy(data.data() + view.byteOffset + i * 12, data.data() + v.offset + i * v.stride, 12);
  a.bufferView = static_cast<int>(m.bufferViews.size());
  a.byteOffset = 0;
  if (!a.name.empty()) a.name += suffix;
  m.bufferViews.push_back(view);
  m.accessors.push_back(a);
  return static_cast<int>(m.accessors.size() - 1);
}

/// The accessors written for primitive `primitive` of mesh `mesh`, as the mesh names them now.
WrittenAccessors written(const tinygltf::Model& m, std::size_t mesh, std::size_t primitive,
                         bool normal) {
  const auto& attributes = m.meshes[mesh].primitives[primitive].attributes;
  WrittenAccessors w;
  w.position = attributes.at("POSITION");
  if (normal) w.normal = attributes.at("NORMAL");
  return w;
}

}  // namespace

std::vector<WrittenAccessors> realize_instances(const std::string& path, tinygltf::Model& m,
                                                const GltfSoup& soup,
                                                const std::vector<bool>& normal) {
  std::vector<WrittenAccessors> out(soup.drawn.size());
  std::map<int, std::size_t> owner;  // accessor -> the node whose values it holds
  std::vector<char> mesh_drawn(m.meshes.size(), 0);
  // A node's primitives are drawn one after another (scene_soup): one node at a time.
  for (std::size_t first = 0, end = 0; first < soup.drawn.size(); first = end) {
    const std::size_t node = soup.drawn[first].node, mesh = soup.drawn[first].mesh;
    while (end < soup.drawn.size() && soup.drawn[end].node == node) ++end;
    // The accessors this node writes that an earlier node writes too.
    std::set<int> shared;
    for (std::size_t d = first; d < end; ++d) {
      const WrittenAccessors w = written(m, mesh, soup.drawn[d].primitive, normal[d]);
      for (const int a : {w.position, w.normal}) {
        if (a < 0) continue;
        const auto [it, fresh] = owner.emplace(a, node);
        if (!fresh && it->second != node) shared.insert(a);
      }
    }
    std::size_t target = mesh;
    if (!shared.empty()) {
      const tinygltf::Node& n = m.nodes[node];
      const std::string suffix = " (node " + (n.name.empty() ? std::to_string(node) : n.name) + ")";
      if (mesh_drawn[mesh]) {  // a later drawing of the mesh: a copy of it of its own
        tinygltf::Mesh copy = m.meshes[mesh];
        copy.name = (copy.name.empty() ? "mesh " + std::to_string(mesh) : copy.name) + suffix;
        target = m.meshes.size();
        m.meshes.push_back(std::move(copy));
        m.nodes[node].mesh = static_cast<int>(target);
      }
      std::map<int, int> renamed;
      for (const int a : shared) {
        const std::string what = "mesh " + std::to_string(mesh) + "'s accessor drawn again";
        renamed[a] = copy_accessor(path, m, a, what, suffix);
        owner[renamed[a]] = node;
      }
      for (tinygltf::Primitive& p : m.meshes[target].primitives)
        for (const char* key : {"POSITION", "NORMAL"}) {
          const auto it = p.attributes.find(key);
          if (it == p.attributes.end()) continue;
          const auto r = renamed.find(it->second);
          if (r != renamed.end()) it->second = r->second;
        }
    }
    for (std::size_t d = first; d < end; ++d)
      out[d] = written(m, target, soup.drawn[d].primitive, normal[d]);
    mesh_drawn[mesh] = 1;
  }
  return out;
}

}  // namespace shellcontract::gltf
