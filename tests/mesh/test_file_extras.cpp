// describe_file_extras: what `repair` says its output does not carry, per format. The expected
// phrases are read off the test files themselves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "mesh/file_extras.hpp"
#include "support/gltf_files.hpp"

namespace shellcontract {
namespace {

bool has(const FileExtras& e, const std::string& item) {
  return std::find(e.items.begin(), e.items.end(), item) != e.items.end();
}

std::string joined(const FileExtras& e) {
  std::string s;
  for (const std::string& i : e.items) s += "[" + i + "] ";
  return s;
}

const std::string TETRA_FACES = "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";

TEST(FileExtras, PlainFilesHoldNothingElse) {
  EXPECT_TRUE(describe_file_extras("off", "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + TETRA_FACES).items.empty());
  EXPECT_TRUE(describe_file_extras("obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\n").items.empty());
  EXPECT_TRUE(describe_file_extras("stl", "solid\nfacet normal 0 0 1\nouter loop\nendloop\nendfacet\nendsolid\n").items.empty());
}

TEST(FileExtras, ObjContinuedLinesAreOneStatement) {
  // A continued v, g and f (line_tokens.hpp): before, each continuation line counted as an
  // unknown statement ("1 '4' statement") and the backslash as a group's name.
  const FileExtras e = describe_file_extras(
      "obj", "v 0 0 0\nv 1 \\\n 0 0\nv 0 1 0\nv 0 0 1\ng a \\\n b\nf 1 3 2\nf 1 2 \\\r\n 4\n");
  EXPECT_EQ(e.items, (std::vector<std::string>{"2 groups (g a, b)"})) << joined(e);
}

TEST(FileExtras, OffColoursNormalsAndComments) {
  const FileExtras e = describe_file_extras(
      "off", "# made by hand\nNOFF\n4 4 6\n0 0 0 0 0 1\n1 0 0 0 0 1 0.5 0.5 0.5\n0 1 0 0 0 1\n0 0 1 0 0 1\n"
             "3 0 2 1 255 0 0\n3 0 1 3\n3 1 2 3 # last two\n3 0 3 2 0 255 0\n");
  EXPECT_TRUE(has(e, "vertex normals (NOFF)")) << joined(e);
  EXPECT_TRUE(has(e, "vertex colours (numbers after the vertex data on 1 vertex line)")) << joined(e);
  EXPECT_TRUE(has(e, "face colours (on 2 faces)")) << joined(e);
  EXPECT_TRUE(has(e, "2 comment lines")) << joined(e);
  EXPECT_FALSE(e.binary);
  EXPECT_TRUE(describe_file_extras("off", "OFF BINARY\n").binary);
}

TEST(FileExtras, PlyPropertiesElementsAndComments) {
  const std::string header =
      "ply\nformat ascii 1.0\ncomment from a scanner\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nproperty float s\nproperty float t\nproperty uchar red\nelement face 4\n"
      "property list uchar int vertex_indices\nproperty int part\nelement edge 1\nproperty int a\nproperty int b\n"
      "end_header\n";
  const FileExtras e = describe_file_extras("ply", header + "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n0 0 1 0 0 1\n" +
                                                       "3 0 2 1 7\n3 0 1 3 7\n3 1 2 3 7\n3 0 3 2 7\n0 1\n");
  EXPECT_TRUE(has(e, "vertex properties s, t, red")) << joined(e);
  EXPECT_TRUE(has(e, "face properties part")) << joined(e);
  EXPECT_TRUE(has(e, "other elements (1 'edge')")) << joined(e);
  EXPECT_TRUE(has(e, "1 comment line (comment, obj_info)")) << joined(e);
  EXPECT_FALSE(e.binary);
}

TEST(FileExtras, StlNameHeaderAndAttributeBytes) {
  const FileExtras ascii = describe_file_extras("stl", "solid part7\nfacet normal 0 0 1\nouter loop\nendloop\nendfacet\nendsolid part7\n");
  EXPECT_TRUE(has(ascii, "the solid's name (part7)")) << joined(ascii);
  EXPECT_FALSE(ascii.binary);
  std::string binary = "exported by a CAD tool";
  binary.resize(80, ' ');
  const std::uint32_t n = 2;
  binary.append(reinterpret_cast<const char*>(&n), 4);
  for (std::uint32_t t = 0; t < n; ++t) {
    binary.append(48, '\0');
    binary += t == 0 ? std::string("\x1f\x80", 2) : std::string(2, '\0');  // a colour on the first facet
  }
  const FileExtras b = describe_file_extras("stl", binary);
  EXPECT_TRUE(b.binary);
  EXPECT_TRUE(has(b, "the 80-byte header ('exported by a CAD tool')")) << joined(b);
  EXPECT_TRUE(has(b, "attribute bytes, often colours (on 1 facet)")) << joined(b);
}

TEST(FileExtras, GltfAttributesNodesMaterialsAndExtensions) {
  test::GltfScene plain;
  plain.primitives.push_back(test::octahedron_primitive(false, false));
  EXPECT_TRUE(describe_file_extras("glb", test::glb_bytes(test::gltf_parts(plain))).items.empty());

  test::GltfScene rich = plain;
  rich.primitives.push_back(test::octahedron_primitive(true, true));
  rich.node_transform = "\"translation\":[1,0,0],\"name\":\"hull\",\"extras\":{\"id\":7}";
  rich.png = "not decoded";
  rich.extra = "\"extensionsUsed\":[\"KHR_materials_unlit\"]";
  const test::GltfParts parts = test::gltf_parts(rich);
  for (const auto& [ext, bytes] :
       {std::pair<std::string, std::string>{"glb", test::glb_bytes(parts)},
        {"gltf", test::gltf_text(parts)}}) {
    const FileExtras e = describe_file_extras(ext, bytes);
    EXPECT_FALSE(e.binary);
    for (const char* item :
         {"vertex attributes NORMAL, TEXCOORD_0", "2 primitives (written as one)",
          "1 node and its transform (applied to the positions)", "node and mesh names (hull)",
          "1 material (skin)", "1 texture", "1 image", "extensions (KHR_materials_unlit)",
          "application data (extras) on 1 object"})
      EXPECT_TRUE(has(e, item)) << ext << ": " << item << " not in " << joined(e);
  }
  // JSON it cannot parse is not described rather than refused.
  EXPECT_TRUE(describe_file_extras("gltf", "{\"asset\":").items.empty());
}

TEST(FileExtras, GltfFileUrisAreTheBuffersAndImagesNotEmbedded) {
  test::GltfScene s;
  s.primitives.push_back(test::octahedron_primitive(false, false));
  const test::GltfParts parts = test::gltf_parts(s);
  EXPECT_EQ(gltf_file_uris(test::gltf_text(parts, "mesh.bin")),
            std::vector<std::string>{"mesh.bin"});
  EXPECT_TRUE(gltf_file_uris(test::gltf_text(parts)).empty());  // a data URI
  EXPECT_TRUE(gltf_file_uris(test::glb_bytes(parts)).empty());  // the BIN chunk
}

TEST(FileExtras, GltfFileUrisNameEachFileOnceInTheOrderFirstNamed) {
  const std::string text =
      R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "b.bin", "byteLength": 1},
          {"uri": "a.bin", "byteLength": 1}, {"uri": "b.bin", "byteLength": 1}],
          "images": [{"uri": "t.png"}, {"uri": "a.bin"}, {"uri": "data:image/png;base64,AA=="},
          {"uri": "t.png"}, {"uri": "u.png"}]})";
  EXPECT_EQ(gltf_file_uris(text), (std::vector<std::string>{"b.bin", "a.bin", "t.png", "u.png"}));
}

}  // namespace
}  // namespace shellcontract
