// glTF 2.0 files written byte by byte for the reader's tests (no tinygltf: the reader's own
// parser must not also be the one that wrote what it reads). One mesh of one or more triangle
// primitives, drawn by one node, in a .glb (JSON and BIN chunks) or a .gltf whose buffer is a
// base64 data URI.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace shellcontract::test {

struct GltfPrimitive {
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<float, 2>> texcoords;  ///< TEXCOORD_0 when not empty
  std::vector<std::array<float, 3>> normals;    ///< NORMAL when not empty
  std::vector<std::uint32_t> indices;           ///< none: an unindexed triangle list
  int index_type = 5125;                        ///< 5121 unsigned byte, 5123 short, 5125 int
  int mode = -1;                                ///< -1: no "mode" (triangles)
};

struct GltfScene {
  std::vector<GltfPrimitive> primitives;
  std::string node_transform;  ///< JSON members of the node, e.g. "\"translation\":[1,0,0]"
  std::string extra;  ///< JSON members at the top level, e.g. "\"extensionsRequired\":[...]"
  std::string
      png;  ///< not empty: material 0, textured with this image (a buffer view), on every primitive
};

/// The JSON and the binary buffer of the scene (the buffer's byteLength is the BIN's size).
struct GltfParts {
  std::string json;
  std::string bin;
};

inline void gltf_put(std::string& bin, const void* p, std::size_t n) {
  bin.append(static_cast<const char*>(p), n);
}
inline void gltf_align4(std::string& bin) {
  while (bin.size() % 4) bin += '\0';
}

inline GltfParts gltf_parts(const GltfScene& s) {
  std::string bin, views, accessors, prims;
  int next = 0;  // accessor and buffer view k go together
  const auto add = [&](std::size_t offset, std::size_t length, std::size_t count, int component,
                       const char* type, const std::string& minmax) {
    views += std::string(views.empty() ? "" : ",") +
             "{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) +
             ",\"byteLength\":" + std::to_string(length) + "}";
    accessors +=
        std::string(accessors.empty() ? "" : ",") + "{\"bufferView\":" + std::to_string(next) +
        ",\"componentType\":" + std::to_string(component) + ",\"count\":" + std::to_string(count) +
        ",\"type\":\"" + type + "\"" + minmax + "}";
    return next++;
  };
  for (const GltfPrimitive& p : s.primitives) {
    std::size_t at = bin.size();
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (const auto& x : p.positions) {
      gltf_put(bin, x.data(), 12);
      for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], x[c]), hi[c] = std::max(hi[c], x[c]);
    }
    const auto num = [](float f) { return std::to_string(f); };
    const int pos = add(at, bin.size() - at, p.positions.size(), 5126, "VEC3",
                        ",\"min\":[" + num(lo[0]) + "," + num(lo[1]) + "," + num(lo[2]) +
                            "],\"max\":[" + num(hi[0]) + "," + num(hi[1]) + "," + num(hi[2]) + "]");
    std::string prim = "{\"attributes\":{\"POSITION\":" + std::to_string(pos);
    if (!p.texcoords.empty()) {
      at = bin.size();
      for (const auto& t : p.texcoords) gltf_put(bin, t.data(), 8);
      prim += ",\"TEXCOORD_0\":" +
              std::to_string(add(at, bin.size() - at, p.texcoords.size(), 5126, "VEC2", ""));
    }
    if (!p.normals.empty()) {
      at = bin.size();
      for (const auto& n : p.normals) gltf_put(bin, n.data(), 12);
      prim += ",\"NORMAL\":" +
              std::to_string(add(at, bin.size() - at, p.normals.size(), 5126, "VEC3", ""));
    }
    prim += "}";
    if (!s.png.empty()) prim += ",\"material\":0";
    if (!p.indices.empty()) {
      at = bin.size();
      const std::size_t size = p.index_type == 5121 ? 1 : p.index_type == 5123 ? 2 : 4;
      for (const std::uint32_t i : p.indices) gltf_put(bin, &i, size);  // little-endian hosts
      const int idx = add(at, bin.size() - at, p.indices.size(), p.index_type, "SCALAR", "");
      gltf_align4(bin);
      prim += ",\"indices\":" + std::to_string(idx);
    }
    if (p.mode >= 0) prim += ",\"mode\":" + std::to_string(p.mode);
    prims += (prims.empty() ? "" : ",") + prim + "}";
  }
  std::string material;
  if (!s.png.empty()) {
    const std::size_t at = bin.size();
    bin += s.png;
    views += ",{\"buffer\":0,\"byteOffset\":" + std::to_string(at) +
             ",\"byteLength\":" + std::to_string(s.png.size()) + "}";
    material =
        ",\"materials\":[{\"name\":\"skin\",\"pbrMetallicRoughness\":{\"baseColorTexture\":{"
        "\"index\":0},\"metallicFactor\":0}}]"
        ",\"textures\":[{\"source\":0}],\"images\":[{\"bufferView\":" +
        std::to_string(next) + ",\"mimeType\":\"image/png\"}]";
    gltf_align4(bin);
  }
  GltfParts out;
  out.bin = bin;
  out.json =
      "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{"
      "\"mesh\":0" +
      std::string(s.node_transform.empty() ? "" : "," + s.node_transform) +
      "}],\"meshes\":[{\"primitives\":[" + prims + "]}],\"accessors\":[" + accessors +
      "],\"bufferViews\":[" + views +
      "],\"buffers\":[{\"byteLength\":" + std::to_string(bin.size()) + "%URI%}]" + material +
      (s.extra.empty() ? "" : "," + s.extra) + "}";
  return out;
}

