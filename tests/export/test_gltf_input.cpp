// A glTF input through `shellcontract run` (docs/design/attributes.md, "glTF inputs"): a .glb
// result is the input .glb with new positions and normals, everything else kept (texture
// coordinates per vertex, the node's transform, the material and its image); seam copies move
// together; other outputs are written from it like from any input. Before: "unknown extension
// '.glb'" (exit 2) for every input here, and "-o x.glb" was bad usage.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

#include "export/gltf_reader.hpp"
#include "export_fixtures.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/cli_runner.hpp"
#include "support/gltf_files.hpp"
#include "support/multi_material_sphere.hpp"
#include "support/textured_octahedron.hpp"

namespace shellcontract {
namespace {

using test::ScratchDir;

/// The textured octahedron split at a UV seam, with normals, drawn by a moved and scaled node.
test::GltfScene textured_scene() {
  test::GltfScene s;
  s.primitives.push_back(test::octahedron_primitive(true, true));
  s.node_transform = "\"translation\":[3,-1,2],\"scale\":[2,2,2],\"name\":\"shell\"";
  const auto& png = test::tiny_png();
  s.png.assign(png.begin(), png.end());
  return s;
}

std::string slurp_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string write(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

const tinygltf::Primitive& primitive(const tinygltf::Model& m) {
  return m.meshes.at(0).primitives.at(0);
}
test::Floats attribute(const tinygltf::Model& m, const char* name) {
  return test::read_floats(m, primitive(m).attributes.at(name));
}

TEST(GltfInput, AGlbResultKeepsTexcoordsNodeAndMaterialWithNewPositions) {
  ScratchDir dir("gltf_input");
  const std::string in =
      write(dir.file("seam.glb"), test::glb_bytes(test::gltf_parts(textured_scene())));
  const auto r = test::run_cli({"run", in, "-o", dir.file("out.glb"), "-n", "8", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("seam vertex was welded"), std::string::npos) << r.output;
  const tinygltf::Model a = test::load_glb(in), b = test::load_glb(dir.file("out.glb"));

  EXPECT_EQ(attribute(a, "TEXCOORD_0"), attribute(b, "TEXCOORD_0"));  // per vertex, bit for bit
  const test::Floats pa = attribute(a, "POSITION"), pb = attribute(b, "POSITION");
  ASSERT_EQ(pb.rows(), 7);
  EXPECT_GT((pa - pb).cwiseAbs().maxCoeff(), 1e-4f);  // the shell moved
  EXPECT_EQ(pb.row(0), pb.row(6));                    // the seam copies moved together
  EXPECT_EQ(b.nodes.at(0).translation, a.nodes.at(0).translation);  // node space kept
  EXPECT_EQ(b.nodes.at(0).scale, a.nodes.at(0).scale);
  EXPECT_EQ(b.nodes.at(0).name, "shell");
  ASSERT_EQ(b.materials.size(), 1u);
  EXPECT_EQ(b.materials[0].name, "skin");
  EXPECT_EQ(primitive(b).material, 0);
  ASSERT_EQ(b.images.size(), 1u);
  const auto& view = b.bufferViews.at(static_cast<std::size_t>(b.images[0].bufferView));
  const auto* bytes = b.buffers.at(0).data.data() + view.byteOffset;
  EXPECT_EQ(std::vector<unsigned char>(bytes, bytes + view.byteLength), test::tiny_png());
  const test::Floats n = attribute(b, "NORMAL");
  for (Eigen::Index i = 0; i < n.rows(); ++i) EXPECT_NEAR(n.row(i).norm(), 1.0f, 1e-5f) << i;
  EXPECT_EQ(n.row(0), n.row(6));  // one normal for the welded vertex: no seam shows
  // POSITION's bounds (the spec requires them) are the new ones.
  const auto& acc =
      b.accessors.at(static_cast<std::size_t>(primitive(b).attributes.at("POSITION")));
  EXPECT_FLOAT_EQ(static_cast<float>(acc.maxValues.at(0)), pb.col(0).maxCoeff());

  // The same run written as OFF: the .glb's node-space positions are its world positions
  // brought back through the node (x = 2 p + t), to float precision.
  const auto off = test::run_cli({"run", in, "-o", dir.file("out.off"), "-n", "8", "-q"});
  ASSERT_EQ(off.exit_code, 0) << off.output;
  const Mesh world = read_input_mesh(dir.file("out.off"));
  const Positions xw = input_positions(world, positions_from_mesh(world));
  ASSERT_EQ(xw.rows(), 7);  // the OFF keeps every copy (read back welded: its file's vertices)
  for (Eigen::Index i = 0; i < 7; ++i)
    for (int c = 0; c < 3; ++c) {
      const double t = a.nodes[0].translation[static_cast<std::size_t>(c)];
      EXPECT_NEAR(2.0 * pb(i, c) + t, xw(i, c), 1e-5) << i << ' ' << c;
    }
  // The result reads back as the same closed mesh.
  InputReport report;
  read_input_mesh(dir.file("out.glb"), &report);
  EXPECT_EQ(report.vertices, 6u);
  EXPECT_EQ(report.welded_vertices, 1u);
}

TEST(GltfInput, AGltfResultAndTheRunsAnimationKeepTexcoords) {
  ScratchDir dir("gltf_input_text");
  // The image as a data URI (the usual .gltf way) instead of a buffer view.
  test::GltfParts parts = test::gltf_parts(textured_scene());
  const std::size_t image = parts.json.find("\"images\":[");
  const std::size_t image_end = parts.json.find(']', image) + 1;
  const auto& png = test::tiny_png();
  const std::string data_uri =
      "data:image/png;base64," + test::base64(std::string(png.begin(), png.end()));
  parts.json.replace(image, image_end - image, "\"images\":[{\"uri\":\"" + data_uri + "\"}]");
  const std::string in = write(dir.file("seam.gltf"), test::gltf_text(parts));
  const auto r = test::run_cli(
      {"run", in, "-o", dir.file("out.gltf"), "-n", "4", "-q", "--gltf", dir.file("anim.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(slurp_text(dir.file("out.gltf")).find("\"uri\": \"" + data_uri + "\""),
            std::string::npos)
      << "the data-URI image is not kept";
  InputReport report;
  read_input_mesh(dir.file("out.gltf"), &report);
  EXPECT_EQ(report.vertices, 6u);
  // The animation takes the input's texture coordinates (v flipped twice: as in the file).
  const tinygltf::Model anim = test::load_glb(dir.file("anim.glb"));
  ASSERT_TRUE(primitive(anim).attributes.count("TEXCOORD_0"));
  const test::Floats uv = attribute(anim, "TEXCOORD_0");
  const test::GltfPrimitive src = test::octahedron_primitive(true, true);
  for (Eigen::Index i = 0; i < 6;
       ++i) {  // glTF vertex i < #V is simulation vertex i (its first copy)
    EXPECT_FLOAT_EQ(uv(i, 0), src.texcoords[static_cast<std::size_t>(i)][0]) << i;
    EXPECT_FLOAT_EQ(uv(i, 1), src.texcoords[static_cast<std::size_t>(i)][1]) << i;
  }
}

// The tool's own animated .glb of a multi-material OBJ: four primitives sharing one POSITION
// accessor (each bringing the vertices it draws), morph targets, colour fields, an animation and
// an embedded texture. Run again, it keeps every one of them.
TEST(GltfInput, TheToolsOwnAnimatedGlbRunsAgainAndKeepsItsPrimitives) {
  ScratchDir dir("gltf_input_own");
  const std::string obj = test::write_multi_material_sphere(dir.str(), "sphere");
  auto r = test::run_cli(
      {"run", obj, "-o", dir.file("a.obj"), "-n", "3", "-q", "--gltf", dir.file("a.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::run_cli({"run", dir.file("a.glb"), "-o", dir.file("b.glb"), "-n", "10", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const tinygltf::Model a = test::load_glb(dir.file("a.glb")),
                        b = test::load_glb(dir.file("b.glb"));
  ASSERT_EQ(b.meshes.at(0).primitives.size(), a.meshes.at(0).primitives.size());
  for (std::size_t p = 0; p < a.meshes[0].primitives.size(); ++p) {
    EXPECT_EQ(b.meshes[0].primitives[p].material, a.meshes[0].primitives[p].material) << p;
    EXPECT_EQ(b.meshes[0].primitives[p].targets.size(), a.meshes[0].primitives[p].targets.size())
        << p;
  }
  EXPECT_EQ(attribute(a, "TEXCOORD_0"), attribute(b, "TEXCOORD_0"));
  EXPECT_EQ(b.animations.size(), a.animations.size());
  EXPECT_EQ(b.images.size(), a.images.size());
  EXPECT_GT((attribute(a, "POSITION") - attribute(b, "POSITION")).cwiseAbs().maxCoeff(), 1e-4f);
}

TEST(GltfInput, WhatCannotBeWrittenAsGltfIsRefusedBeforeTheRun) {
  ScratchDir dir("gltf_input_refused");
  const std::string off = std::string(test::MESH_DIR) + "/ico2.off";
  auto r = test::run_cli({"run", off, "-o", dir.file("out.glb"), "-n", "2", "-q"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("a .glb result is written only for a .glb input"), std::string::npos)
      << r.output;

  // One mesh drawn by two nodes: one file cannot hold two moved copies of its positions.
  test::GltfParts parts = test::gltf_parts(textured_scene());
  const std::string one = "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0,";
  parts.json.replace(parts.json.find(one), one.size(),
                     "\"scenes\":[{\"nodes\":[0,1]}],\"nodes\":[{\"mesh\":0,\"translation\":[-9,0,"
                     "0]},{\"mesh\":0,");
  const std::string twice = write(dir.file("twice.glb"), test::glb_bytes(parts));
  r = test::run_cli({"run", twice, "-o", dir.file("out.glb"), "-n", "2", "-q"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("is drawn by node 0 and node 1"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("out.glb")));
  r = test::run_cli({"run", twice, "-o", dir.file("out.obj"), "-n", "2", "-q"});  // two octahedra
  EXPECT_EQ(r.exit_code, 0) << r.output;

  // NORMAL shorter than POSITION: its elements are written by POSITION's numbers, so it is refused.
  test::GltfParts short_normals = test::gltf_parts(textured_scene());
  std::size_t at = 0;
  for (int k = 0; k < 3; ++k)
    at = short_normals.json.find("\"count\":7", at + 1);  // POSITION, TEXCOORD_0, NORMAL
  short_normals.json.replace(at, 9, "\"count\":5");
  const std::string normals = write(dir.file("normals.glb"), test::glb_bytes(short_normals));
  r = test::run_cli({"run", normals, "-o", dir.file("normals_out.glb"), "-n", "2", "-q"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("mesh 0 primitive 0 NORMAL (accessor 2) has 5 elements, POSITION 7"),
            std::string::npos)
      << r.output;

  const std::string bad = write(dir.file("cut.glb"),
                                test::glb_bytes(test::gltf_parts(textured_scene())).substr(0, 100));
  r = test::run_cli({"run", bad, "-o", dir.file("cut_out.glb"), "-n", "2", "-q"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("cut.glb: truncated .glb"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace shellcontract
