// The glTF of a PLY that names its textures in its header (docs/design/attributes.md, "Textures
// of a PLY"): MeshLab's `comment TextureFile <path>` lines, a face's `texnumber` choosing one.
// Each texture a face uses is a material with its image embedded, sampled with TEXCOORD_0; a
// texture that cannot be used is a warning naming the PLY and the header line, never a failed
// run. Before, the texture coordinates reached the .glb but the image did not.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "export_fixtures.hpp"
#include "gltf_reader.hpp"
#include "support/cli_runner.hpp"
#include "support/textured_octahedron.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

// The octahedron of textured_octahedron.hpp: faces 0-3 above z = 0, faces 4-7 below.
const double OCTA[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
const int OCTA_FACES[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                              {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
const double OCTA_UV[6][2] = {{0, 0.5}, {1, 0.5}, {0.5, 0.75}, {0.5, 0.25}, {0.25, 1}, {0.75, 0}};

/// The header line of the first TextureFile comment (1-based) in octahedron_ply's files.
constexpr int FIRST_TEXTURE_LINE = 4;

/// An ASCII PLY of the octahedron with (`texcoords`) MeshLab's per-corner `texcoord` lists and
/// one `comment TextureFile` line per texture (from line 4 on); with `texnumber`, the upper
/// faces take texture 0 and the lower ones texture 1.
std::string octahedron_ply(const std::vector<std::string>& textures, bool texnumber,
                           bool texcoords = true) {
  std::ostringstream o;
  o << "ply\nformat ascii 1.0\ncomment written by test_gltf_ply_texture.cpp\n";
  for (const std::string& t : textures) o << "comment TextureFile " << t << '\n';
  o << "element vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 8\nproperty list uchar int vertex_indices\n"
    << (texcoords ? "property list uchar float texcoord\n" : "")
    << (texnumber ? "property int texnumber\n" : "") << "end_header\n";
  for (const auto& v : OCTA) o << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
  for (int f = 0; f < 8; ++f) {
    o << "3 " << OCTA_FACES[f][0] << ' ' << OCTA_FACES[f][1] << ' ' << OCTA_FACES[f][2];
    if (texcoords) o << " 6";
    for (const int v : OCTA_FACES[f])
      if (texcoords) o << ' ' << OCTA_UV[v][0] << ' ' << OCTA_UV[v][1];
    if (texnumber) o << ' ' << (f < 4 ? 0 : 1);
    o << '\n';
  }
  return o.str();
}

void write_bytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
}

test::RunResult run_to_glb(const std::string& input, const test::ScratchDir& dir) {
  return test::run_cli(
      {"run", input, "-o", dir.file("out.ply"), "-n", "4", "-q", "--gltf", dir.file("run.glb")});
}

/// The bytes of material `mat`'s base colour image (empty when it has none).
std::vector<unsigned char> image_bytes(const tinygltf::Model& m, const tinygltf::Material& mat) {
  const int t = mat.pbrMetallicRoughness.baseColorTexture.index;
  if (t < 0) return {};
  const tinygltf::Texture& tex = m.textures.at(static_cast<std::size_t>(t));
  const tinygltf::Image& img = m.images.at(static_cast<std::size_t>(tex.source));
  const tinygltf::BufferView& view = m.bufferViews.at(static_cast<std::size_t>(img.bufferView));
  const auto* b = m.buffers.at(static_cast<std::size_t>(view.buffer)).data.data() + view.byteOffset;
  return std::vector<unsigned char>(b, b + view.byteLength);
}

TEST(GltfPlyTexture, ATextureFileCommentIsEmbeddedAsTheMaterialsImage) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("ply_texture");
  // A name with spaces: the rest of the comment's line is the path.
  std::ofstream(dir.file("scan.ply")) << octahedron_ply({"my scan.png"}, false);
  write_bytes(dir.file("my scan.png"), test::tiny_png());
  const auto r = run_to_glb(dir.file("scan.ply"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;

  const tinygltf::Model m = test::load_glb(dir.file("run.glb"));
  ASSERT_EQ(m.meshes.size(), 1u);
  EXPECT_EQ(m.meshes[0].name, "scan");
  ASSERT_EQ(m.meshes[0].primitives.size(), 1u);
  const tinygltf::Primitive& p = m.meshes[0].primitives[0];
  EXPECT_TRUE(p.attributes.count("TEXCOORD_0"));
  ASSERT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(p.material, 0);
  const tinygltf::Material& mat = m.materials[0];
  EXPECT_EQ(mat.name, "my scan.png");
  EXPECT_EQ(mat.pbrMetallicRoughness.baseColorFactor, (std::vector<double>{1.0, 1.0, 1.0, 1.0}));
  EXPECT_EQ(mat.pbrMetallicRoughness.baseColorTexture.texCoord, 0);
  ASSERT_GE(mat.pbrMetallicRoughness.baseColorTexture.index, 0);
  EXPECT_EQ(m.images.at(0).mimeType, "image/png");
  EXPECT_EQ(image_bytes(m, mat), test::tiny_png());
  // The PLY itself is written back with its comments as read.
  std::ifstream out(dir.file("out.ply"));
  const std::string text((std::istreambuf_iterator<char>(out)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("comment TextureFile my scan.png\n"), std::string::npos) << text;
}

TEST(GltfPlyTexture, TexnumberSplitsTheFacesBetweenTwoTextures) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("ply_texnumber");
  fs::create_directory(dir.file("maps"));
  std::ofstream(dir.file("scan.ply")) << octahedron_ply({"maps/top.png", "maps/bottom.png"}, true);
  std::vector<unsigned char> bottom = test::tiny_png();
  bottom.push_back(0);  // other bytes, still a PNG by its signature
  write_bytes(dir.file("maps/top.png"), test::tiny_png());
  write_bytes(dir.file("maps/bottom.png"), bottom);
  const auto r = run_to_glb(dir.file("scan.ply"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;

  const tinygltf::Model m = test::load_glb(dir.file("run.glb"));
  ASSERT_EQ(m.materials.size(), 2u);
  EXPECT_EQ(m.materials[0].name, "maps/top.png");
  EXPECT_EQ(m.materials[1].name, "maps/bottom.png");
  EXPECT_EQ(image_bytes(m, m.materials[0]), test::tiny_png());
  EXPECT_EQ(image_bytes(m, m.materials[1]), bottom);
  const tinygltf::Mesh& mesh = m.meshes.at(0);
  ASSERT_EQ(mesh.primitives.size(), 2u);
  std::array<bool, 2> seen{false, false};
  for (const tinygltf::Primitive& p : mesh.primitives) {
    ASSERT_TRUE(p.material == 0 || p.material == 1) << p.material;
    seen[static_cast<std::size_t>(p.material)] = true;
    // Its faces: the four above z = 0 for the first texture, the four below for the second.
    const test::Floats x = test::read_positions(m, p.attributes.at("POSITION"));
    const std::vector<std::uint32_t> idx = test::read_indices(m, p.indices);
    ASSERT_EQ(idx.size(), 12u) << "material " << p.material;
    for (std::size_t f = 0; f < 4; ++f) {
      float z = 0;
      for (std::size_t k = 0; k < 3; ++k) z += x(static_cast<Eigen::Index>(idx[3 * f + k]), 2);
      EXPECT_EQ(z > 0, p.material == 0) << "material " << p.material << ", face " << f;
    }
  }
  EXPECT_TRUE(seen[0] && seen[1]);
}

TEST(GltfPlyTexture, AMissingTextureFileWarnsWithThePlyAndLineAndTheRunGoesOn) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("ply_texture_missing");
  std::ofstream(dir.file("scan.ply")) << octahedron_ply({"gone.png"}, false);
  const auto r = run_to_glb(dir.file("scan.ply"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: " + dir.file("scan.ply") + ": line " +
                          std::to_string(FIRST_TEXTURE_LINE) + ": TextureFile '" +
                          dir.file("gone.png") + "' not found"),
            std::string::npos)
      << r.output;

  const tinygltf::Model m = test::load_glb(dir.file("run.glb"));
  ASSERT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(m.materials[0].pbrMetallicRoughness.baseColorTexture.index, -1);
  EXPECT_TRUE(m.images.empty());
  EXPECT_TRUE(m.textures.empty());
  EXPECT_TRUE(m.meshes.at(0).primitives.at(0).attributes.count("TEXCOORD_0"));
}

/// How often `what` occurs in `text`.
std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(GltfPlyTexture, AMissingTextureFileIsWarnedOncePerRun) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  // The frames and the result in other folders than the input: each file written from the PLY
  // document would have its TextureFile path rewritten, and finds it names no file.
  test::ScratchDir dir("ply_texture_warned_once");
  fs::create_directory(dir.file("in"));
  fs::create_directory(dir.file("out"));
  const std::string input = dir.file("in/scan.ply");
  std::ofstream(input) << octahedron_ply({"gone.png"}, false);
  const auto r =
      test::run_cli({"run", input, "-o", dir.file("out/out.ply"), "-n", "3", "-q", "--export-dir",
                     dir.file("frames"), "--export-every", "1", "--gltf", dir.file("out/run.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir.file("frames/out_3.ply"))) << r.output;
  const std::string line =
      input + ": line " + std::to_string(FIRST_TEXTURE_LINE) + ": TextureFile '";
  // The PLY outputs' warning (four frames and the result) and the glTF's, once each.
  EXPECT_EQ(occurrences(r.output, line + "gone.png' is no file from the PLY's folder"), 1u)
      << r.output;
  EXPECT_EQ(occurrences(r.output, line + dir.file("in/gone.png") + "' not found"), 1u) << r.output;
}

TEST(GltfPlyTexture, ATextureWithoutTexcoordsOrNotAnImageIsAWarning) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("ply_texture_unusable");
  // No texcoord list: nothing to sample the image with.
  std::ofstream(dir.file("plain.ply")) << octahedron_ply({"tex.png"}, false, false);
  write_bytes(dir.file("tex.png"), test::tiny_png());
  auto r = run_to_glb(dir.file("plain.ply"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: " + dir.file("plain.ply") + ": line 4: TextureFile '" +
                          dir.file("tex.png") + "' not embedded"),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(test::load_glb(dir.file("run.glb")).images.empty());

  // Not PNG or JPEG: the material without its image.
  std::ofstream(dir.file("tex.png")) << "BM not a glTF image";
  std::ofstream(dir.file("scan.ply")) << octahedron_ply({"tex.png"}, false);
  r = run_to_glb(dir.file("scan.ply"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: " + dir.file("scan.ply") + ": line 4: TextureFile"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("neither PNG nor JPEG"), std::string::npos) << r.output;
  const tinygltf::Model m = test::load_glb(dir.file("run.glb"));
  EXPECT_EQ(m.materials.size(), 1u);
  EXPECT_TRUE(m.images.empty());
}

}  // namespace
}  // namespace shellcontract
