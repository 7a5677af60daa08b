// One glTF primitive per material (docs/design/export.md, "Name and material"): an OBJ whose faces
// use several materials keeps every one in the .glb, each primitive with exactly its faces (read
// here from the OBJ's usemtl lines, not from the writer), its own material and texture, and the
// same attributes and morph targets as the others; faces of no material (or an undefined one) go
// into a primitive without material. Before, the material of most faces was kept for all of them.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "export_fixtures.hpp"
#include "gltf_reader.hpp"
#include "shellcontract/export.hpp"
#include "support/cgal_volume.hpp"
#include "support/cli_runner.hpp"
#include "support/multi_material_sphere.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using Triangle = std::array<std::uint32_t, 3>;

/// A triangle turned so that its smallest index comes first (the same face, the same orientation).
Triangle canonical(Triangle t) {
  std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  return t;
}

/// The OBJ's faces per material as its lines say, materials in the order of their first face;
/// a face after no usemtl, or of a material not in `defined`, is under "".
std::vector<std::pair<std::string, std::vector<Triangle>>> faces_by_usemtl(
    const std::string& path, const std::set<std::string>& defined) {
  std::vector<std::pair<std::string, std::vector<Triangle>>> out;
  std::ifstream in(path);
  std::string line, current;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string key;
    s >> key;
    if (key == "usemtl") {
      current.clear();
      s >> current;
    } else if (key == "f") {
      Triangle t{};
      std::string corner;
      for (std::uint32_t& i : t) {
        s >> corner;
        i = static_cast<std::uint32_t>(std::stoul(corner.substr(0, corner.find('/')))) - 1;
      }
      const std::string m = defined.count(current) ? current : "";
      auto it = std::find_if(out.begin(), out.end(), [&](const auto& g) { return g.first == m; });
      if (it == out.end()) it = out.insert(out.end(), {m, {}});
      it->second.push_back(canonical(t));
    }
  }
  return out;
}

std::size_t count_of(const std::string& text, const std::string& s) {
  std::size_t n = 0;
  for (std::size_t at = text.find(s); at != std::string::npos; at = text.find(s, at + 1)) ++n;
  return n;
}

