// Reading a glTF 2.0 file into a triangle soup (gltf_reader.hpp).
#include "mesh/gltf_reader.hpp"

#include <sys/stat.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>
#include <utility>

#include "mesh/file_safety.hpp"
#include "mesh/gltf_json_checks.hpp"
#include "mesh/gltf_model.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/file_error.hpp"

namespace shellcontract {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem,
                       const std::string& details) {
  throw InputError(path + ": " + problem + ": " + details);
}

/// A required extension that the reader would have to apply to get the geometry right: anything
/// but materials, textures and lights (which change how it looks, not where its vertices are).
/// Only extensionsRequired is consulted: an extension a file uses without requiring it has a
/// fallback by the spec (Draco's uncompressed accessors, one instance for GPU instancing), which
/// is what is read, as by any renderer without the extension.
bool changes_geometry(const std::string& ext) {
  for (const char* harmless : {"KHR_materials_", "KHR_texture_", "EXT_texture_",
                               "KHR_lights_punctual", "MSFT_texture_dds"})
    if (ext.rfind(harmless, 0) == 0) return false;
  return true;
}

}  // namespace

namespace gltf {

ElementView element_view(const std::string& path, const tinygltf::Model& m, int index,
                         const std::string& what, std::size_t element_size) {
  const std::string name = what + " (accessor " + std::to_string(index) + ")";
  if (index < 0 || static_cast<std::size_t>(index) >= m.accessors.size())
    fail(path, "accessor out of range",
         what + " is accessor " + std::to_string(index) + ", but the file has " +
             std::to_string(m.accessors.size()) + " accessors");
  const tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(index)];
  if (a.sparse.isSparse) fail(path, "sparse accessor", name + " is sparse, which is not read");
  if (a.bufferView < 0 || static_cast<std::size_t>(a.bufferView) >= m.bufferViews.size())
    fail(path, "accessor without data",
         name + " has no buffer view (or buffer view " + std::to_string(a.bufferView) +
             " does not exist)");
  const tinygltf::BufferView& v = m.bufferViews[static_cast<std::size_t>(a.bufferView)];
  const std::string view = "buffer view " + std::to_string(a.bufferView);
  if (v.buffer < 0 || static_cast<std::size_t>(v.buffer) >= m.buffers.size())
    fail(path, "buffer out of range",
         view + " names buffer " + std::to_string(v.buffer) + ", but the file has " +
             std::to_string(m.buffers.size()));
  const std::size_t size = m.buffers[static_cast<std::size_t>(v.buffer)].data.size();
  if (v.byteOffset > size || v.byteLength > size - v.byteOffset)
    fail(path, "buffer view out of range",
         view + " (bytes " + std::to_string(v.byteOffset) + " + " + std::to_string(v.byteLength) +
             ") runs past the end of buffer " + std::to_string(v.buffer) + " (" +
             std::to_string(size) + " bytes)");
  const std::size_t stride = v.byteStride == 0 ? element_size : v.byteStride;
  if (stride < element_size)
    fail(path, "bad byte stride",
         view + "'s byteStride " + std::to_string(stride) + " is less than the " +
             std::to_string(element_size) + " bytes of an element of " + name);
  if (a.count > 0) {
    // Last element's end: byteOffset + stride * (count - 1) + element_size, inside the view. Each
    // step is checked against the view's length, so nothing overflows.
    const std::size_t room = v.byteLength;
    const bool fits = a.byteOffset <= room && element_size <= room - a.byteOffset &&
                      (a.count - 1) <= (room - a.byteOffset - element_size) / stride;
    if (!fits)
      fail(path, "accessor out of range",
           name + ": " + std::to_string(a.count) + " elements from byte " +
               std::to_string(a.byteOffset) + " with a stride of " + std::to_string(stride) +
               " run past the end of " + view + " (" + std::to_string(room) + " bytes)");
  }
  ElementView out;
  out.buffer = static_cast<std::size_t>(v.buffer);
  out.offset = v.byteOffset + a.byteOffset;
  out.stride = stride;
  out.count = a.count;
  return out;
}

}  // namespace gltf

