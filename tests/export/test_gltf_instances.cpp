// An instanced glTF input (docs/design/attributes.md, "glTF inputs"): one mesh drawn by two
// nodes is simulated as two shells, and the result gives the second node a copy of the mesh with
// POSITION and NORMAL accessors of its own, the other attributes shared. Before: refused before
// the run with exit 2 ("accessor 0 (mesh 0) is drawn by node 0 and node 1").
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <string>

#include "export/gltf_reader.hpp"
#include "export_fixtures.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/cli_runner.hpp"
#include "support/gltf_files.hpp"
#include "support/textured_octahedron.hpp"

namespace shellcontract {
namespace {

using test::ScratchDir;

/// The textured octahedron (split at a UV seam, with normals), mesh "Balloon", drawn by node
/// "left" at x = -3 and by node "right" at x = 4, turned a quarter about z and scaled by 2.
test::GltfParts instanced_parts() {
  test::GltfScene s;
  s.primitives.push_back(test::octahedron_primitive(true, true));
  s.node_transform =
      "\"translation\":[4,0,0],\"rotation\":[0,0,0.70710678,0.70710678],\"scale\":[2,2,2],"
      "\"name\":\"right\"";
  const auto& png = test::tiny_png();
  s.png.assign(png.begin(), png.end());
  test::GltfParts parts = test::gltf_parts(s);
  const std::string one = "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0,";
  parts.json.replace(parts.json.find(one), one.size(),
                     "\"scenes\":[{\"nodes\":[0,1]}],\"nodes\":[{\"mesh\":0,\"translation\":[-3,0,"
                     "0],\"name\":\"left\"},{\"mesh\":0,");
  const std::string mesh = "\"meshes\":[{";
  parts.json.replace(parts.json.find(mesh), mesh.size(), mesh + "\"name\":\"Balloon\",");
  return parts;
}

std::string write(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

tinygltf::Model parse(const std::string& bytes, bool binary) {
  tinygltf::Model m;
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&test::keep_image_undecoded, nullptr);
  std::string err, warn;
  const bool ok =
      binary ? loader.LoadBinaryFromMemory(&m, &err, &warn,
                                           reinterpret_cast<const unsigned char*>(bytes.data()),
                                           static_cast<unsigned int>(bytes.size()))
             : loader.LoadASCIIFromString(&m, &err, &warn, bytes.data(),
                                          static_cast<unsigned int>(bytes.size()), "");
  EXPECT_TRUE(ok) << err;
  return m;
}

/// Node k's local-to-world transform (a root node: translation * rotation * scale).
Eigen::Affine3d node_transform(const tinygltf::Node& n) {
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (!n.translation.empty())
    t.translate(Eigen::Vector3d(n.translation[0], n.translation[1], n.translation[2]));
  if (!n.rotation.empty())
    t.rotate(Eigen::Quaterniond(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2])
                 .normalized());
  if (!n.scale.empty()) t.scale(Eigen::Vector3d(n.scale[0], n.scale[1], n.scale[2]));
  return t;
}

/// The world positions of node k's POSITION accessor in the written file.
Positions world_positions(const tinygltf::Model& m, std::size_t k) {
  const tinygltf::Node& n = m.nodes.at(k);
  const auto& prim = m.meshes.at(static_cast<std::size_t>(n.mesh)).primitives.at(0);
  const test::Floats local = test::read_floats(m, prim.attributes.at("POSITION"));
  const Eigen::Affine3d t = node_transform(n);
  Positions out(local.rows(), 3);
  for (Eigen::Index i = 0; i < local.rows(); ++i)
    out.row(i) = (t * Eigen::Vector3d(local(i, 0), local(i, 1), local(i, 2))).transpose();
  return out;
}

/// The written document of an instanced file: both instances' new positions, each in its own
/// POSITION accessor, every other attribute shared.
void expect_two_instances(const tinygltf::Model& out, const Positions& x) {
  ASSERT_EQ(out.nodes.size(), 2u);
  ASSERT_EQ(out.meshes.size(), 2u);
  EXPECT_EQ(out.nodes[0].mesh, 0);
  EXPECT_EQ(out.nodes[1].mesh, 1);
  EXPECT_EQ(out.nodes[0].name, "left");
  EXPECT_EQ(out.nodes[1].name, "right");
  EXPECT_EQ(out.meshes[0].name, "Balloon");
  EXPECT_EQ(out.meshes[1].name, "Balloon (node right)");
  const tinygltf::Primitive &a = out.meshes[0].primitives.at(0),
                            &b = out.meshes[1].primitives.at(0);
  EXPECT_NE(a.attributes.at("POSITION"), b.attributes.at("POSITION"));
  EXPECT_NE(a.attributes.at("NORMAL"), b.attributes.at("NORMAL"));
  EXPECT_EQ(a.attributes.at("TEXCOORD_0"), b.attributes.at("TEXCOORD_0"));
  EXPECT_EQ(a.indices, b.indices);
  EXPECT_EQ(a.material, b.material);
  ASSERT_EQ(x.rows(), 14);  // 7 copies (the seam split) per instance, node 0's first
  for (std::size_t k = 0; k < 2; ++k) {
    const Positions w = world_positions(out, k);
    ASSERT_EQ(w.rows(), 7);
    EXPECT_LT((w - x.middleRows(static_cast<Eigen::Index>(7 * k), 7)).cwiseAbs().maxCoeff(), 1e-5)
        << "node " << k;
    const test::Floats n =
        test::read_floats(out, out.meshes[k].primitives[0].attributes.at("NORMAL"));
    for (Eigen::Index i = 0; i < n.rows(); ++i)
      EXPECT_NEAR(n.row(i).norm(), 1.0f, 1e-5f) << k << ' ' << i;
  }
}

TEST(GltfInstances, EachNodeOfAnInstancedMeshGetsItsOwnPositions) {
  for (const bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "glb" : "gltf");
    const test::GltfParts parts = instanced_parts();
    const std::string bytes = binary ? test::glb_bytes(parts) : test::gltf_text(parts);
    const auto doc = parse_gltf_document("balloons", bytes, binary);
    ASSERT_EQ(doc->vertex_count(), 14u);
    // New positions: each instance's read positions, moved by its own amounts.
    const tinygltf::Model in = parse(bytes, binary);
    Positions x(14, 3);
    for (std::size_t k = 0; k < 2; ++k)
      x.middleRows(static_cast<Eigen::Index>(7 * k), 7) = world_positions(in, k);
    for (Eigen::Index i = 0; i < 14; ++i)
      x.row(i) += Eigen::RowVector3d(0.01 * static_cast<double>(i), -0.02, i < 7 ? 0.5 : -0.25);
    const tinygltf::Model out = parse(doc->text(x), binary);
    expect_two_instances(out, x);
    // The first instance keeps the input's accessors.
    EXPECT_EQ(out.meshes[0].primitives[0].attributes, in.meshes[0].primitives[0].attributes);
  }
}

