// A glTF input through `shellcontract run` (docs/design/attributes.md, "glTF inputs"): a .glb
// result is the input .glb with new positions and normals, everything else kept (texture
// coordinates per vertex, the node's transform, the material and its image); seam copies move
// together; other outputs are written from it like from any input. Before: "unknown extension
// '.glb'" (exit 2) for every input here, and "-o x.glb" was bad usage.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
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
  // A glTF's vertices are the reader's, per node: the note does not pass them off as the
  // file's (a mesh drawn by two nodes counts its elements twice).
  EXPECT_NE(r.output.find("vertices (counted per glTF node drawing them) include copies"),
            std::string::npos)
      << r.output;
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
  EXPECT_NE(r.output.find("use --gltf FILE.glb"), std::string::npos) << r.output;

  // (An instanced mesh, refused here before, is written: test_gltf_instances.cpp.)

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

// Normals of a glTF result where the file shades hard edges: glTF has no smoothing groups, so an
// exporter makes a hard edge by giving each side its own copies of the vertices there, each
// with its side's normal. Those copies move together (welded), but their new normals stay apart.

/// The outward normal of side `axis` (0 x, 1 y, 2 z), `sign` -1 or 1, of the box [-1, 1]^3.
std::array<float, 3> axis_normal(int axis, int sign) {
  std::array<float, 3> n{0, 0, 0};
  n[static_cast<std::size_t>(axis)] = static_cast<float>(sign);
  return n;
}

/// The corner (a, b) of that side, a and b its coordinates along the next two axes.
std::array<float, 3> side_corner(int axis, int sign, float a, float b) {
  std::array<float, 3> q{};
  q[static_cast<std::size_t>(axis)] = static_cast<float>(sign);
  q[static_cast<std::size_t>((axis + 1) % 3)] = a;
  q[static_cast<std::size_t>((axis + 2) % 3)] = b;
  return q;
}

/// Appends a quad's two triangles (corners first..first + 3 in order around it), wound outwards:
/// the corners go counterclockwise about the next two axes' cross product, the side's +axis.
void add_quad(test::GltfPrimitive& p, std::uint32_t first, bool reverse) {
  const std::uint32_t q[2][3] = {{0, 1, 2}, {0, 2, 3}};
  for (const auto& t : q)
    for (int k = 0; k < 3; ++k) p.indices.push_back(first + t[reverse ? (3 - k) % 3 : k]);
}

/// One flat side: four corners of its own, each with the side's normal (flat shading).
void add_flat_side(test::GltfPrimitive& p, int axis, int sign) {
  const auto first = static_cast<std::uint32_t>(p.positions.size());
  const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (const auto& ab : corners) {
    p.positions.push_back(side_corner(axis, sign, ab[0], ab[1]));
    p.normals.push_back(axis_normal(axis, sign));
  }
  add_quad(p, first, sign < 0);
}

/// An affine map: every side stays flat, but its normal turns away from its axis, each side's
/// its own way, so the normals a result must have are the sides' at the new positions.
Eigen::Vector3d moved(const std::array<float, 3>& p) {
  Eigen::Matrix3d a;
  a << 2.0, 0.5, 0.0, 0.0, 1.0, 0.25, 0.1, 0.0, 1.5;
  return a * Eigen::Vector3d(p[0], p[1], p[2]) + Eigen::Vector3d(0.3, -0.2, 0.1);
}

/// The scene's vertices moved (simulation order: primitive by primitive, in accessor order).
Positions moved_positions(const test::GltfScene& s) {
  std::vector<Eigen::Vector3d> rows;
  for (const auto& p : s.primitives)
    for (const auto& q : p.positions) rows.push_back(moved(q));
  Positions x(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t i = 0; i < rows.size(); ++i) x.row(static_cast<Eigen::Index>(i)) = rows[i];
  return x;
}

/// Twice the triangle's area along its normal, at the moved positions.
Eigen::Vector3d area_normal(const test::GltfPrimitive& p, std::size_t t) {
  const Eigen::Vector3d a = moved(p.positions[p.indices[3 * t]]),
                        b = moved(p.positions[p.indices[3 * t + 1]]),
                        c = moved(p.positions[p.indices[3 * t + 2]]);
  return (b - a).cross(c - a);
}

/// The document of the scene's .glb written with x, read back.
tinygltf::Model written(const ScratchDir& dir, const test::GltfScene& s, const Positions& x) {
  const auto doc = parse_gltf_document("in.glb", test::glb_bytes(test::gltf_parts(s)), true);
  return test::load_glb(write(dir.file("out.glb"), doc->text(x)));
}

