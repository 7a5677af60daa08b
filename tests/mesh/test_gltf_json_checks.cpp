// A glTF's JSON checked before tinygltf parses it (src/mesh/gltf_json_checks.cpp): a JSON nested
// deeper than MAX_JSON_DEPTH (512) levels, an asset version other than 2, a default scene that is
// not a scene index, and an external buffer file larger than its byteLength are each an
// InputError naming the file. Before: 20,000 nested arrays crashed the reader (stack overflow in
// tinygltf's recursive parse; tests/cli/test_cli_gltf_hostile.cpp), 513 levels were read,
// "3.0" was read as 2.0, "scene": -2 as scene 0, and a buffer file was read whole before its size
// was compared (the message then tinygltf's "File size mismatch"). An index member (nodes[0].mesh)
// with an integer of 2^31 or more, or below 0, is refused naming it: tinygltf cut it to an int.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/gltf_files.hpp"
#include "support/input_refusal.hpp"
#include "support/scratch_dir.hpp"

namespace shellcontract {
namespace {

using test::GltfScene;

class GltfJsonChecks : public test::ScratchDirTest {
 protected:
  GltfJsonChecks() : ScratchDirTest("shellcontract_gltf_json_checks_") {}
  /// The refusal of the file, or "(no error)".
  static std::string error_of(const std::string& path) { return test::input_refusal(path); }
  static GltfScene octahedron(const std::string& extra = "") {
    GltfScene s;
    s.primitives.push_back(test::octahedron_primitive(false, false));
    s.extra = extra;
    return s;
  }
  /// The octahedron's .glb with `json` edited: `from` replaced by `to`.
  std::string edited(const std::string& name, const std::string& from, const std::string& to) {
    test::GltfParts parts = test::gltf_parts(octahedron());
    const std::size_t at = parts.json.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    parts.json.replace(at, from.size(), to);
    return write(name, test::glb_bytes(parts));
  }
};

/// A top-level "extras" of `arrays` nested arrays: the JSON then nests arrays + 1 levels.
std::string nested_extras(std::size_t arrays) {
  return "\"extras\":" + std::string(arrays, '[') + std::string(arrays, ']');
}

TEST_F(GltfJsonChecks, AJsonNestedDeeperThan512LevelsIsRefusedAndOneOf512IsRead) {
  const GltfScene deepest = octahedron(nested_extras(511));  // 512 levels with the root object
  EXPECT_EQ(read_input_mesh(write("d512.glb", test::glb_bytes(test::gltf_parts(deepest))))
                .number_of_faces(),
            8u);
  const GltfScene deeper = octahedron(nested_extras(512));
  const test::GltfParts parts = test::gltf_parts(deeper);
  for (const std::string& path :
       {write("d513.glb", test::glb_bytes(parts)), write("d513.gltf", test::gltf_text(parts))}) {
    const std::string e = error_of(path);
    EXPECT_EQ(e.rfind(path + ": JSON nested too deeply: the JSON nests deeper than 512 levels", 0),
              0u)
        << e;
    // The 513th '[' opens level 513: its byte in the file (the .glb's JSON starts at byte 20).
    const std::size_t json_at = path.back() == 'b' ? 20 : 0;
    const std::string json =
        path.back() == 'b' ? test::replace_uri(parts.json, "") : test::gltf_text(parts);
    const std::size_t opens = json.find('[', json.find("\"extras\"")) + 511;
    EXPECT_NE(e.find("(byte " + std::to_string(json_at + opens) + " opens level 513)"),
              std::string::npos)
        << e;
  }
}

TEST_F(GltfJsonChecks, BracketsInsideStringsAndEscapedQuotesDoNotCount) {
  // 600 '[' and '{' inside a string (after an escaped quote and an escaped backslash): depth 2.
  const std::string s = "\\\"\\\\" + std::string(300, '[') + std::string(300, '{');
  const GltfScene scene = octahedron("\"extras\":{\"text\":\"" + s + "\"}");
  EXPECT_EQ(read_input_mesh(write("strings.glb", test::glb_bytes(test::gltf_parts(scene))))
                .number_of_faces(),
            8u);
}

TEST_F(GltfJsonChecks, AnAssetVersionOtherThanTwoIsRefused) {
  const std::string v3 = edited("v3.glb", "\"version\":\"2.0\"", "\"version\":\"3.0\"");
  EXPECT_EQ(error_of(v3), v3 + ": unsupported glTF version: asset.version is \"3.0\" (only glTF "
                               "2.x is read)");
  const std::string v1 = edited("v1.glb", "\"version\":\"2.0\"", "\"version\":\"1.0\"");
  EXPECT_NE(error_of(v1).find("asset.version is \"1.0\""), std::string::npos) << error_of(v1);
  const std::string min =
      edited("min.glb", "\"version\":\"2.0\"", "\"version\":\"2.1\",\"minVersion\":\"2.1\"");
  EXPECT_NE(error_of(min).find("asset.minVersion is \"2.1\""), std::string::npos) << error_of(min);
  // A later minor version without minVersion is meant to be read by a 2.0 reader (the spec).
  const std::string minor =
      edited("minor.glb", "\"version\":\"2.0\"", "\"version\":\"2.1\",\"minVersion\":\"2.0\"");
  EXPECT_EQ(read_input_mesh(minor).number_of_faces(), 8u);
}

TEST_F(GltfJsonChecks, ADefaultSceneThatIsNoSceneIndexIsRefused) {
  for (const std::string value : {"-2", "-1", "0.5"}) {
    const std::string path = edited("scene.glb", "\"scene\":0", "\"scene\":" + value);
    EXPECT_EQ(error_of(path),
              path + ": bad default scene: \"scene\" is " + value + ", not a scene index");
  }
  const std::string big = edited("big.glb", "\"scene\":0", "\"scene\":4294967296");
  EXPECT_NE(error_of(big).find("scene out of range"), std::string::npos) << error_of(big);
}

TEST_F(GltfJsonChecks, AnIndexOfTwoToThe31OrMoreOrBelowZeroIsRefusedAsWritten) {
  // Before: tinygltf cut each to its low 32 bits, so mesh 2^32 drew mesh 0 (read, 8 faces).
  const std::string too_large = ", more than the largest index that is read (2147483647)";
  const std::string negative = ", not an index (an index is 0 or more)";
  struct Case {
    const char* from;
    const char* to;
    const char* member;
    std::string says;
  };
  for (const Case& c : std::vector<Case>{
           {"\"mesh\":0", "\"mesh\":4294967296", "nodes[0].mesh is 4294967296", too_large},
           {"\"mesh\":0", "\"mesh\":-4294967296", "nodes[0].mesh is -4294967296", negative},
           {"\"mesh\":0", "\"mesh\":-1", "nodes[0].mesh is -1", negative},
           {"\"mesh\":0", "\"mesh\":0,\"children\":[1099511627776]",
            "nodes[0].children[0] is 1099511627776", too_large},
           {"\"nodes\":[0]", "\"nodes\":[4294967296]", "scenes[0].nodes[0] is 4294967296",
            too_large},
           {"\"POSITION\":0", "\"POSITION\":4294967296",
            "meshes[0].primitives[0].attributes.POSITION is 4294967296", too_large},
           {"\"indices\":1", "\"indices\":4294967297",
            "meshes[0].primitives[0].indices is 4294967297", too_large},
           {"\"bufferView\":1", "\"bufferView\":2147483648",
            "accessors[1].bufferView is 2147483648", too_large},
           {"\"buffer\":0", "\"buffer\":18446744073709551615",
            "bufferViews[0].buffer is 18446744073709551615", too_large},
       }) {
    const std::string path = edited("index.glb", c.from, c.to);
    EXPECT_EQ(error_of(path), path + ": bad index: " + c.member + c.says);
  }
  // The largest int is no index of this file either, but tinygltf keeps it as written: the
  // reader's own range check names it.
  const std::string max = edited("max.glb", "\"mesh\":0", "\"mesh\":2147483647");
  EXPECT_NE(error_of(max).find("mesh out of range: node 0 names mesh 2147483647"),
            std::string::npos)
      << error_of(max);
  // The same numbers outside index members (extras, an extension, a count) are not indices.
  const std::string extras = edited("extras.glb", "\"mesh\":0",
                                    "\"mesh\":0,\"extras\":{\"mesh\":4294967296,\"nodes\":[-5]},"
                                    "\"extensions\":{\"X_y\":{\"mesh\":-4294967296}}");
  EXPECT_EQ(read_input_mesh(extras).number_of_faces(), 8u);
  // A .gltf is scanned as a .glb is.
  test::GltfParts parts = test::gltf_parts(octahedron());
  parts.json.replace(parts.json.find("\"mesh\":0"), 8, "\"mesh\":4294967296");
  const std::string gltf = write("index.gltf", test::gltf_text(parts));
  EXPECT_EQ(error_of(gltf), gltf + ": bad index: nodes[0].mesh is 4294967296" + too_large);
}

TEST_F(GltfJsonChecks, ABufferFileLargerThanItsByteLengthIsRefusedUnread) {
  const test::GltfParts parts = test::gltf_parts(octahedron());
  write("octa.bin", parts.bin + std::string(4, '\0'));
  const std::string gltf = write("octa.gltf", test::gltf_text(parts, "octa.bin"));
  const std::string e = error_of(gltf);
  const std::string bin = (dir_ / "octa.bin").string();
  EXPECT_EQ(e, gltf + ": buffer file too large: '" + bin + "' has " +
                   std::to_string(parts.bin.size() + 4) + " bytes, more than buffer 0's " +
                   "byteLength of " + std::to_string(parts.bin.size()) +
                   " ('octa.bin'); it was not read");
  // A file of the right size is read, also through a percent-encoded URI.
  write("oc ta.bin", parts.bin);
  EXPECT_EQ(
      read_input_mesh(write("ok.gltf", test::gltf_text(parts, "oc%20ta.bin"))).number_of_faces(),
      8u);
}

}  // namespace
}  // namespace shellcontract
