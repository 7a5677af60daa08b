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

std::uint32_t le32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i)
    v = (v << 8) | static_cast<unsigned char>(b[at + static_cast<std::size_t>(i)]);
  return v;
}

/// The GLB container, checked before tinygltf sees it: tinygltf accepts a header length short of
/// the file and reads a BIN chunk's 8-byte header past a length that only covers its data, and
/// its messages say "Invalid glTF binary." without saying what is wrong.
void check_glb_container(const std::string& path, const std::string& b) {
  if (b.size() < 12)
    fail(path, "truncated .glb",
         "the file has " + std::to_string(b.size()) + " bytes, less than the 12-byte header");
  if (b.compare(0, 4, "glTF") != 0)
    fail(path, "not a binary glTF", "the file does not start with the magic 'glTF'");
  const std::uint32_t version = le32(b, 4), length = le32(b, 8);
  if (version != 2)
    fail(path, "unsupported glTF version",
         "the header says version " + std::to_string(version) + " (only 2 is read)");
  if (length != b.size())
    fail(path, length > b.size() ? "truncated .glb" : "bytes after the .glb's end",
         "the header says " + std::to_string(length) + " bytes, the file has " +
             std::to_string(b.size()));
  std::size_t at = 12;
  for (int chunk = 0; at < b.size(); ++chunk) {
    if (b.size() - at < 8)
      fail(path, "truncated .glb",
           "chunk " + std::to_string(chunk) + " at byte " + std::to_string(at) +
               " has no complete 8-byte header");
    const std::uint64_t n = le32(b, at);
    const std::uint32_t type = le32(b, at + 4);
    if (n > b.size() - at - 8)
      fail(path, "truncated .glb",
           "chunk " + std::to_string(chunk) + " at byte " + std::to_string(at) + " declares " +
               std::to_string(n) + " bytes, " + std::to_string(b.size() - at - 8) + " remain");
    if (chunk == 0 && type != 0x4E4F534Au) fail(path, "bad .glb", "the first chunk is not JSON");
    at += 8 + n;
  }
}

// tinygltf's file callbacks: an external buffer is read like the mesh file itself (a regular file,
// every read checked: read_regular_file), and a path is never expanded by the shell's rules
// (tinygltf's default ExpandFilePath calls wordexp) nor opened to test that it exists (fopen on a
// FIFO blocks).
/// The callbacks' user data: the paths asked about and why the file system refused them, so
/// that a glTF whose buffer cannot be had is a file error about the buffer (Python's
/// FileNotFoundError naming the .bin), not about the .gltf.
struct ExternalFiles {
  /// When given, every path asked about, found or not (input_dependencies).
  std::vector<std::string>* looked_up = nullptr;
  /// Each path not found or not read, with its errno, in the order asked.
  std::vector<FileSystemFailure> refused;
  /// The buffers the JSON declares (check_top_level), to bound an external buffer's read.
  std::vector<gltf::DeclaredBuffer> declared;
  /// The refusal of a buffer file larger than its buffer, made before reading it.
  std::string too_large;
};
bool file_exists(const std::string& p, void* files) {
  auto& f = *static_cast<ExternalFiles*>(files);
  if (f.looked_up) f.looked_up->push_back(p);
  struct stat st {};
  if (::stat(p.c_str(), &st) == 0) return true;
  const int error_number = errno;
  f.refused.emplace_back(error_number, p);
  return false;
}
std::string same_path(const std::string& p, void*) { return p; }
bool read_buffer_file(std::vector<unsigned char>* out, std::string* err, const std::string& p,
                      void* files) {
  try {
    auto& f = *static_cast<ExternalFiles*>(files);
    const auto [bound, why] = gltf::buffer_file_bound(f.declared, p);
    const std::uint64_t size = regular_file_size(p);  // a folder, device or FIFO refused as before
    if (size > bound) {
      f.too_large = "buffer file too large: '" + printable(p) + "' has " + std::to_string(size) +
                    " bytes, more than " + why + "; it was not read";
      if (err) *err += f.too_large;
      return false;
    }
    const std::string b = read_regular_file(p, bound);
    out->assign(b.begin(), b.end());
    return true;
  } catch (const std::exception& e) {
    if (const auto* failure = dynamic_cast<const FileSystemFailure*>(&e))
      static_cast<ExternalFiles*>(files)->refused.push_back(*failure);
    if (err) *err += e.what();
    return false;
  }
}

