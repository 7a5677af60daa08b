// What a glTF costs to write back, bounded by the file: a scene of many instances written back
// in one pass over its nodes (gltf_json.cpp). The tests held to a timeout of their own are listed
// in tests/CMakeLists.txt: their input cost the code before quadratic work (5e9 steps and more),
// the bounded code linear.
#include <gtest/gtest.h>

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "mesh/gltf_json.hpp"

namespace shellcontract {
namespace {

using json = nlohmann::json;

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

}  // namespace
}  // namespace shellcontract
