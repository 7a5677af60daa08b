// A glTF result keeps the input's JSON (src/mesh/gltf_json.hpp): every element the run does not
// change is written as the input had it. Before: tinygltf's writer wrote an empty scene, an
// empty node and KHR_materials_unlit's {} as null (`check` refused the result: "`scenes' does
// not contain an JSON object"), gave an infinite perspective camera "zfar": 0, and added wrap
// modes to a sampler that had none.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "export/gltf_reader.hpp"
#include "export_fixtures.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/cli_runner.hpp"
#include "support/gltf_document_parts.hpp"

namespace shellcontract {
namespace {

using nlohmann::json;
using test::document_parts;
using test::ScratchDir;

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The JSON of a .glb (its JSON chunk) or a .gltf.
json json_of(const std::string& bytes) {
  if (bytes.compare(0, 4, "glTF") != 0) return json::parse(bytes);
  const auto b = [&](std::size_t i) {
    return static_cast<std::uint32_t>(static_cast<unsigned char>(bytes.at(i)));
  };
  const std::uint32_t n = b(12) | b(13) << 8 | b(14) << 16 | b(15) << 24;
  return json::parse(bytes.substr(20, n));
}

/// The output's JSON is the input's except the buffers (new positions and normals: byteLength,
/// uri) and POSITION's min and max.
void expect_input_json_kept(const json& in, json out) {
  for (const char* key : {"buffers", "accessors"}) {
    ASSERT_TRUE(out.contains(key)) << key;
    EXPECT_EQ(out[key].size(), in[key].size()) << key;
  }
  const int pos = in["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>();
  for (const char* key : {"min", "max"}) {
    ASSERT_TRUE(out["accessors"][pos].contains(key));
    EXPECT_NE(out["accessors"][pos][key], in["accessors"][pos][key]) << key << ": not moved";
    out["accessors"][pos][key] = in["accessors"][pos][key];
  }
  out["buffers"] = in["buffers"];
  for (auto it = in.begin(); it != in.end(); ++it) EXPECT_EQ(out[it.key()], it.value()) << it.key();
  for (auto it = out.begin(); it != out.end(); ++it)
    EXPECT_TRUE(in.contains(it.key())) << "added: " << it.key();
  // What tinygltf's writer alone got wrong, named.
  EXPECT_EQ(out["scenes"][0], json::object());
  EXPECT_EQ(out["scenes"][3]["nodes"], json::array());
  EXPECT_EQ(out["nodes"][1], json::object());
  EXPECT_FALSE(out["cameras"][0]["perspective"].contains("zfar"));
  EXPECT_FALSE(out["cameras"][0]["perspective"].contains("aspectRatio"));
  EXPECT_EQ(out["materials"][0]["extensions"]["KHR_materials_unlit"], json::object());
  EXPECT_EQ(out["samplers"][0], json::object());
}

TEST(GltfDocumentJson, ARunKeepsEveryElementItDoesNotChange) {
  for (const bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "glb" : "gltf");
    ScratchDir dir(binary ? "gltf_json_glb" : "gltf_json_gltf");
    const std::string ext = binary ? ".glb" : ".gltf";
    test::GltfParts parts = document_parts();
    // A scene with an empty list of nodes: not valid (minItems 1), but read, so kept as read.
    test::replace_once(parts.json, "{\"extras\":{}}]", "{\"extras\":{}},{\"nodes\":[]}]");
    const std::string bytes = binary ? test::glb_bytes(parts) : test::gltf_text(parts);
    const std::string in = dir.file("doc" + ext), out = dir.file("out" + ext);
    std::ofstream(in, std::ios::binary) << bytes;
    auto r = test::run_cli({"check", in});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = test::run_cli({"run", in, "-o", out, "-n", "8", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string written = slurp(out);
    expect_input_json_kept(json_of(bytes), json_of(written));
    r = test::run_cli({"check", out});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("\nusable: yes\n"), std::string::npos) << r.output;
    EXPECT_GT(read_input_mesh(out).number_of_vertices(), 0u);
    if (binary) {
      const tinygltf::Model model = test::load_glb(out);
      EXPECT_EQ(model.defaultScene, 1);
      EXPECT_EQ(model.scenes.size(), 4u);
    }
  }
}

// An instanced mesh's copy (gltf_instances.hpp) is the input's mesh with accessors of its own:
// its extras (with an empty array) as the input had them.
TEST(GltfDocumentJson, AnInstancedMeshsCopyKeepsTheMeshsJson) {
  ScratchDir dir("gltf_json_instanced");
  test::GltfParts parts = document_parts();
  test::replace_once(parts.json, "{},{\"camera\":0",
                     "{\"mesh\":0,\"translation\":[-3,0,0]},{\"camera\":0");
  test::replace_once(parts.json, "\"nodes\":[0,2]", "\"nodes\":[0,1,2]");
  const std::string in = dir.file("twice.glb"), out = dir.file("out.glb");
  std::ofstream(in, std::ios::binary) << test::glb_bytes(parts);
  auto r = test::run_cli({"run", in, "-o", out, "-n", "8", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json j = json_of(slurp(out));
  ASSERT_EQ(j["meshes"].size(), 2u);
  EXPECT_EQ(j["nodes"][1]["mesh"], 1);
  EXPECT_EQ(j["meshes"][1]["extras"], json::parse("{\"tags\":[]}"));
  EXPECT_NE(j["meshes"][1]["primitives"][0]["attributes"]["POSITION"],
            j["meshes"][0]["primitives"][0]["attributes"]["POSITION"]);
  EXPECT_EQ(j["scenes"][0], json::object());
  r = test::run_cli({"check", out});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\ncomponents: 2\n"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace shellcontract