namespace {

using gltf::element_view;
using gltf::ElementView;

/// A node's local transform: its matrix, or translation * rotation * scale (glTF's order).
Eigen::Matrix4d local_transform(const std::string& path, const tinygltf::Node& n,
                                std::size_t index) {
  const std::string name = "node " + std::to_string(index);
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  if (!n.matrix.empty()) {
    if (n.matrix.size() != 16)
      fail(path, "bad node transform",
           name + "'s matrix has " + std::to_string(n.matrix.size()) + " numbers, not 16");
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        t(r, c) = n.matrix[static_cast<std::size_t>(4 * c + r)];  // column-major
    return t;
  }
  const auto size_is = [&](const std::vector<double>& v, std::size_t k, const char* what) {
    if (!v.empty() && v.size() != k)
      fail(path, "bad node transform",
           name + "'s " + what + " has " + std::to_string(v.size()) + " numbers, not " +
               std::to_string(k));
    return !v.empty();
  };
  if (size_is(n.scale, 3, "scale"))
    t.topLeftCorner<3, 3>() = Eigen::Vector3d(n.scale[0], n.scale[1], n.scale[2]).asDiagonal();
  if (size_is(n.rotation, 4, "rotation")) {
    Eigen::Quaterniond q(n.rotation[3], n.rotation[0], n.rotation[1],
                         n.rotation[2]);  // glTF: x y z w
    if (!(q.norm() > 0.0))
      fail(path, "bad node transform",
           name + "'s rotation is not a unit quaternion (its norm is 0 or not a number)");
    q.normalize();  // exporters write rounded unit quaternions
    t.topLeftCorner<3, 3>() = q.toRotationMatrix() * t.topLeftCorner<3, 3>();
  }
  if (size_is(n.translation, 3, "translation"))
    t.topRightCorner<3, 1>() =
        Eigen::Vector3d(n.translation[0], n.translation[1], n.translation[2]);
  return t;
}

/// A primitive's triangles, checked: each corner is an element of its POSITION accessor.
struct PrimitiveCorners {
  ElementView xyz;
  std::vector<std::size_t> corners;
};

PrimitiveCorners read_corners(const std::string& path, const tinygltf::Model& m,
                              std::size_t mesh_index, std::size_t p, GltfSoup& soup) {
  const tinygltf::Primitive& prim = m.meshes[mesh_index].primitives[p];
  const std::string name = "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(p);
  soup.morphed += !prim.targets.empty();
  static const char* const MODES[] = {"points",    "lines",          "line loop",   "line strip",
                                      "triangles", "triangle strip", "triangle fan"};
  if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1)
    fail(path, "not triangles",
         name + ": mode " + std::to_string(prim.mode) + " (" +
             (prim.mode >= 0 && prim.mode < 7 ? MODES[prim.mode] : "not a glTF mode") +
             ") is not triangles (mode 4); export the mesh as triangles");
  const auto pos = prim.attributes.find("POSITION");
  if (pos == prim.attributes.end()) fail(path, "no positions", name + " has no POSITION attribute");
  const std::string pos_name = name + " POSITION";
  if (pos->second >= 0 && static_cast<std::size_t>(pos->second) < m.accessors.size()) {
    const tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(pos->second)];
    if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT ||
        a.normalized)
      fail(path, "bad positions",
           pos_name + " (accessor " + std::to_string(pos->second) +
               ") is not float VEC3 (quantized positions are not read)");
  }
  PrimitiveCorners out;
  out.xyz = element_view(path, m, pos->second, pos_name, 12);
  const ElementView& xyz = out.xyz;
  // The primitive's triangles on its POSITION accessor's elements.
  std::vector<std::size_t>& corners = out.corners;
  if (prim.indices < 0) {
    if (xyz.count % 3 != 0)
      fail(path, "bad triangle list",
           name + " has no indices and " + std::to_string(xyz.count) +
               " positions, not a multiple of 3");
    corners.resize(xyz.count);
    for (std::size_t i = 0; i < xyz.count; ++i) corners[i] = i;
  } else {
    const std::string idx_name = name + " indices";
    if (static_cast<std::size_t>(prim.indices) >= m.accessors.size())
      fail(path, "accessor out of range",
           idx_name + " is accessor " + std::to_string(prim.indices) + ", but the file has " +
               std::to_string(m.accessors.size()) + " accessors");
    const tinygltf::Accessor& ia = m.accessors[static_cast<std::size_t>(prim.indices)];
    std::size_t size = 0;
    if (ia.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE)
      size = 1;
    else if (ia.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)
      size = 2;
    else if (ia.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      size = 4;
    if (ia.type != TINYGLTF_TYPE_SCALAR || size == 0)
      fail(path, "bad indices",
           idx_name + " (accessor " + std::to_string(prim.indices) +
               ") is not SCALAR unsigned byte, short or int (component type " +
               std::to_string(ia.componentType) + ")");
    const ElementView idx = element_view(path, m, prim.indices, idx_name, size);
    if (idx.count % 3 != 0)
      fail(path, "bad triangle list",
           idx_name + " has " + std::to_string(idx.count) + " indices, not a multiple of 3");
    corners.resize(idx.count);
    for (std::size_t i = 0; i < idx.count; ++i) {
      std::uint32_t v = 0;
      const unsigned char* b = idx.at(m, i);
      for (std::size_t k = size; k-- > 0;) v = (v << 8) | b[k];  // little-endian
      if (v >= xyz.count)
        fail(path, "vertex index out of range",
             name + " triangle " + std::to_string(i / 3) + " refers to vertex " +
                 std::to_string(v) + ", but its POSITION has " + std::to_string(xyz.count));
      corners[i] = v;
    }
  }
  return out;
}

