// What a glTF costs to read and to write back, bounded by the file: a scene of many instances
// written back in one pass over its nodes (gltf_json.cpp); a file named by many buffers read once
// (gltf_load.cpp); a scene drawing more triangles than its bytes bound refused before any is read,
// and the triangles of many drawn primitives gathered without moving them all for each
// (gltf_reader.cpp). The tests held to a timeout of their own are listed in tests/CMakeLists.txt:
// their input cost the code before quadratic work (5e9 steps and more), the bounded code linear.
#include <gtest/gtest.h>

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "mesh/gltf_json.hpp"
#include "mesh/gltf_reader.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/gltf_document_parts.hpp"
#include "support/gltf_files.hpp"
#include "support/input_refusal.hpp"
#include "support/scratch_dir.hpp"

namespace shellcontract {
namespace {

using json = nlohmann::json;
using test::replace_once;

class GltfCosts : public test::ScratchDirTest {
 protected:
  GltfCosts() : ScratchDirTest("shellcontract_gltf_costs_") {}
  /// The refusal of the file, or "(no error)".
  static std::string error_of(const std::string& path) { return test::input_refusal(path); }
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

// In a .glb only buffer 0 may leave out its uri (the BIN chunk). Before, each other buffer
// without one was read as a copy of the chunk: a thousand of them cost a thousand copies.
TEST_F(GltfCosts, AGlbBufferOtherThanTheFirstWithoutAUriIsRefused) {
  test::GltfScene s;
  s.primitives.push_back(test::octahedron_primitive(false, false));
  test::GltfParts parts = test::gltf_parts(s);
  std::string more;
  for (int k = 1; k < 1000; ++k)
    more += R"(,{"byteLength":)" + std::to_string(parts.bin.size()) + "}";
  const std::string one = write("one.glb", test::glb_bytes(parts));
  EXPECT_EQ(error_of(one), "(no error)");
  replace_once(parts.json, "%URI%}", "%URI%}" + more);
  const std::string path = write("many.glb", test::glb_bytes(parts));
  EXPECT_EQ(error_of(path), path +
                                ": buffer without uri: buffer 1 names no file; in a .glb only "
                                "buffer 0 may, and is then the BIN chunk");
}

/// A .glb whose mesh 0 has `primitives` primitives, each drawing `triangles` triangles (uint8
/// indices on a tetrahedron's 4 positions: the first `triangles` of its faces, cycled), and whose
/// scene has `nodes` nodes drawing mesh 0, translated apart.
std::string instanced_glb(std::size_t primitives, std::size_t nodes, std::size_t triangles) {
  const float xyz[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  const unsigned char tet[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  std::string bin(reinterpret_cast<const char*>(xyz), sizeof xyz);
  for (std::size_t t = 0; t < triangles; ++t)
    bin.append(reinterpret_cast<const char*>(tet + 3 * (t % 4)), 3);
  std::string prims, node_list, scene;
  for (std::size_t p = 0; p < primitives; ++p)
    prims += std::string(p ? "," : "") + R"({"attributes":{"POSITION":0},"indices":1})";
  for (std::size_t n = 0; n < nodes; ++n) {
    node_list += std::string(n ? "," : "") + R"({"mesh":0,"translation":[)" +
                 std::to_string(2 * n) + ",0,0]}";
    scene += std::string(n ? "," : "") + std::to_string(n);
  }
  test::GltfParts parts;
  parts.json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[)" + scene +
               R"(]}],"nodes":[)" + node_list + R"(],"meshes":[{"primitives":[)" + prims +
               R"(]}],"accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3",)"
               R"("min":[0,0,0],"max":[1,1,1]},{"bufferView":1,"componentType":5121,"count":)" +
               std::to_string(3 * triangles) +
               R"(,"type":"SCALAR"}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},)"
               R"({"buffer":0,"byteOffset":48,"byteLength":)" +
               std::to_string(3 * triangles) + R"(}],"buffers":[{"byteLength":)" +
               std::to_string(bin.size()) + "%URI%}]}";
  parts.bin = bin;
  return test::glb_bytes(parts);
}

// Primitives x nodes drawing one index accessor: the triangles are counted from the accessors'
// counts before any is read, and a scene drawing more than 64 for each byte of the file and its
// buffers is refused, naming the mesh. Before, all 1,000,000 were read (100 primitives of 1000
// triangles, 10 nodes, an 8 KB file) and then refused as duplicate faces; a file of this kind
// drawing 1e9 from 65 KB was read for as long as that takes.
TEST_F(GltfCosts, AScenesTrianglesAreBoundedByItsFile) {
  const std::string bytes = instanced_glb(100, 10, 1000);
  const std::string path = write("amplified.glb", bytes);
  // 11088 bytes: the .glb's 8040 and its buffer's 3048.
  ASSERT_EQ(bytes.size(), 8040u);
  EXPECT_EQ(error_of(path),
            path +
                ": scene too large for its file: the default scene draws 1000000 triangles, "
                "more than 64 for each of the 11088 bytes of the file and its buffers: mesh 0 "
                "(100 primitives, 100000 triangles) is drawn by 10 nodes; it was not read");
  // Instances within the bound are read: 1000 tetrahedra.
  const Mesh mesh = read_input_mesh(write("instances.glb", instanced_glb(1, 1000, 4)));
  EXPECT_EQ(mesh.number_of_faces(), 4000u);
}

// Many drawn primitives, within the bound (1000 primitives of one triangle, drawn by 500 nodes:
// 500,000 triangles from a 60 KB file), are gathered without moving the faces read before each:
// an exact reserve per primitive moved them all every time, 1.25e11 moves here.
TEST_F(GltfCosts, ManyDrawnPrimitivesAreGatheredInLinearTime) {
  const std::string bytes = instanced_glb(1000, 500, 1);
  const GltfSoup soup = read_gltf(write("many_primitives.glb", bytes), bytes);
  EXPECT_EQ(soup.drawn.size(), 500000u);
  EXPECT_EQ(soup.faces.size(), 500000u);
  EXPECT_EQ(soup.points.size(), 1500u);  // each node's primitives share their three vertices
}

}  // namespace
}  // namespace shellcontract
