// What a glTF costs to read and to write back, bounded by the file: a scene of many instances
// written back in one pass over its nodes (gltf_json.cpp); a file named by many buffers read once
// (gltf_load.cpp). The tests held to a timeout of their own are listed in tests/CMakeLists.txt:
// their input cost the code before quadratic work (5e9 steps and more), the bounded code linear.
#include <gtest/gtest.h>

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "mesh/gltf_json.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/gltf_document_parts.hpp"
#include "support/gltf_files.hpp"
#include "support/scratch_dir.hpp"

namespace shellcontract {
namespace {

using json = nlohmann::json;
using test::replace_once;

class GltfCosts : public test::ScratchDirTest {
 protected:
  GltfCosts() : ScratchDirTest("shellcontract_gltf_costs_") {}
  /// The refusal of the file, or "(no error)".
  static std::string error_of(const std::string& path) {
    try {
      read_input_mesh(path);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  }
};

// A document that appends a mesh per instance (realize_instances: M nodes drawing one mesh become
// M meshes) has each appended mesh's input found in one pass over the nodes. Before, every
// appended mesh looked for its node among all nodes: M * M / 2 node lookups, 5e9 here.
TEST(GltfCostsJson, AnInstancedScenesJsonIsWrittenBackInOnePassOverItsNodes) {
  const std::size_t M = 100000;
  std::string in = R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":)"
                   R"({"POSITION":0}}],"extras":{"kept":1}}],"nodes":[)";
  std::string out = R"({"asset":{"version":"2.0"},"meshes":[)";
  for (std::size_t i = 0; i < M; ++i) {
    const std::string k = std::to_string(i), comma = i + 1 < M ? "," : "";
    in += R"({"mesh":0})" + comma;
    out += R"({"name":"copy )" + k + R"(","primitives":[{"attributes":{"POSITION":)" + k + "}}]}" +
           comma;
  }
  out += R"(],"nodes":[)";
  for (std::size_t i = 0; i < M; ++i)
    out += R"({"mesh":)" + std::to_string(i) + "}" + (i + 1 < M ? "," : "");
  in += "]}";
  out += "]}";
  const json j = json::parse(gltf::restore_input_json(in, out, false, {}));
  ASSERT_EQ(j["meshes"].size(), M);
  for (const std::size_t k : {std::size_t{1}, M / 2, M - 1}) {
    const json& mesh = j["meshes"][k];
    // The input's mesh (its extras), with the copy's name and attributes.
    EXPECT_EQ(mesh["extras"]["kept"], 1) << k;
    EXPECT_EQ(mesh["name"], "copy " + std::to_string(k)) << k;
    EXPECT_EQ(mesh["primitives"][0]["attributes"]["POSITION"], k) << k;
    EXPECT_EQ(j["nodes"][k]["mesh"], k) << k;
  }
}

// Many buffers naming one external file: the second is refused before the file is read again,
// naming the file and the buffers (each buffer holds a copy of its file, so a few bytes of JSON
// per buffer cost the whole file again). Before, every buffer read the file: here 1000 times,
// and the octahedron was read without complaint.
TEST_F(GltfCosts, AFileNamedByManyBuffersIsReadOnce) {
  test::GltfScene s;
  s.primitives.push_back(test::octahedron_primitive(false, false));
  const test::GltfParts parts = test::gltf_parts(s);
  write("octa.bin", parts.bin);
  const std::string one = R"({"byteLength":)" + std::to_string(parts.bin.size()) + ",";
  const auto with = [&](const std::string& more) {
    std::string text = test::gltf_text(parts, "octa.bin");
    replace_once(text, R"("uri":"octa.bin"}])", R"("uri":"octa.bin"})" + more + "]");
    return text;
  };
  std::string more;
  for (int k = 1; k < 1000; ++k) more += "," + one + R"("uri":"octa.bin"})";
  const std::string path = write("many.gltf", with(more));
  const std::string error = error_of(path);
  EXPECT_EQ(error.find(path + ": buffer file read twice: '" + (dir_ / "octa.bin").string() + "' (" +
                       std::to_string(parts.bin.size()) +
                       " bytes) is named by buffers 0, 1, 2, ..., 999 (1000 buffers)"),
            0u)
      << error;
  // The same file by another path is the same file; another file is read.
  EXPECT_NE(error_of(write("dot.gltf", with("," + one + R"("uri":"./octa.bin"})")))
                .find("buffer file read twice"),
            std::string::npos);
  write("copy.bin", parts.bin);
  EXPECT_EQ(error_of(write("copy.gltf", with("," + one + R"("uri":"copy.bin"})"))), "(no error)");
}

}  // namespace
}  // namespace shellcontract