TEST(GltfInstances, AnInstancedGlbRunsAndReadsBackAsTheSameComponents) {
  ScratchDir dir("gltf_instances_run");
  const std::string in = write(dir.file("balloons.glb"), test::glb_bytes(instanced_parts()));
  auto r = test::run_cli({"run", in, "-o", dir.file("out.glb"), "-n", "8", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::run_cli({"run", in, "-o", dir.file("out.off"), "-n", "8", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The OFF holds the simulated positions of every copy, in the document's vertex order.
  const Mesh off = read_input_mesh(dir.file("out.off"));
  expect_two_instances(test::load_glb(dir.file("out.glb")),
                       input_positions(off, positions_from_mesh(off)));
  for (const std::string& file : {in, dir.file("out.glb")}) {
    r = test::run_cli({"check", file});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("\ncomponents: 2\n"), std::string::npos) << file << r.output;
    EXPECT_NE(r.output.find("\nusable: yes\n"), std::string::npos) << file << r.output;
  }
}

// A POSITION accessor shared by two meshes, each drawn by its own node: the second mesh is
// the first that its node draws, so its primitive is given a new accessor in place.
TEST(GltfInstances, APositionAccessorSharedByTwoMeshesIsSplitInPlace) {
  test::GltfParts parts = instanced_parts();
  const std::string prims = "\"primitives\":[";
  const std::size_t from = parts.json.find(prims), to = parts.json.find("]}],\"accessors\"");
  const std::string primitive = parts.json.substr(from, to + 1 - from);
  parts.json.insert(to + 2, ",{\"name\":\"twin\"," + primitive + "}");
  const std::string second = "{\"mesh\":0,\"translation\":[4";
  parts.json.replace(parts.json.find(second), second.size(), "{\"mesh\":1,\"translation\":[4");
  const std::string bytes = test::glb_bytes(parts);
  const tinygltf::Model in = parse(bytes, true);
  ASSERT_EQ(in.meshes.size(), 2u);
  ASSERT_EQ(in.meshes[1].primitives.at(0).attributes, in.meshes[0].primitives.at(0).attributes);
  const auto doc = parse_gltf_document("twins.glb", bytes, true);
  Positions x(14, 3);
  for (std::size_t k = 0; k < 2; ++k)
    x.middleRows(static_cast<Eigen::Index>(7 * k), 7) = world_positions(in, k) * 1.25;
  const tinygltf::Model out = parse(doc->text(x), true);
  ASSERT_EQ(out.meshes.size(), 2u);
  EXPECT_EQ(out.meshes[1].name, "twin");
  EXPECT_EQ(out.nodes[1].mesh, 1);
  EXPECT_NE(out.meshes[1].primitives[0].attributes.at("POSITION"),
            out.meshes[0].primitives[0].attributes.at("POSITION"));
  for (std::size_t k = 0; k < 2; ++k)
    EXPECT_LT((world_positions(out, k) - x.middleRows(static_cast<Eigen::Index>(7 * k), 7))
                  .cwiseAbs()
                  .maxCoeff(),
              1e-5)
        << k;
}

}  // namespace
}  // namespace shellcontract