/// What makes two primitives of one node draw the same vertices: their POSITION accessor, and
/// every other attribute and morph target naming the same accessors, so that an element's
/// normal, texture coordinates and colour are one whichever primitive draws it.
using VertexSet = std::tuple<std::map<std::string, int>, std::vector<std::map<std::string, int>>>;

/// The triangles of node `node`'s mesh, each primitive drawn in order (soup.drawn). An element of
/// a POSITION accessor that several primitives draw (a mesh split into one primitive per
/// material over one vertex buffer, as exporters write it) is one vertex, not a copy per
/// primitive; only primitives whose other attributes name other accessors for it (their own
/// NORMAL, say) get copies of their own, welded as seam copies are. Only the elements the
/// triangles use become vertices (unused ones would be refused), in accessor order per set of
/// primitives sharing them, the sets in the order of their first primitive; each is found by
/// sorting the corners, not by walking the whole accessor, so that many primitives on one large
/// accessor cost their corners, not primitives x elements.
void read_node(const std::string& path, const tinygltf::Model& m, std::size_t node,
               std::size_t mesh_index, const Eigen::Matrix4d& world, GltfSoup& soup) {
  const std::vector<tinygltf::Primitive>& prims = m.meshes[mesh_index].primitives;
  const std::size_t first_drawn = soup.drawn.size();
  std::vector<PrimitiveCorners> read;
  read.reserve(prims.size());
  for (std::size_t p = 0; p < prims.size(); ++p) {
    read.push_back(read_corners(path, m, mesh_index, p, soup));
    soup.drawn.push_back({node, mesh_index, p});
  }
  // Per set of primitives sharing vertices: its elements used, sorted, each with the first
  // primitive drawing it, and the index of its first vertex.
  struct Shared {
    std::vector<std::pair<std::size_t, std::size_t>> used;  // element, drawn ordinal
    std::size_t first = 0;
  };
  std::vector<Shared> sets;
  std::vector<std::size_t> set_of(prims.size());
  std::map<VertexSet, std::size_t> set_by_key;
  for (std::size_t p = 0; p < prims.size(); ++p) {
    VertexSet key{prims[p].attributes, prims[p].targets};
    const auto [it, fresh] = set_by_key.emplace(std::move(key), sets.size());
    if (fresh) sets.emplace_back();
    set_of[p] = it->second;
    for (const std::size_t e : read[p].corners)
      sets[it->second].used.emplace_back(e, first_drawn + p);
  }
  for (Shared& s : sets) {
    // By element, then drawn ordinal: the first pair of an element names its first primitive.
    std::sort(s.used.begin(), s.used.end());
    s.used.erase(std::unique(s.used.begin(), s.used.end(),
                             [](const auto& a, const auto& b) { return a.first == b.first; }),
                 s.used.end());
  }
  // The vertices, set by set in the order of each set's first primitive (set indices are in that
  // order), each read through the view of a primitive of its set (they share the accessor).
  std::vector<const ElementView*> view_of(sets.size(), nullptr);
  for (std::size_t p = 0; p < prims.size(); ++p)
    if (!view_of[set_of[p]]) view_of[set_of[p]] = &read[p].xyz;
  for (std::size_t k = 0; k < sets.size(); ++k) {
    sets[k].first = soup.points.size();
    for (const auto& [i, drawn] : sets[k].used) {
      float f[3];
      std::memcpy(f, view_of[k]->at(m, i), sizeof f);
      const Eigen::Vector4d w = world * Eigen::Vector4d(f[0], f[1], f[2], 1.0);
      soup.points.push_back({w[0], w[1], w[2]});
      soup.sources.push_back({drawn, i});
    }
  }
  // A mirroring transform turns the triangles inside out; glTF renderers reverse them (the spec,
  // "Transformations"), so the mesh keeps its outside.
  const bool mirrored = world.topLeftCorner<3, 3>().determinant() < 0.0;
  for (std::size_t p = 0; p < prims.size(); ++p) {
    const Shared& s = sets[set_of[p]];
    const auto vertex_of = [&](std::size_t corner) {
      const auto it = std::lower_bound(
          s.used.begin(), s.used.end(), corner,
          [](const std::pair<std::size_t, std::size_t>& u, std::size_t e) { return u.first < e; });
      return s.first + static_cast<std::size_t>(it - s.used.begin());
    };
    // No reserve here: an exact one per primitive would move every face read so far each time.
    const std::vector<std::size_t>& corners = read[p].corners;
    for (std::size_t t = 0; t + 2 < corners.size(); t += 3) {
      const std::size_t a = vertex_of(corners[t]), b = vertex_of(corners[t + 1]),
                        c = vertex_of(corners[t + 2]);
      soup.faces.push_back(mirrored ? std::vector<std::size_t>{a, c, b}
                                    : std::vector<std::size_t>{a, b, c});
      soup.face_drawn.push_back(first_drawn + p);
    }
  }
}

