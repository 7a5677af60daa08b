// The --gltf animation of a glTF input carries the input's materials, textures, samplers and
// images (docs/design/export.md, "Name and material"), one primitive per material, the images
// embedded; what it cannot carry is a warning naming it. Before: the animation had no material,
// texture or image at all (only TEXCOORD_0), without a word.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "export/gltf_reader.hpp"
#include "export_fixtures.hpp"
#include "support/cli_runner.hpp"
#include "support/gltf_files.hpp"
#include "support/textured_octahedron.hpp"

namespace shellcontract {
namespace {

using test::ScratchDir;

std::string write(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const std::size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? s : s.replace(at, from.size(), to);
}

/// The octahedron as two primitives (its top half and its bottom half, each with its own copy
/// of the vertices, as exporters split a mesh by material): material 0 "skin", textured with the
/// PNG through a sampler, and material 1 "spots", a base colour only.
test::GltfParts two_material_octahedron() {
  const test::GltfPrimitive whole = test::octahedron_primitive(false, true);
  test::GltfScene s;
  for (int half = 0; half < 2; ++half) {
    test::GltfPrimitive p = whole;
    p.indices.assign(whole.indices.begin() + 12 * half, whole.indices.begin() + 12 * (half + 1));
    s.primitives.push_back(p);
  }
  const auto& png = test::tiny_png();
  s.png.assign(png.begin(), png.end());
  test::GltfParts parts = test::gltf_parts(s);
  // The builder gives every primitive material 0: the second gets material 1.
  const std::size_t first = parts.json.find("\"material\":0");
  parts.json.replace(parts.json.find("\"material\":0", first + 1), 12, "\"material\":1");
  parts.json = replaced(parts.json, "\"metallicFactor\":0}}]",
                        "\"metallicFactor\":0}},{\"name\":\"spots\",\"pbrMetallicRoughness\":{"
                        "\"baseColorFactor\":[0.25,0.5,0.75,1]},\"doubleSided\":true}]");
  parts.json = replaced(parts.json, "\"textures\":[{\"source\":0}]",
                        "\"textures\":[{\"source\":0,\"sampler\":0}],\"samplers\":[{"
                        "\"magFilter\":9728,\"wrapS\":33071,\"wrapT\":33648}]");
  return parts;
}

/// The image's bytes as the .glb embeds them.
std::vector<unsigned char> image_bytes(const tinygltf::Model& m, std::size_t i) {
  const tinygltf::Image& image = m.images.at(i);
  if (image.bufferView < 0) return {};
  const auto& view = m.bufferViews.at(static_cast<std::size_t>(image.bufferView));
  const auto* b = m.buffers.at(0).data.data() + view.byteOffset;
  return {b, b + view.byteLength};
}

TEST(GltfInputMaterials, TheAnimationOfAGlbCarriesItsMaterialsTexturesSamplersAndImages) {
  ScratchDir dir("gltf_materials");
  const std::string in = write(dir.file("two.glb"), test::glb_bytes(two_material_octahedron()));
  const auto r = test::run_cli(
      {"run", in, "-o", dir.file("out.glb"), "-n", "4", "-q", "--gltf", dir.file("anim.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  const tinygltf::Model m = test::load_glb(dir.file("anim.glb"));

  ASSERT_EQ(m.materials.size(), 2u);
  EXPECT_EQ(m.materials[0].name, "skin");
  EXPECT_EQ(m.materials[0].pbrMetallicRoughness.baseColorTexture.index, 0);
  EXPECT_EQ(m.materials[0].pbrMetallicRoughness.metallicFactor, 0.0);
  EXPECT_EQ(m.materials[1].name, "spots");
  EXPECT_EQ(m.materials[1].pbrMetallicRoughness.baseColorFactor,
            (std::vector<double>{0.25, 0.5, 0.75, 1.0}));
  EXPECT_TRUE(m.materials[1].doubleSided);
  ASSERT_EQ(m.textures.size(), 1u);
  EXPECT_EQ(m.textures[0].source, 0);
  ASSERT_EQ(m.textures[0].sampler, 0);
  ASSERT_EQ(m.samplers.size(), 1u);
  EXPECT_EQ(m.samplers[0].magFilter, 9728);
  EXPECT_EQ(m.samplers[0].wrapS, 33071);
  EXPECT_EQ(m.samplers[0].wrapT, 33648);
  ASSERT_EQ(m.images.size(), 1u);
  EXPECT_EQ(m.images[0].uri, "");
  EXPECT_EQ(m.images[0].mimeType, "image/png");
  EXPECT_EQ(image_bytes(m, 0), test::tiny_png());

  // One primitive per material, each with its half's four triangles, on TEXCOORD_0.
  const auto& prims = m.meshes.at(0).primitives;
  ASSERT_EQ(prims.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(prims[static_cast<std::size_t>(k)].material, k);
    EXPECT_EQ(test::read_indices(m, prims[static_cast<std::size_t>(k)].indices).size(), 12u);
    EXPECT_TRUE(prims[static_cast<std::size_t>(k)].attributes.count("TEXCOORD_0"));
  }
}

TEST(GltfInputMaterials, AGltfsImageFileIsEmbeddedAndWhatCannotBeCarriedIsAWarning) {
  ScratchDir dir("gltf_materials_files");
  std::filesystem::create_directories(dir.file("in"));
  std::filesystem::create_directories(dir.file("out"));
  test::GltfParts parts = two_material_octahedron();
  const std::size_t image = parts.json.find("\"images\":[");
  parts.json.replace(image, parts.json.find(']', image) + 1 - image,
                     "\"images\":[{\"uri\":\"skin%20file.png\",\"name\":\"skin image\"}]");
  const std::string in = write(dir.file("in/two.gltf"), test::gltf_text(parts));
  const auto& png = test::tiny_png();
  write(dir.file("in/skin file.png"), std::string(png.begin(), png.end()));
  auto r = test::run_cli({"run", in, "-o", dir.file("out/out.off"), "-n", "3", "-q", "--gltf",
                          dir.file("out/anim.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // No warning but the -o .off result's, which drops the glTF's attributes (run_document.cpp).
  const std::string dropped =
      "warning: the result is written without the input's attributes: it is a .off file";
  const std::size_t at = r.output.find(dropped);
  ASSERT_NE(at, std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("warning"), at) << r.output;
  EXPECT_EQ(r.output.find("warning", at + dropped.size()), std::string::npos) << r.output;
  tinygltf::Model m = test::load_glb(dir.file("out/anim.glb"));
  ASSERT_EQ(m.images.size(), 1u);
  EXPECT_EQ(m.images[0].uri, "");  // in the .glb: it holds in any folder
  EXPECT_EQ(m.images[0].name, "skin image");
  EXPECT_EQ(image_bytes(m, 0), test::tiny_png());

  // The image file missing, and a texture on TEXCOORD_1 (the animation has only TEXCOORD_0):
  // still exit 0, each one a warning naming it.
  std::filesystem::remove(dir.file("in/skin file.png"));
  parts.json = replaced(parts.json, "\"metallicFactor\":0}},{\"name\":\"spots\"",
                        "\"metallicFactor\":0},\"emissiveTexture\":{\"index\":0,\"texCoord\":1}},"
                        "{\"name\":\"spots\"");
  write(in, test::gltf_text(parts));
  r = test::run_cli({"run", in, "-o", dir.file("out/out.off"), "-n", "3", "-q", "--gltf",
                     dir.file("out/anim.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: " + in + ": images[0] ('skin image') not embedded"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("it names 'skin%20file.png' as the input does"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("material 0 ('skin'): its emissive texture uses TEXCOORD_1"),
            std::string::npos)
      << r.output;
  m = test::load_glb(dir.file("out/anim.glb"));
  ASSERT_EQ(m.materials.size(), 2u);
  EXPECT_EQ(m.materials[0].emissiveTexture.index, -1);
  EXPECT_EQ(m.materials[0].pbrMetallicRoughness.baseColorTexture.index, 0);
}

}  // namespace
}  // namespace shellcontract