TEST(GltfInput, AFlatShadedBoxKeepsItsHardEdges) {
  ScratchDir dir("gltf_input_flat");
  // The x and y sides in one primitive, the z sides in another: hard edges within a primitive
  // and across two.
  test::GltfScene s;
  s.primitives.resize(2);
  for (int axis = 0; axis < 3; ++axis)
    for (const int sign : {-1, 1}) add_flat_side(s.primitives[axis == 2 ? 1 : 0], axis, sign);
  const tinygltf::Model b = written(dir, s, moved_positions(s));
  for (std::size_t k = 0; k < 2; ++k) {
    const test::GltfPrimitive& p = s.primitives[k];
    const test::Floats n =
        test::read_floats(b, b.meshes.at(0).primitives.at(k).attributes.at("NORMAL"));
    ASSERT_EQ(n.rows(), static_cast<Eigen::Index>(p.positions.size()));
    for (std::size_t side = 0; side < p.positions.size() / 4; ++side) {
      // The side's normal at the new positions (flat: both of its triangles give it).
      const Eigen::Vector3d want = area_normal(p, 2 * side).normalized();
      EXPECT_LT((area_normal(p, 2 * side + 1).normalized() - want).norm(), 1e-12);
      for (std::size_t c = 4 * side; c < 4 * side + 4; ++c)
        EXPECT_LT((n.row(static_cast<Eigen::Index>(c)).cast<double>().transpose() - want).norm(),
                  1e-6)
            << "primitive " << k << " corner " << c << ": " << n.row(static_cast<Eigen::Index>(c))
            << ", the side's normal is " << want.transpose();
    }
  }
}

TEST(GltfInput, ASmoothBandBetweenFlatCapsKeepsBothAndItsSeamShowsNot) {
  ScratchDir dir("gltf_input_band");
  // The box's four sides smooth-shaded (each corner's normal the horizontal diagonal through
  // it), split at a UV seam (the last column repeats the first, same normal, u = 1), between
  // flat top and bottom caps with their own corners: two hard edges and one seam.
  test::GltfScene s;
  s.primitives.resize(1);
  test::GltfPrimitive& p = s.primitives[0];
  test::add_smooth_band_with_seam(p);  // one copy's normal a float rounding off: the same
  const std::size_t band_triangles = p.indices.size() / 3;
  for (const int sign : {-1, 1}) {
    const std::size_t first = p.positions.size();
    add_flat_side(p, 2, sign);
    for (std::size_t c = first; c < p.positions.size(); ++c) p.texcoords.push_back({0.5f, 0.5f});
  }
  ASSERT_EQ(p.positions.size(), 18u);
  const tinygltf::Model b = written(dir, s, moved_positions(s));
  const test::Floats n =
      test::read_floats(b, b.meshes.at(0).primitives.at(0).attributes.at("NORMAL"));
  ASSERT_EQ(n.rows(), 18);
  const auto normal = [&](std::size_t v) {
    return Eigen::Vector3d(n.row(static_cast<Eigen::Index>(v)).cast<double>().transpose());
  };
  // A band corner: the area-weighted sum over the band's triangles at its position (the seam
  // copies' too), not the caps'.
  for (std::size_t v = 0; v < 10; ++v) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (std::size_t t = 0; t < band_triangles; ++t)
      for (std::size_t k = 0; k < 3; ++k)
        if (p.positions[p.indices[3 * t + k]] == p.positions[v]) sum += area_normal(p, t);
    EXPECT_LT((normal(v) - sum.normalized()).norm(), 1e-6)
        << "band corner " << v << ": " << normal(v).transpose() << ", the band's "
        << sum.normalized().transpose();
  }
  // The seam copies: one normal, bit for bit.
  EXPECT_EQ(n.row(0), n.row(8));
  EXPECT_EQ(n.row(1), n.row(9));
  // A cap corner: the cap's normal.
  for (std::size_t cap = 0; cap < 2; ++cap) {
    const Eigen::Vector3d want = area_normal(p, band_triangles + 2 * cap).normalized();
    for (std::size_t v = 10 + 4 * cap; v < 14 + 4 * cap; ++v)
      EXPECT_LT((normal(v) - want).norm(), 1e-6)
          << "cap corner " << v << ": " << normal(v).transpose() << ", the cap's "
          << want.transpose();
  }
}

}  // namespace
}  // namespace shellcontract