/// The most triangles a scene may draw for each byte of its file and buffers (scene_soup).
constexpr std::uint64_t TRIANGLES_PER_BYTE = 64;

/// Refuses a scene that draws more than TRIANGLES_PER_BYTE triangles for each byte of the file and
/// its buffers, counted from the accessors' counts before any of their data is read: a mesh whose
/// primitives all draw one index accessor, drawn by many nodes, makes primitives x nodes copies of
/// the accessor's triangles from a few bytes of JSON each. What is malformed counts nothing here
/// (the read refuses it as before): an element out of range, a node reached twice.
void check_scene_size(const std::string& path, const tinygltf::Model& m, int scene,
                      std::size_t file_bytes) {
  constexpr std::uint64_t MAX = std::numeric_limits<std::uint64_t>::max();
  const auto add = [](std::uint64_t a, std::uint64_t b) { return a > MAX - b ? MAX : a + b; };
  const auto mul = [](std::uint64_t a, std::uint64_t b) {
    return b != 0 && a > MAX / b ? MAX : a * b;
  };
  const auto count_of = [&](int accessor) -> std::uint64_t {
    return accessor >= 0 && static_cast<std::size_t>(accessor) < m.accessors.size()
               ? m.accessors[static_cast<std::size_t>(accessor)].count / 3
               : 0;
  };
  std::vector<std::uint64_t> per_draw(m.meshes.size(), 0), draws(m.meshes.size(), 0);
  for (std::size_t k = 0; k < m.meshes.size(); ++k)
    for (const tinygltf::Primitive& p : m.meshes[k].primitives) {
      const auto pos = p.attributes.find("POSITION");
      const int counted = p.indices >= 0 ? p.indices : pos != p.attributes.end() ? pos->second : -1;
      per_draw[k] = add(per_draw[k], count_of(counted));
    }
  std::vector<char> seen(m.nodes.size(), 0);
  std::vector<int> stack(m.scenes[static_cast<std::size_t>(scene)].nodes);
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    if (n < 0 || static_cast<std::size_t>(n) >= m.nodes.size() || seen[static_cast<std::size_t>(n)])
      continue;
    seen[static_cast<std::size_t>(n)] = 1;
    const tinygltf::Node& node = m.nodes[static_cast<std::size_t>(n)];
    if (node.mesh >= 0 && static_cast<std::size_t>(node.mesh) < m.meshes.size())
      ++draws[static_cast<std::size_t>(node.mesh)];
    stack.insert(stack.end(), node.children.begin(), node.children.end());
  }
  std::uint64_t bytes = file_bytes, total = 0;
  for (const tinygltf::Buffer& b : m.buffers) bytes = add(bytes, b.data.size());
  std::size_t worst = 0;
  for (std::size_t k = 0; k < m.meshes.size(); ++k) {
    total = add(total, mul(draws[k], per_draw[k]));
    if (mul(draws[k], per_draw[k]) > mul(draws[worst], per_draw[worst])) worst = k;
  }
  if (total <= mul(bytes, TRIANGLES_PER_BYTE)) return;
  fail(path, "scene too large for its file",
       "the default scene draws " + std::to_string(total) + " triangles, more than " +
           std::to_string(TRIANGLES_PER_BYTE) + " for each of the " + std::to_string(bytes) +
           " bytes of the file and its buffers: mesh " + std::to_string(worst) + " (" +
           std::to_string(m.meshes[worst].primitives.size()) + " primitives, " +
           std::to_string(per_draw[worst]) + " triangles) is drawn by " +
           std::to_string(draws[worst]) + " nodes; it was not read");
}

}  // namespace

