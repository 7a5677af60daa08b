// The glTF of a textured input: TEXCOORD_0 per corner as the OBJ gave it, vertices
// split at UV seams with their copies moving together in every morph target, and each colour
// field's values as a custom attribute named after it. Read back with tinygltf's loader and
// compared with what tests/support/textured_obj.hpp wrote.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "export_fixtures.hpp"
#include "gltf_reader.hpp"
#include "shellcontract/export.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/textured_obj.hpp"

namespace shellcontract {
namespace {

std::vector<std::uint32_t> read_indices(const tinygltf::Model& m, int index) {
  const tinygltf::Accessor& acc = m.accessors.at(static_cast<std::size_t>(index));
  EXPECT_EQ(acc.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
  const tinygltf::BufferView& view = m.bufferViews.at(static_cast<std::size_t>(acc.bufferView));
  std::vector<std::uint32_t> idx(acc.count);
  std::memcpy(idx.data(), m.buffers[0].data.data() + view.byteOffset + acc.byteOffset, 4 * acc.count);
  return idx;
}

TEST(GltfTexcoords, SeamsAreSplitAndEveryCornerHasItsFileCoordinates) {
  const int nlat = 8, nlon = 12;
  const test::TexturedObj t = test::textured_uv_sphere(nlat, nlon);
  test::ScratchDir dir("texcoords");
  const std::string obj = dir.file("ball.obj");
  std::ofstream(obj) << t.text;
  const Mesh mesh = read_input_mesh(obj);
  const auto doc = read_mesh_document(obj);
  ASSERT_TRUE(doc->matches(mesh));
  const CornerTexcoords tc = doc->texcoords(mesh);

  GltfAnimation a;
  a.faces = test::faces_of(mesh);
  const Positions x0 = positions_from_mesh(mesh);
  for (int f = 0; f <= 20; f += 10) {
    a.frame_numbers.push_back(f);
    a.frames.push_back(test::fake_frame(x0, f, 20));
  }
  a.colour_fields.push_back({"mean curvature", x0.col(2)});
  a.uv.resize(static_cast<Eigen::Index>(tc.uv.size()), 2);
  for (std::size_t i = 0; i < tc.uv.size(); ++i) a.uv.row(static_cast<Eigen::Index>(i)) << tc.uv[i][0], tc.uv[i][1];
  a.face_uv.resize(a.faces.rows(), 3);
  for (std::size_t f = 0; f < tc.face_uv.size(); ++f)
    for (int k = 0; k < 3; ++k) a.face_uv(static_cast<Eigen::Index>(f), k) = static_cast<int>(tc.face_uv[f][static_cast<std::size_t>(k)]);
  // Each frame's own values of a field: here the frame's z coordinates.
  a.frame_fields.push_back({"height", {}});
  for (const Positions& x : a.frames) a.frame_fields[0].second.push_back(x.col(2).cast<float>());
  const std::string glb = dir.file("ball.glb");
  write_gltf_animation(glb, a);

  const tinygltf::Model m = test::load_glb(glb);
  const tinygltf::Primitive& p = m.meshes.at(0).primitives.at(0);
  ASSERT_TRUE(p.attributes.count("TEXCOORD_0"));
  const test::Floats pos = test::read_positions(m, p.attributes.at("POSITION"));
  const test::Floats uv = test::read_floats(m, p.attributes.at("TEXCOORD_0"));
  // The seam: each of the nlat - 1 rings' vertex at longitude 0 has u = 0 and u = 1; each pole
  // has nlon coordinates. So many copies, no more.
  const Eigen::Index nv = x0.rows();
  EXPECT_EQ(pos.rows(), nv + (nlat - 1) + 2 * (nlon - 1));
  ASSERT_EQ(uv.rows(), pos.rows());

  // Every corner: the glTF vertex is at its simulation vertex's place and has the coordinates
  // the file gave that corner (v flipped: glTF's origin is the top left).
  const std::vector<std::uint32_t> idx = read_indices(m, p.indices);
  ASSERT_EQ(idx.size(), static_cast<std::size_t>(a.faces.size()));
  std::vector<Eigen::Index> source(static_cast<std::size_t>(pos.rows()), -1);
  for (Eigen::Index f = 0; f < a.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t g = idx[static_cast<std::size_t>(3 * f + k)];
      const int v = a.faces(f, k);
      source[g] = v;
      for (int c = 0; c < 3; ++c) EXPECT_EQ(pos(g, c), static_cast<float>(x0(v, c)));
      // The generator's coordinates of vertex v in the polygon that holds face f.
      std::size_t expected = SIZE_MAX;
      for (const auto& poly : t.polygons) {
        int hits = 0;
        std::size_t at_v = SIZE_MAX;
        for (const auto& corner : poly) {
          for (int q = 0; q < 3; ++q) hits += corner[0] == static_cast<std::size_t>(a.faces(f, q));
          if (corner[0] == static_cast<std::size_t>(v)) at_v = corner[1];
        }
        if (hits == 3) expected = at_v;
      }
      ASSERT_NE(expected, SIZE_MAX);
      EXPECT_EQ(uv(g, 0), static_cast<float>(t.uv[expected][0])) << "face " << f;
      EXPECT_EQ(uv(g, 1), static_cast<float>(1.0 - t.uv[expected][1])) << "face " << f;
    }
  // Copies move with their vertex: in every morph target, a copy's displacement is its source's.
  for (const auto& target : p.targets) {
    const test::Floats d = test::read_floats(m, target.at("POSITION"));
    for (Eigen::Index g = 0; g < d.rows(); ++g) {
      ASSERT_GE(source[static_cast<std::size_t>(g)], 0);
      EXPECT_EQ(d.row(g), d.row(source[static_cast<std::size_t>(g)])) << "vertex " << g;
    }
  }
  // The field's values under its name, per glTF vertex.
  ASSERT_TRUE(p.attributes.count("_MEAN_CURVATURE"));
  const test::Floats values = test::read_floats(m, p.attributes.at("_MEAN_CURVATURE"));
  for (Eigen::Index g = 0; g < values.rows(); ++g)
    EXPECT_EQ(values(g, 0), static_cast<float>(x0(source[static_cast<std::size_t>(g)], 2)));
  const tinygltf::Value& info = m.meshes[0].extras.Get("colour_fields").Get(0);
  EXPECT_EQ(info.Get("values_attribute").Get<std::string>(), "_MEAN_CURVATURE");

  // The per-frame field: one accessor per frame, frame k's z per glTF vertex (copies too), and
  // one scale: the 2nd and 98th percentiles of all frames' values (nearest rank, computed here).
  const tinygltf::Value& ff = m.meshes[0].extras.Get("frame_fields").Get(0);
  EXPECT_EQ(ff.Get("name").Get<std::string>(), "height");
  ASSERT_EQ(ff.Get("accessors").ArrayLen(), a.frames.size());
  std::vector<float> all;
  for (std::size_t k = 0; k < a.frames.size(); ++k) {
    const test::Floats v = test::read_floats(m, ff.Get("accessors").Get(static_cast<int>(k)).GetNumberAsInt());
    ASSERT_EQ(v.rows(), pos.rows());
    for (Eigen::Index g = 0; g < v.rows(); ++g)
      EXPECT_EQ(v(g, 0), static_cast<float>(a.frames[k](source[static_cast<std::size_t>(g)], 2))) << "frame " << k;
    for (Eigen::Index i = 0; i < nv; ++i) all.push_back(static_cast<float>(a.frames[k](i, 2)));
  }
  std::sort(all.begin(), all.end());
  EXPECT_EQ(ff.Get("low").GetNumberAsDouble(), all[static_cast<std::size_t>(std::lround(0.02 * static_cast<double>(all.size() - 1)))]);
  EXPECT_EQ(ff.Get("high").GetNumberAsDouble(), all[static_cast<std::size_t>(std::lround(0.98 * static_cast<double>(all.size() - 1)))]);
}

TEST(GltfTexcoords, WithoutCoordinatesNothingIsSplit) {
  test::ScratchDir dir("texcoords_none");
  const test::TexturedObj t = test::textured_uv_sphere(5, 6);
  const std::string obj = dir.file("ball.obj");
  std::ofstream(obj) << t.text;
  const Mesh mesh = read_input_mesh(obj);
  GltfAnimation a;
  a.faces = test::faces_of(mesh);
  a.frame_numbers = {0};
  a.frames = {positions_from_mesh(mesh)};
  write_gltf_animation(dir.file("plain.glb"), a);
  const tinygltf::Model m = test::load_glb(dir.file("plain.glb"));
  const tinygltf::Primitive& p = m.meshes.at(0).primitives.at(0);
  EXPECT_FALSE(p.attributes.count("TEXCOORD_0"));
  EXPECT_EQ(m.accessors.at(static_cast<std::size_t>(p.attributes.at("POSITION"))).count, static_cast<std::size_t>(mesh.number_of_vertices()));
}

TEST(GltfTexcoords, AnIndexOutOfRangeIsRefused) {
  GltfAnimation a;
  a.faces.resize(1, 3);
  a.faces << 0, 1, 2;
  a.frame_numbers = {0};
  a.frames = {Positions::Identity(3, 3)};
  a.uv.resize(2, 2);
  a.uv << 0, 0, 1, 1;
  a.face_uv.resize(1, 3);
  a.face_uv << 0, 1, 2;
  EXPECT_THROW(write_gltf_animation("/nonexistent/x.glb", a), std::invalid_argument);
}

}  // namespace
}  // namespace shellcontract
