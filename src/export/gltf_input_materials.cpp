#include "export/gltf_input_materials.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <set>
#include <utility>

#include "mesh/file_safety.hpp"
#include "mesh/input_dependencies.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract::gltf {
namespace {

namespace fs = std::filesystem;

/// As an OBJ's map_Kd (gltf_material.cpp): a .glb's chunk lengths are 32-bit.
constexpr std::uint64_t MAX_IMAGE_BYTES = std::uint64_t{1} << 30;

/// The mime type of an image file the spec or a common extension allows: by its first bytes
/// (PNG, JPEG), else by its name (KHR_texture_basisu's .ktx2, EXT_texture_webp's .webp).
std::string mime_type_of(const std::vector<unsigned char>& bytes, const std::string& name) {
  std::string mime = image_mime_type(bytes);
  if (!mime.empty()) return mime;
  std::string ext = fs::path(name).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".webp") return "image/webp";
  if (ext == ".ktx2") return "image/ktx2";
  return {};
}

/// The image's bytes into image.image (why not, in `why`): from its buffer view, its data URI
/// (the reader already decoded those into image.image) or the file its URI names beside the input.
bool resolve_image(const tinygltf::Model& in, const std::string& input, tinygltf::Image& image,
                   std::string& why) {
  const auto fail = [&](const std::string& reason) {
    why = reason;
    return false;
  };
  if (image.bufferView >= 0) {
    const auto v = static_cast<std::size_t>(image.bufferView);
    if (v >= in.bufferViews.size()) return fail("its bufferView does not exist");
    const tinygltf::BufferView& view = in.bufferViews[v];
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= in.buffers.size())
      return fail("its bufferView's buffer does not exist");
    const std::vector<unsigned char>& data = in.buffers[static_cast<std::size_t>(view.buffer)].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
      return fail("its bufferView lies outside its buffer");
    const auto* b = data.data() + view.byteOffset;
    image.image.assign(b, b + view.byteLength);
    image.bufferView = -1;
  } else if (image.image.empty()) {
    if (image.uri.empty()) return fail("it has neither a bufferView nor a uri");
    const fs::path rel(percent_decoded(image.uri));
    const std::string path =
        rel.is_absolute() ? rel.string() : (fs::path(input).parent_path() / rel).string();
    try {
      const std::string bytes = read_regular_file(path, MAX_IMAGE_BYTES);
      image.image.assign(bytes.begin(), bytes.end());
    } catch (const InputError& e) {
      return fail(e.what());
    }
  }
  if (image.mimeType.empty()) image.mimeType = mime_type_of(image.image, image.uri);
  if (image.mimeType.empty()) {
    image.image.clear();
    return fail("its type is none that glTF names (PNG, JPEG, KTX2, WebP)");
  }
  image.uri.clear();
  return true;
}

/// Leaves out a texture reference of the material that the animation cannot draw: one on another
/// set of texture coordinates than TEXCOORD_0, the only set the animation has, or any when the
/// mesh has none.
void check_texture(int& index, int tex_coord, bool has_texcoords, const std::string& material,
                   const char* slot, const std::string& input, std::vector<std::string>& warnings) {
  if (index < 0) return;
  if (has_texcoords && tex_coord == 0) return;
  warnings.push_back(input + ": material " + material + ": its " + slot + " texture " +
                     (has_texcoords ? "uses TEXCOORD_" + std::to_string(tex_coord) +
                                          ", which the glTF animation does not have"
                                    : std::string("needs texture coordinates, which not every "
                                                  "face of the mesh has")) +
                     ": left out of the animation's material");
  index = -1;
}

/// The names of the extensions an element uses, into `used`.
void collect(const tinygltf::ExtensionMap& e, std::set<std::string>& used) {
  for (const auto& [name, value] : e) used.insert(name);
}

/// An empty extras object is left out: tinygltf's writer writes it as null, which no reader
/// accepts (gltf_json.hpp).
void drop_empty_extras(tinygltf::Value& extras) {
  if (extras.IsObject() && extras.Keys().empty()) extras = tinygltf::Value();
}

}  // namespace