GltfSoup gltf::scene_soup(const std::string& path, const tinygltf::Model& m, std::size_t file_bytes,
                          std::vector<Eigen::Matrix4d>* world_of) {
  for (const std::string& e : m.extensionsRequired)
    if (changes_geometry(e))
      fail(path, "unsupported extension",
           "the file requires " + e +
               ", which is not read (export without it: no compression, no quantization, no GPU "
               "instancing)");
  if (m.scenes.empty()) fail(path, "no scene", "the file has no scene, so nothing is drawn");
  const int scene = m.defaultScene >= 0 ? m.defaultScene : 0;
  if (static_cast<std::size_t>(scene) >= m.scenes.size())
    fail(path, "scene out of range",
         "the default scene is " + std::to_string(scene) + ", but the file has " +
             std::to_string(m.scenes.size()));
  check_scene_size(path, m, scene, file_bytes);

  GltfSoup soup;
  // Depth first, children in order, without recursion (a file decides the depth); a node reached
  // twice (a cycle, or a child of two parents) is refused: glTF's nodes are a forest.
  std::vector<char> seen(m.nodes.size(), 0);
  std::vector<std::pair<std::size_t, Eigen::Matrix4d>> stack;
  const auto push = [&](int node, const Eigen::Matrix4d& parent, const std::string& from) {
    if (node < 0 || static_cast<std::size_t>(node) >= m.nodes.size())
      fail(path, "node out of range",
           from + " names node " + std::to_string(node) + ", but the file has " +
               std::to_string(m.nodes.size()));
    const auto k = static_cast<std::size_t>(node);
    if (seen[k])
      fail(path, "bad node tree",
           "node " + std::to_string(node) + " is reached twice (" + from +
               "): a cycle or two parents");
    seen[k] = 1;
    stack.emplace_back(k, parent * local_transform(path, m.nodes[k], k));
  };
  const std::vector<int>& roots = m.scenes[static_cast<std::size_t>(scene)].nodes;
  for (auto r = roots.rbegin(); r != roots.rend(); ++r)
    push(*r, Eigen::Matrix4d::Identity(), "scene " + std::to_string(scene));
  while (!stack.empty()) {
    const auto [k, world] = stack.back();
    stack.pop_back();
    const tinygltf::Node& node = m.nodes[k];
    if (node.mesh >= 0) {
      if (static_cast<std::size_t>(node.mesh) >= m.meshes.size())
        fail(path, "mesh out of range",
             "node " + std::to_string(k) + " names mesh " + std::to_string(node.mesh) +
                 ", but the file has " + std::to_string(m.meshes.size()));
      const auto mi = static_cast<std::size_t>(node.mesh);
      read_node(path, m, k, mi, world, soup);
      if (world_of) world_of->resize(soup.drawn.size(), world);
    }
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c)
      push(*c, world, "node " + std::to_string(k) + "'s children");
  }
  return soup;
}

GltfSoup read_gltf(const std::string& path, const std::string& bytes) {
  return gltf::scene_soup(path, gltf::load_model(path, bytes), bytes.size());
}

}  // namespace shellcontract