TEST(GltfPrimitives, EachMaterialOfAnObjIsAPrimitiveWithExactlyItsFaces) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("primitives");
  const std::string obj = test::write_multi_material_sphere(dir.str(), "head");
  const std::string frames = dir.file("frames");
  fs::create_directories(frames);
  const auto r = test::run_cli({"run", obj, "-o", dir.file("run.off"), "-n", "6", "-q",
                                "--export-every", "2", "--export-dir", frames, "--gltf",
                                dir.file("run.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The one real problem, named with the OBJ; nothing is "dropped" any more.
  EXPECT_NE(r.output.find("warning: " + obj + ": material 'ghost' is defined in none"),
            std::string::npos)
      << r.output;
  // And the -o .off result's: it drops the OBJ's attributes, which is said (run_document.cpp).
  EXPECT_NE(r.output.find("warning: the result is written without the input's attributes: it is "
                          "a .off file"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(count_of(r.output, "warning"), 2u) << r.output;

  std::set<std::string> defined;
  for (const test::SphereMaterial& sm : test::sphere_materials()) defined.insert(sm.name);
  const auto groups = faces_by_usemtl(obj, defined);
  ASSERT_EQ(groups.size(), 4u);  // none (the first faces and ghost's), eyes, body, teeth

  const tinygltf::Model m = test::load_glb(dir.file("run.glb"));
  ASSERT_EQ(m.meshes.size(), 1u);
  const tinygltf::Mesh& mesh = m.meshes[0];
  ASSERT_EQ(mesh.primitives.size(), groups.size());
  ASSERT_EQ(m.materials.size(), 3u);
  const tinygltf::Primitive& p0 = mesh.primitives[0];
  std::set<int> index_accessors;
  for (std::size_t k = 0; k < groups.size(); ++k) {
    const tinygltf::Primitive& p = mesh.primitives[k];
    const std::string name = p.material < 0 ? "" : m.materials.at(static_cast<std::size_t>(p.material)).name;
    EXPECT_EQ(name, groups[k].first) << "primitive " << k;
    EXPECT_EQ(p.mode, TINYGLTF_MODE_TRIANGLES);
    // Its faces, in the OBJ's order (seamless texture coordinates: glTF vertex i is OBJ vertex i).
    const std::vector<std::uint32_t> idx = test::read_indices(m, p.indices);
    ASSERT_EQ(idx.size(), 3 * groups[k].second.size()) << "primitive " << k;
    for (std::size_t f = 0; f < groups[k].second.size(); ++f)
      EXPECT_EQ(canonical({idx[3 * f], idx[3 * f + 1], idx[3 * f + 2]}), groups[k].second[f])
          << "primitive " << k << " ('" << name << "'), face " << f;
    index_accessors.insert(p.indices);
    // Everything else is the same accessors for every primitive.
    EXPECT_EQ(p.attributes, p0.attributes) << "primitive " << k;
    EXPECT_EQ(p.targets, p0.targets) << "primitive " << k;
  }
  EXPECT_EQ(index_accessors.size(), groups.size());
  EXPECT_TRUE(p0.attributes.count("TEXCOORD_0"));
  EXPECT_FALSE(p0.attributes.count("COLOR_0"));  // it would multiply the materials' colours
  EXPECT_EQ(mesh.weights.size(), p0.targets.size());

  // Each material as its .mtl says; body and teeth name the same PNG: one image, one texture.
  ASSERT_EQ(m.images.size(), 1u);
  ASSERT_EQ(m.textures.size(), 1u);
  const tinygltf::BufferView& view = m.bufferViews.at(static_cast<std::size_t>(m.images[0].bufferView));
  const auto* b = m.buffers.at(0).data.data() + view.byteOffset;
  EXPECT_EQ(std::vector<unsigned char>(b, b + view.byteLength), test::tiny_png());
  EXPECT_EQ(m.images[0].mimeType, "image/png");
  for (const test::SphereMaterial& sm : test::sphere_materials()) {
    const auto mat = std::find_if(m.materials.begin(), m.materials.end(),
                                  [&](const tinygltf::Material& x) { return x.name == sm.name; });
    ASSERT_NE(mat, m.materials.end()) << sm.name;
    const auto& pbr = mat->pbrMetallicRoughness;
    EXPECT_EQ(pbr.baseColorFactor, (std::vector<double>{sm.r, sm.g, sm.b, sm.alpha})) << sm.name;
    EXPECT_EQ(pbr.metallicFactor, 0.0) << sm.name;
    EXPECT_EQ(mat->alphaMode, sm.alpha < 1.0 ? "BLEND" : "OPAQUE") << sm.name;
    EXPECT_EQ(pbr.baseColorTexture.index, sm.textured ? 0 : -1) << sm.name;
  }

  // The morph targets: every keyframe is the frame file of the same frame (test_cli_run_export).
  const std::vector<int> want_frames = {0, 2, 4, 6};
  ASSERT_EQ(p0.targets.size() + 1, want_frames.size());
  const test::Floats base = test::read_positions(m, p0.attributes.at("POSITION"));
  const Positions first = test::cgal_read_positions(frames + "/run_0.off");
  const double tol = 4.0 * first.cwiseAbs().maxCoeff() * std::numeric_limits<float>::epsilon();
  double motion = 0.0;
  for (std::size_t k = 0; k < want_frames.size(); ++k) {
    const Positions file = test::cgal_read_positions(frames + "/run_" + std::to_string(want_frames[k]) + ".off");
    test::Floats xk = base;
    if (k > 0) xk += test::read_floats(m, p0.targets[k - 1].at("POSITION"));
    ASSERT_EQ(xk.rows(), file.rows());
    EXPECT_LE((xk.cast<double>() - file).cwiseAbs().maxCoeff(), tol) << "frame " << want_frames[k];
    motion = std::max(motion, (file - first).cwiseAbs().maxCoeff());
  }
  EXPECT_GT(motion, 100.0 * tol);
}

/// A tetrahedron, one frame, for the library's own checks.
GltfAnimation tetrahedron() {
  GltfAnimation a;
  a.faces.resize(4, 3);
  a.faces << 0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2;
  Positions x(4, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  a.frames = {x, 0.9 * x};
  a.frame_numbers = {0, 1};
  return a;
}

TEST(GltfPrimitives, FacesWithoutMaterialGetAPrimitiveWithout) {
  test::ScratchDir dir("primitives_none");
  GltfAnimation a = tetrahedron();
  a.materials = {GltfMaterial{"red", {1, 0, 0, 1}, {}, ""}};
  a.face_material = {-1, 0, -1, 0};
  write_gltf_animation(dir.file("a.glb"), a);
  const tinygltf::Model m = test::load_glb(dir.file("a.glb"));
  const auto& prims = m.meshes.at(0).primitives;
  ASSERT_EQ(prims.size(), 2u);  // in the order of their first face
  EXPECT_EQ(prims[0].material, -1);
  EXPECT_EQ(prims[1].material, 0);
  ASSERT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(m.materials[0].name, "red");
  EXPECT_EQ(test::read_indices(m, prims[0].indices), (std::vector<std::uint32_t>{0, 2, 1, 1, 2, 3}));
  EXPECT_EQ(test::read_indices(m, prims[1].indices), (std::vector<std::uint32_t>{0, 1, 3, 0, 3, 2}));
  EXPECT_EQ(prims[0].targets, prims[1].targets);
  EXPECT_EQ(prims[0].targets.size(), 1u);
}

TEST(GltfPrimitives, OneMaterialForEveryFaceIsOnePrimitiveWhicheverWayItIsSaid) {
  test::ScratchDir dir("primitives_one");
  GltfAnimation a = tetrahedron();
  a.materials = {GltfMaterial{"red", {1, 0, 0, 1}, {}, ""}};
  write_gltf_animation(dir.file("implicit.glb"), a);  // face_material empty: every face material 0
  a.face_material = {0, 0, 0, 0};
  write_gltf_animation(dir.file("explicit.glb"), a);
  EXPECT_EQ(test::read_bytes(dir.file("implicit.glb")), test::read_bytes(dir.file("explicit.glb")));
  const tinygltf::Model m = test::load_glb(dir.file("explicit.glb"));
  ASSERT_EQ(m.meshes.at(0).primitives.size(), 1u);
  EXPECT_EQ(m.meshes[0].primitives[0].material, 0);
  EXPECT_EQ(test::read_indices(m, m.meshes[0].primitives[0].indices).size(), 12u);
  // A material no face uses is not written.
  a.materials.push_back(GltfMaterial{"unused", {0, 1, 0, 1}, {}, ""});
  write_gltf_animation(dir.file("unused.glb"), a);
  EXPECT_EQ(test::load_glb(dir.file("unused.glb")).materials.size(), 1u);
}

TEST(GltfPrimitives, TheSameImageIsEmbeddedOnceAndAnotherSeparately) {
  test::ScratchDir dir("primitives_images");
  GltfAnimation a = tetrahedron();
  a.uv.resize(1, 2);
  a.uv << 0.5, 0.5;
  a.face_uv = Faces::Zero(4, 3);
  std::vector<unsigned char> other = test::tiny_png();
  other.push_back(0);  // other bytes, still a PNG by its signature
  a.materials = {GltfMaterial{"a", {1, 1, 1, 1}, test::tiny_png(), "image/png"},
                 GltfMaterial{"b", {1, 1, 1, 1}, test::tiny_png(), "image/png"},
                 GltfMaterial{"c", {1, 1, 1, 1}, other, "image/png"}};
  a.face_material = {0, 1, 2, 1};
  write_gltf_animation(dir.file("a.glb"), a);
  const tinygltf::Model m = test::load_glb(dir.file("a.glb"));
  ASSERT_EQ(m.materials.size(), 3u);
  EXPECT_EQ(m.images.size(), 2u);
  EXPECT_EQ(m.textures.size(), 2u);
  EXPECT_EQ(m.samplers.size(), 1u);
  const auto tex = [&](std::size_t i) { return m.materials[i].pbrMetallicRoughness.baseColorTexture.index; };
  EXPECT_EQ(tex(0), tex(1));
  EXPECT_NE(tex(0), tex(2));
}

TEST(GltfPrimitives, AWrongFaceMaterialIsRefused) {
  test::ScratchDir dir("primitives_bad");
  GltfAnimation a = tetrahedron();
  a.materials = {GltfMaterial{"red", {1, 0, 0, 1}, {}, ""}};
  for (const std::vector<int>& bad : {std::vector<int>{0, 0, 0}, std::vector<int>{0, 1, 0, 0},
                                      std::vector<int>{0, -2, 0, 0}}) {
    a.face_material = bad;
    EXPECT_THROW(write_gltf_animation(dir.file("a.glb"), a), std::invalid_argument)
        << ::testing::PrintToString(bad);
  }
  a.materials.clear();
  a.face_material = {0, 0, 0, 0};
  EXPECT_THROW(write_gltf_animation(dir.file("a.glb"), a), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir.file("a.glb")));
}

}  // namespace
}  // namespace shellcontract