GltfFaceMaterials gltf_input_materials(const FaceMaterials& materials, bool has_texcoords,
                                       std::vector<std::string>& warnings) {
  const tinygltf::Model& in = *materials.gltf;
  const std::string& input = materials.source;
  auto source = std::make_shared<tinygltf::Model>();
  source->materials = in.materials;
  source->textures = in.textures;
  source->samplers = in.samplers;
  source->images = in.images;
  std::set<std::string> used;
  for (std::size_t i = 0; i < source->materials.size(); ++i) {
    tinygltf::Material& m = source->materials[i];
    const std::string name = std::to_string(i) + (m.name.empty() ? "" : " ('" + m.name + "')");
    tinygltf::PbrMetallicRoughness& pbr = m.pbrMetallicRoughness;
    check_texture(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, has_texcoords, name,
                  "base colour", input, warnings);
    check_texture(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                  has_texcoords, name, "metallic-roughness", input, warnings);
    check_texture(m.normalTexture.index, m.normalTexture.texCoord, has_texcoords, name, "normal",
                  input, warnings);
    check_texture(m.occlusionTexture.index, m.occlusionTexture.texCoord, has_texcoords, name,
                  "occlusion", input, warnings);
    check_texture(m.emissiveTexture.index, m.emissiveTexture.texCoord, has_texcoords, name,
                  "emissive", input, warnings);
    collect(m.extensions, used);
    for (const tinygltf::ExtensionMap* e :
         {&pbr.extensions, &pbr.baseColorTexture.extensions,
          &pbr.metallicRoughnessTexture.extensions, &m.normalTexture.extensions,
          &m.occlusionTexture.extensions, &m.emissiveTexture.extensions})
      collect(*e, used);
    drop_empty_extras(m.extras);
  }
  for (tinygltf::Texture& t : source->textures) {
    collect(t.extensions, used);
    drop_empty_extras(t.extras);
  }
  for (tinygltf::Sampler& s : source->samplers) {
    collect(s.extensions, used);
    drop_empty_extras(s.extras);
  }
  for (std::size_t i = 0; i < source->images.size(); ++i) {
    tinygltf::Image& image = source->images[i];
    collect(image.extensions, used);
    drop_empty_extras(image.extras);
    std::string why;
    if (!resolve_image(in, input, image, why))
      warnings.push_back(input + ": images[" + std::to_string(i) + "]" +
                         (image.name.empty() ? "" : " ('" + image.name + "')") +
                         " not embedded in the glTF animation (" + why + ")" +
                         (image.uri.empty() ? ": its textures show nothing"
                                            : ": it names '" + image.uri + "' as the input does"));
  }
  // The extensions the carried elements use are declared as the input declares them.
  for (const std::string& e : in.extensionsUsed)
    if (used.count(e)) source->extensionsUsed.push_back(e);
  for (const std::string& e : in.extensionsRequired)
    if (used.count(e)) source->extensionsRequired.push_back(e);

  GltfFaceMaterials out;
  for (std::size_t i = 0; i < in.materials.size(); ++i) {
    GltfMaterial g;
    g.name = in.materials[i].name;
    g.source_material = static_cast<int>(i);
    out.materials.push_back(std::move(g));
  }
  out.face_material = materials.face_material;
  out.source = std::move(source);
  return out;
}

void add_source_materials(tinygltf::Model& model, BufferBuilder& bb,
                          const tinygltf::Model& source) {
  model.materials = source.materials;
  model.textures = source.textures;
  model.samplers = source.samplers;
  for (tinygltf::Image image : source.images) {
    if (!image.image.empty()) {
      image.bufferView = bb.add_view(image.image.data(), image.image.size(), 0);
      image.image.clear();
    }
    model.images.push_back(std::move(image));
  }
  model.extensionsUsed = source.extensionsUsed;
  model.extensionsRequired = source.extensionsRequired;
}

std::size_t source_material_bytes(const tinygltf::Model* source) {
  std::size_t n = 0;
  if (source)
    for (const tinygltf::Image& image : source->images) n += image.image.size() + 3;
  return n;
}

}  // namespace shellcontract::gltf