inline void gltf_put32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xFF);
}

inline std::string replace_uri(std::string json, const std::string& uri) {
  const std::size_t at = json.find("%URI%");
  return json.replace(at, 5, uri.empty() ? "" : ",\"uri\":\"" + uri + "\"");
}

/// The .glb of the parts: header, JSON chunk (space-padded), BIN chunk (zero-padded).
inline std::string glb_bytes(const GltfParts& parts) {
  std::string json = replace_uri(parts.json, "");
  while (json.size() % 4) json += ' ';
  std::string bin = parts.bin;
  gltf_align4(bin);
  std::string out = "glTF";
  gltf_put32(out, 2);
  gltf_put32(out,
             static_cast<std::uint32_t>(12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size())));
  gltf_put32(out, static_cast<std::uint32_t>(json.size()));
  gltf_put32(out, 0x4E4F534Au);
  out += json;
  if (!bin.empty()) {
    gltf_put32(out, static_cast<std::uint32_t>(bin.size()));
    gltf_put32(out, 0x004E4942u);
    out += bin;
  }
  return out;
}

inline std::string base64(const std::string& in) {
  static const char* const A = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) |
                       (static_cast<unsigned char>(in[i + 1]) << 8) |
                       static_cast<unsigned char>(in[i + 2]);
    for (int k = 3; k >= 0; --k) out += A[(v >> (6 * k)) & 63];
  }
  if (i + 1 == in.size()) {
    const unsigned v = static_cast<unsigned char>(in[i]) << 16;
    out += A[(v >> 18) & 63], out += A[(v >> 12) & 63], out += "==";
  } else if (i + 2 == in.size()) {
    const unsigned v =
        (static_cast<unsigned char>(in[i]) << 16) | (static_cast<unsigned char>(in[i + 1]) << 8);
    out += A[(v >> 18) & 63], out += A[(v >> 12) & 63], out += A[(v >> 6) & 63], out += '=';
  }
  return out;
}

/// The .gltf of the parts, its buffer a data URI; or (external_bin) named `external_bin`, which
/// the caller writes beside it.
inline std::string gltf_text(const GltfParts& parts, const std::string& external_bin = "") {
  return replace_uri(parts.json, external_bin.empty()
                                     ? "data:application/octet-stream;base64," + base64(parts.bin)
                                     : external_bin);
}

/// The octahedron of radius 1 at the origin, outward, indexed, with (`texcoords`) texture
/// coordinates and normals; `split_seam`: vertex 0 (+x) has a
/// second copy (index 6) used by the faces on the -y side, with its own texture coordinate, as
/// exporters split a vertex on a UV seam.
inline GltfPrimitive octahedron_primitive(bool split_seam, bool texcoords) {
  GltfPrimitive p;
  p.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  p.indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  if (texcoords)
    p.texcoords = {{0.0f, 0.5f},   {0.5f, 0.5f},  {0.25f, 0.25f},
                   {0.75f, 0.25f}, {0.25f, 0.0f}, {0.75f, 1.0f}};
  if (texcoords) p.normals = p.positions;  // unit already: the vertex normals of the octahedron
  if (split_seam) {
    p.positions.push_back({1, 0, 0});
    if (texcoords) p.texcoords.push_back({1.0f, 0.5f}), p.normals.push_back({1, 0, 0});
    p.indices[10] = 6;  // face 3 (3 0 4)
    p.indices[21] = 6;  // face 7 (0 3 5)
  }
  return p;
}

/// The four sides of the box [-1, 1]^3 as one smooth band, appended to `p`: corners 0-9 (bottom,
/// top, around the box; 8 and 9 repeat 0 and 1 with u = 1, a UV seam), each corner's normal the
/// horizontal diagonal through it, 8 triangles. Corner 8's normal is a float rounding off (an
/// exporter that normalized it again): seam copies must still be taken as one.
inline void add_smooth_band_with_seam(GltfPrimitive& p) {
  const float around[5][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {-1, -1}};
  for (int k = 0; k < 5; ++k)
    for (const float z : {-1.0f, 1.0f}) {
      const float dx = around[k][0], dy = around[k][1];
      p.positions.push_back({dx, dy, z});
      p.normals.push_back({dx / std::sqrt(2.0f), dy / std::sqrt(2.0f), 0.0f});
      p.texcoords.push_back({static_cast<float>(k) / 4.0f, z < 0 ? 1.0f : 0.0f});
    }
  for (std::uint32_t k = 0; k < 4; ++k) {  // bottom, bottom next, top next, top
    const std::uint32_t b0 = 2 * k, t0 = b0 + 1, b1 = b0 + 2, t1 = b0 + 3;
    for (const std::uint32_t i : {b0, b1, t1, b0, t1, t0}) p.indices.push_back(i);
  }
  p.normals[8][0] = std::nextafter(p.normals[8][0], 0.0f);
}

}  // namespace shellcontract::test