/// The refusal that ended a load whose error ends with `last_line`: a buffer tinygltf did not
/// find ("File not found : URI", looked for first in `dir`, the name the glTF gives it) or
/// could not read ("File read error : PATH : ..."). A buffer ends the load at once, so its
/// line is the last; an image missing earlier only warns, and is never the one returned.
const FileSystemFailure* buffer_refusal(const ExternalFiles& files, const std::string& dir,
                                        const std::string& last_line) {
  static const std::string NOT_FOUND = "File not found : ", READ_ERROR = "File read error : ";
  std::string path;
  if (last_line.rfind(NOT_FOUND, 0) == 0) {
    const std::string uri = last_line.substr(NOT_FOUND.size());
    // tinygltf's JoinPath: the folder, a '/' unless it ends with one, the URI.
    path = dir.empty() ? uri : dir + (dir.back() == '/' ? "" : "/") + uri;
  } else if (last_line.rfind(READ_ERROR, 0) == 0) {
    const std::size_t end = last_line.find(" : ", READ_ERROR.size());
    if (end == std::string::npos) return nullptr;
    path = last_line.substr(READ_ERROR.size(), end - READ_ERROR.size());
  } else {
    return nullptr;
  }
  for (auto it = files.refused.rbegin(); it != files.refused.rend(); ++it)
    if (it->path() == path) return &*it;
  return nullptr;
}
bool no_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is not done by the reader";
  return false;
}
/// Images are never decoded. One in a buffer view stays there; one in a data URI (tinygltf
/// decodes the base64 and drops the URI) keeps its encoded bytes in `image`, so that the glTF
/// document can write it back (gltf_document.cpp).
bool skip_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                const unsigned char* bytes, int size, void*) {
  if (image->bufferView < 0 && bytes && size > 0) image->image.assign(bytes, bytes + size);
  return true;
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
    const std::vector<std::size_t>& corners = read[p].corners;
    soup.faces.reserve(soup.faces.size() + corners.size() / 3);
    for (std::size_t t = 0; t + 2 < corners.size(); t += 3) {
      const std::size_t a = vertex_of(corners[t]), b = vertex_of(corners[t + 1]),
                        c = vertex_of(corners[t + 2]);
      soup.faces.push_back(mirrored ? std::vector<std::size_t>{a, c, b}
                                    : std::vector<std::size_t>{a, b, c});
      soup.face_drawn.push_back(first_drawn + p);
    }
  }
}

}  // namespace

tinygltf::Model gltf::load_model(const std::string& path, const std::string& bytes,
                                 std::vector<std::string>* looked_up) {
  if (bytes.size() > std::numeric_limits<unsigned int>::max())
    fail(path, "too large", "a glTF file holds at most 4 GiB");
  const bool binary = bytes.compare(0, 4, "glTF") == 0;
  if (binary) check_glb_container(path, bytes);
  // Before any recursive parser sees it: the JSON's depth, then what tinygltf reads leniently.
  const std::size_t json_at = binary ? 20 : 0;
  const std::size_t json_size = binary ? le32(bytes, 12) : bytes.size();
  ExternalFiles files{looked_up, {}, {}, {}};
  files.declared = gltf::check_top_level(path, bytes.data() + json_at, json_size, json_at);
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  loader.SetFsCallbacks(
      tinygltf::FsCallbacks{file_exists, same_path, read_buffer_file, no_write, &files});
  tinygltf::Model m;
  std::string err, warn;
  const std::string dir = std::filesystem::path(path).parent_path().string();
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const auto n = static_cast<unsigned int>(bytes.size());
  bool ok = false;
  try {
    ok = binary ? loader.LoadBinaryFromMemory(&m, &err, &warn, data, n, dir)
                : loader.LoadASCIIFromString(&m, &err, &warn, bytes.data(), n, dir);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {  // nlohmann-json's, for a document it cannot parse
    err += e.what();
  }
  if (!ok && !files.too_large.empty()) throw InputError(path + ": " + files.too_large);
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    const std::size_t last_line = err.rfind('\n');
    const FileSystemFailure* buffer =
        buffer_refusal(files, dir, err.substr(last_line == std::string::npos ? 0 : last_line + 1));
    for (char& c : err)
      if (c == '\n') c = ';';
    const std::string message = path + ": " + (binary ? "cannot read .glb" : "cannot read .gltf") +
                                ": " + (err.empty() ? "tinygltf refused it" : "tinygltf: " + err);
    if (buffer) throw InputFileError(message, buffer->error_number(), buffer->path());
    throw InputError(message);
  }
  return m;
}

GltfSoup gltf::scene_soup(const std::string& path, const tinygltf::Model& m,
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
  return gltf::scene_soup(path, gltf::load_model(path, bytes));
}

}  // namespace shellcontract
