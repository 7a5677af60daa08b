// A glTF result whose rewritten bytes something else reads too (review7 F5): a primitive whose
// NORMAL is its POSITION accessor, or a NORMAL or TEXCOORD_0 accessor on POSITION's bytes, is
// refused when the document is made, before the run (exit 2), since the new normals would
// overwrite the new positions, or the texture coordinates would become positions, without a word.
// Before: the document was made, and the .glb result of "NORMAL": 0 held the new normals as its
// positions (a unit sphere for any shape), exit 0.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "export_fixtures.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/cli_runner.hpp"
#include "support/gltf_files.hpp"

namespace shellcontract {
namespace {

/// The textured octahedron (accessors: 0 POSITION, 1 TEXCOORD_0, 2 NORMAL, 3 indices; buffer
/// view k for accessor k), its JSON with `from` replaced by `to`.
test::GltfParts edited(const std::string& from, const std::string& to) {
  test::GltfScene s;
  s.primitives.push_back(test::octahedron_primitive(true, true));
  test::GltfParts parts = test::gltf_parts(s);
  const std::size_t at = parts.json.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  parts.json.replace(at, from.size(), to);
  return parts;
}

std::string refusal(const test::GltfParts& parts) {
  try {
    parse_gltf_document("in.glb", test::glb_bytes(parts), true);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(GltfAliasing, ANormalOnThePositionsIsRefused) {
  EXPECT_EQ(refusal(edited("\"NORMAL\":2", "\"NORMAL\":0")),
            "in.glb: not writable with new positions: mesh 0 primitive 0 NORMAL and mesh 0 "
            "primitive 0 POSITION share accessor 0");
  // Another accessor on the same bytes: accessor 2 reads buffer view 0.
  EXPECT_EQ(refusal(edited("{\"bufferView\":2,", "{\"bufferView\":0,")),
            "in.glb: not writable with new positions: mesh 0 primitive 0 NORMAL (accessor 2) "
            "shares bytes with mesh 0 primitive 0 POSITION (accessor 0; buffer 0 byte 0)");
}

TEST(GltfAliasing, TexcoordsOnThePositionsAreRefused) {
  EXPECT_EQ(refusal(edited("{\"bufferView\":1,", "{\"bufferView\":0,")),
            "in.glb: not writable with new positions: mesh 0 primitive 0 TEXCOORD_0 (accessor 1) "
            "shares bytes with mesh 0 primitive 0 POSITION (accessor 0; buffer 0 byte 0)");
  EXPECT_EQ(refusal(edited("\"NORMAL\":2", "\"NORMAL\":2,\"COLOR_0\":2")),
            "in.glb: not writable with new positions: mesh 0 primitive 0 COLOR_0 (accessor 2) "
            "shares bytes with mesh 0 primitive 0 NORMAL (accessor 2; buffer 0 byte 140)");
  // The file as written (every accessor its own bytes) is a document.
  EXPECT_EQ(refusal(edited("\"NORMAL\":2", "\"NORMAL\":2")), "(no error)");
}

TEST(GltfAliasing, TheCliRefusesAGlbResultBeforeTheRunAndWritesAnOff) {
  test::ScratchDir dir("gltf_aliasing");
  const std::string in = dir.file("normal_is_position.glb");
  std::ofstream(in, std::ios::binary) << test::glb_bytes(edited("\"NORMAL\":2", "\"NORMAL\":0"));
  auto r = test::run_cli({"run", in, "-o", dir.file("out.glb"), "-n", "2", "-q"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("NORMAL and mesh 0 primitive 0 POSITION share accessor 0"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("out.glb")));
  r = test::run_cli({"run", in, "-o", dir.file("out.off"), "-n", "2", "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

}  // namespace
}  // namespace shellcontract
