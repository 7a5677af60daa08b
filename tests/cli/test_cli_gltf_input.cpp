// glTF inputs on the command line: `check` and `run` read a .glb or .gltf (exit 0), and every
// malformed one is exit 2 with a message naming the file and the problem, never a crash. Before
// the glTF reader, every file here was exit 2 with "unknown extension".
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "support/cli_runner.hpp"
#include "support/gltf_files.hpp"
#include "support/scratch_dir.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

class CliGltf : public test::ScratchDirTest {
 protected:
  CliGltf() : ScratchDirTest("shellcontract_cli_gltf_") {}
};

test::GltfScene octahedron() {
  test::GltfScene s;
  s.primitives.push_back(test::octahedron_primitive(true, true));
  return s;
}

TEST_F(CliGltf, CheckAndRunReadAGlbAndAGltf) {
  const test::GltfParts parts = test::gltf_parts(octahedron());
  for (const std::string& in :
       {write("o.glb", test::glb_bytes(parts)), write("o.gltf", test::gltf_text(parts))}) {
    auto r = test::run_cli({"check", in});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("vertices: 6"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("closed: yes"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("morph targets"), std::string::npos) << r.output;  // it has none
    r = test::run_cli({"run", in, "-o", (dir_ / "out.off").string(), "-n", "3", "-q"});
    EXPECT_EQ(r.exit_code, 0) << r.output;
  }
}

TEST_F(CliGltf, MalformedFilesAreExitTwoNamingTheProblem) {
  const test::GltfParts parts = test::gltf_parts(octahedron());
  const std::string good = test::glb_bytes(parts);
  test::GltfScene lines = octahedron();
  lines.primitives[0].mode = 1;
  test::GltfScene index = octahedron();
  index.primitives[0].indices[4] = 200;
  test::GltfScene draco = octahedron();
  draco.extra = "\"extensionsRequired\":[\"KHR_draco_mesh_compression\"]";
  std::string bad_json = test::gltf_text(parts);
  bad_json.resize(bad_json.size() / 2);
  std::string sparse = parts.json;
  sparse.replace(sparse.find("\"count\":7"), 9, "\"count\":7,\"sparse\":{\"count\":0}");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {write("lines.glb", test::glb_bytes(test::gltf_parts(lines))),
       "mesh 0 primitive 0: mode 1 (lines) is not triangles"},
      {write("index.glb", test::glb_bytes(test::gltf_parts(index))),
       "refers to vertex 200, but its POSITION has 7"},
      {write("draco.glb", test::glb_bytes(test::gltf_parts(draco))),
       "requires KHR_draco_mesh_compression"},
      {write("truncated.glb", good.substr(0, good.size() / 2)), "truncated .glb"},
      {write("empty_bin.glb", good.substr(0, 12)), "truncated .glb"},
      {write("json.gltf", bad_json), "cannot read .gltf"},
      {write("sparse.glb", test::glb_bytes({sparse, parts.bin})), "sparse"},
      {write("missing.gltf", test::gltf_text(parts, "missing.bin")), "missing.bin"},
  };
  for (const auto& [path, problem] : cases) {
    const auto r = test::run_cli({"check", path});
    EXPECT_EQ(r.exit_code, 2) << path << ": " << r.output;
    EXPECT_NE(r.output.find(path + ": "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(problem), std::string::npos)
        << "'" << problem << "' not in: " << r.output;
  }
}

}  // namespace
}  // namespace shellcontract
