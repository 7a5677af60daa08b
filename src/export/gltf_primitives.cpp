#include "export/gltf_primitives.hpp"

#include <algorithm>
#include <cstddef>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace shellcontract::gltf {

namespace {

/// The material of face f: a.face_material's, or material 0 for all when it is empty.
int material_of(const GltfAnimation& a, Eigen::Index f) {
  if (a.face_material.empty()) return a.materials.empty() ? -1 : 0;
  return a.face_material[static_cast<std::size_t>(f)];
}

}  // namespace

void check_materials(const GltfAnimation& a) {
  if (!a.face_material.empty() &&
      a.face_material.size() != static_cast<std::size_t>(a.faces.rows()))
    throw std::invalid_argument("write_gltf_animation: " + std::to_string(a.face_material.size()) +
                                " face materials for " + std::to_string(a.faces.rows()) + " faces");
  for (const int m : a.face_material)
    if (m < -1 || m >= static_cast<int>(a.materials.size()))
      throw std::invalid_argument("write_gltf_animation: a face's material index " +
                                  std::to_string(m) + " is out of range (" +
                                  std::to_string(a.materials.size()) + " materials)");
  for (const GltfMaterial& m : a.materials) {
    if (m.source_material >= 0 &&
        (!a.material_source ||
         static_cast<std::size_t>(m.source_material) >= a.material_source->materials.size()))
      throw std::invalid_argument("write_gltf_animation: a source material index is out of range");
    if (!m.image.empty()) {
      if (a.face_uv.rows() == 0)
        throw std::invalid_argument("write_gltf_animation: a material image without texture coordinates");
      if (m.image_mime_type.empty())
        throw std::invalid_argument("write_gltf_animation: a material image without a mime type");
    }
    for (const double c : m.base_colour)
      if (!(c >= 0.0 && c <= 1.0))
        throw std::invalid_argument("write_gltf_animation: a base colour component outside [0, 1]");
  }
}

std::vector<PrimitiveFaces> faces_by_material(const GltfAnimation& a, const Faces& faces) {
  // Two passes (count, then fill) so that each primitive's faces are sized once.
  std::map<int, std::size_t> slot;  // material -> primitive
  std::vector<PrimitiveFaces> out;
  std::vector<Eigen::Index> count;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const int m = material_of(a, f);
    const auto [it, added] = slot.emplace(m, out.size());
    if (added) {
      out.push_back({m, Faces()});
      count.push_back(0);
    }
    ++count[it->second];
  }
  for (std::size_t p = 0; p < out.size(); ++p) out[p].faces.resize(count[p], 3);
  std::vector<Eigen::Index> filled(out.size(), 0);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const std::size_t p = slot.at(material_of(a, f));
    out[p].faces.row(filled[p]++) = faces.row(f);
  }
  return out;
}

std::vector<int> add_materials(tinygltf::Model& model, BufferBuilder& bb,
                               const std::vector<GltfMaterial>& materials,
                               const std::vector<PrimitiveFaces>& primitives) {
  std::vector<int> out;
  std::vector<std::pair<const GltfMaterial*, int>> textures;  // an image's first material, texture
  int sampler = -1;
  for (const PrimitiveFaces& p : primitives) {
    if (p.material < 0) {
      out.push_back(-1);
      continue;
    }
    const GltfMaterial& m = materials[static_cast<std::size_t>(p.material)];
    tinygltf::Material mat;
    mat.name = m.name;
    mat.pbrMetallicRoughness.baseColorFactor.assign(m.base_colour.begin(), m.base_colour.end());
    mat.pbrMetallicRoughness.metallicFactor = 0.0;
    if (m.base_colour[3] < 1.0) mat.alphaMode = "BLEND";
    if (!m.image.empty()) {
      // Two materials naming the same file (a character's body and head on one atlas) carry
      // the same bytes: embedded once, so the file and the GPU hold it once.
      int texture = -1;
      for (const auto& [first, index] : textures)
        if (first->image == m.image && first->image_mime_type == m.image_mime_type) texture = index;
      if (texture < 0) {
        tinygltf::Image image;
        image.name = m.name;
        image.mimeType = m.image_mime_type;
        image.bufferView = bb.add_view(m.image.data(), m.image.size(), 0);
        model.images.push_back(image);
        if (sampler < 0) {
          tinygltf::Sampler s;  // OBJ texture coordinates may leave [0, 1]: repeat, as OBJ viewers do
          s.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
          s.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
          s.wrapS = s.wrapT = TINYGLTF_TEXTURE_WRAP_REPEAT;
          model.samplers.push_back(s);
          sampler = static_cast<int>(model.samplers.size()) - 1;
        }
        tinygltf::Texture t;
        t.source = static_cast<int>(model.images.size()) - 1;
        t.sampler = sampler;
        model.textures.push_back(t);
        texture = static_cast<int>(model.textures.size()) - 1;
        textures.emplace_back(&m, texture);
      }
      mat.pbrMetallicRoughness.baseColorTexture.index = texture;
      mat.pbrMetallicRoughness.baseColorTexture.texCoord = 0;  // TEXCOORD_0
    }
    model.materials.push_back(mat);
    out.push_back(static_cast<int>(model.materials.size()) - 1);
  }
  return out;
}

std::size_t material_bytes(const std::vector<GltfMaterial>& materials) {
  // Each image once, as add_materials embeds it: the materials that share one count it once.
  std::size_t n = 0;
  std::vector<const ImageBytes*> counted;
  for (const GltfMaterial& m : materials) {
    if (m.image.empty()) continue;
    if (std::any_of(counted.begin(), counted.end(),
                    [&](const ImageBytes* c) { return *c == m.image; }))
      continue;
    counted.push_back(&m.image);
    n += m.image.size() + 3;
  }
  return n;
}

}  // namespace shellcontract::gltf
