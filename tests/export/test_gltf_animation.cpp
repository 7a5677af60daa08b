// write_gltf_animation: the .glb read back with tinygltf's own loader gives every frame's positions
// (base + morph displacement) to float precision, unit normals, one keyframe per frame.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "export_fixtures.hpp"
#include "gltf_reader.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/export.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

GltfAnimation sphere_animation(int frames, int every) {
  const test::TriMesh s = test::icosphere(3, 2.5);
  Positions x = s.x;
  x.col(0).array() += 40.0;  // far from the origin: the float error must be relative to the size
  GltfAnimation a;
  a.faces = s.faces;
  for (int f = 0; f <= frames; f += every) {
    a.frame_numbers.push_back(f);
    a.frames.push_back(test::fake_frame(x, f, frames));
  }
  a.seconds_per_frame = 0.05;
  a.colour_fields.push_back({"height", x.col(2)});
  a.colour_fields.push_back({"wave", x.col(0).array().sin().matrix()});
  return a;
}

TEST(GltfAnimation, EveryFrameReadsBackToFloatPrecision) {
  test::ScratchDir dir("gltf");
  const GltfAnimation a = sphere_animation(40, 5);
  const std::string path = dir.file("sphere.glb");
  const GltfStats stats = write_gltf_animation(path, a);
  EXPECT_EQ(stats.bytes, std::filesystem::file_size(path));

  const tinygltf::Model m = test::load_glb(path);
  ASSERT_EQ(m.meshes.size(), 1u);
  ASSERT_EQ(m.meshes[0].primitives.size(), 1u);
  const tinygltf::Primitive& p = m.meshes[0].primitives[0];
  const std::size_t nk = a.frames.size();
  ASSERT_EQ(p.targets.size(), nk - 1);

  // Indices: the faces in order.
  {
    const tinygltf::Accessor& acc = m.accessors.at(static_cast<std::size_t>(p.indices));
    ASSERT_EQ(acc.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
    ASSERT_EQ(acc.count, static_cast<std::size_t>(a.faces.size()));
    const tinygltf::BufferView& view = m.bufferViews.at(static_cast<std::size_t>(acc.bufferView));
    std::vector<std::uint32_t> idx(acc.count);
    std::memcpy(idx.data(), m.buffers[0].data.data() + view.byteOffset + acc.byteOffset,
                4 * acc.count);
    for (Eigen::Index i = 0; i < a.faces.size(); ++i)
      ASSERT_EQ(idx[static_cast<std::size_t>(i)], static_cast<std::uint32_t>(a.faces.data()[i]))
          << "index " << i;
  }

  const test::Floats x0 = test::read_positions(m, p.attributes.at("POSITION"));
  const test::Floats n0 = test::read_floats(m, p.attributes.at("NORMAL"));
  const double size = (a.frames[0].colwise().maxCoeff() - a.frames[0].colwise().minCoeff()).norm();
  const double extent = a.frames[0].cwiseAbs().maxCoeff();
  // One float rounding of the base and one of the displacement and the sum: a few ulps of the
  // coordinates' magnitude.
  const double tol = 4.0 * extent * std::numeric_limits<float>::epsilon();
  ASSERT_LT(tol, 1e-4 * size) << "the test must be able to see a wrong frame";
  for (std::size_t k = 0; k < nk; ++k) {
    test::Floats xk = x0, nk_ = n0;
    if (k > 0) {
      xk += test::read_floats(m, p.targets[k - 1].at("POSITION"));
      nk_ += test::read_floats(m, p.targets[k - 1].at("NORMAL"));
    }
    const double err = (xk.cast<double>() - a.frames[k]).cwiseAbs().maxCoeff();
    EXPECT_LE(err, tol) << "frame " << a.frame_numbers[k];
    const Positions expected_n = vertex_normals(a.frames[k], a.faces);
    for (Eigen::Index i = 0; i < nk_.rows(); ++i) {
      ASSERT_NEAR(nk_.row(i).cast<double>().norm(), 1.0, 1e-5)
          << "frame " << a.frame_numbers[k] << " vertex " << i;
      ASSERT_GT(nk_.row(i).cast<double>().dot(expected_n.row(i)), 1.0 - 1e-5)
          << "frame " << a.frame_numbers[k];
    }
    if (k > 0) {  // outward: the normals point away from the centroid on this star-shaped mesh
      const Eigen::RowVector3d c = a.frames[k].colwise().mean();
      EXPECT_GT((a.frames[k].row(0) - c).dot(nk_.row(0).cast<double>()), 0.0);
    }
  }

  // The animation: one STEP sampler on the node's weights, one keyframe per frame.
  ASSERT_EQ(m.animations.size(), 1u);
  const tinygltf::Animation& anim = m.animations[0];
  ASSERT_EQ(anim.channels.size(), 1u);
  EXPECT_EQ(anim.channels[0].target_path, "weights");
  EXPECT_EQ(anim.channels[0].target_node, 0);
  const tinygltf::AnimationSampler& s =
      anim.samplers.at(static_cast<std::size_t>(anim.channels[0].sampler));
  EXPECT_EQ(s.interpolation, "STEP");
  const test::Floats times = test::read_floats(m, s.input);
  const test::Floats weights = test::read_floats(m, s.output);
  ASSERT_EQ(static_cast<std::size_t>(times.rows()), nk);
  ASSERT_EQ(static_cast<std::size_t>(weights.rows()), nk * (nk - 1));
  for (std::size_t k = 0; k < nk; ++k) {
    EXPECT_FLOAT_EQ(times(static_cast<Eigen::Index>(k)),
                    static_cast<float>(a.frame_numbers[k] * 0.05));
    for (std::size_t t = 0; t + 1 < nk; ++t)
      EXPECT_EQ(weights(static_cast<Eigen::Index>(k * (nk - 1) + t)),
                (k > 0 && t == k - 1) ? 1.0f : 0.0f)
          << "keyframe " << k << " target " << t;
  }

  // Extras: frame numbers and the colour fields' names.
  const tinygltf::Value& extras = m.meshes[0].extras;
  ASSERT_TRUE(extras.Has("frame_numbers"));
  ASSERT_EQ(extras.Get("frame_numbers").ArrayLen(), nk);
  EXPECT_EQ(extras.Get("frame_numbers").Get(static_cast<int>(nk - 1)).GetNumberAsInt(),
            a.frame_numbers.back());
  ASSERT_EQ(extras.Get("colour_fields").ArrayLen(), 2u);
  EXPECT_EQ(extras.Get("colour_fields").Get(1).Get("name").Get<std::string>(), "wave");
  // Each field's values under its own custom attribute, and the range a viewer maps to colours.
  const tinygltf::Value& wave = extras.Get("colour_fields").Get(1);
  EXPECT_FALSE(wave.Has("attribute"));
  ASSERT_EQ(wave.Get("values_attribute").Get<std::string>(), "_WAVE");
  const test::Floats w = test::read_floats(m, p.attributes.at("_WAVE"));
  ASSERT_EQ(w.rows(), a.colour_fields[1].values.size());
  EXPECT_LE((w.cast<double>() - a.colour_fields[1].values).cwiseAbs().maxCoeff(), 1e-6);
  const double low = wave.Get("low").GetNumberAsDouble(),
               high = wave.Get("high").GetNumberAsDouble();
  EXPECT_LT(low, high);
  EXPECT_GE(low, a.colour_fields[1].values.minCoeff());
  EXPECT_LE(high, a.colour_fields[1].values.maxCoeff());
}

// glTF multiplies COLOR_0 with the base colour, so field colours there tinted every textured
// asset in Blender and three.js (the writer had put field i on COLOR_i).
TEST(GltfAnimation, ColourFieldsAreNoColorAttributes) {
  test::ScratchDir dir("nocolor");
  const GltfAnimation a = sphere_animation(10, 5);
  write_gltf_animation(dir.file("sphere.glb"), a);
  const tinygltf::Model m = test::load_glb(dir.file("sphere.glb"));
  for (const tinygltf::Primitive& p : m.meshes.at(0).primitives) {
    for (const auto& [name, accessor] : p.attributes)
      EXPECT_NE(name.rfind("COLOR_", 0), 0u) << name;
    EXPECT_TRUE(p.attributes.count("_HEIGHT"));
    EXPECT_TRUE(p.attributes.count("_WAVE"));
  }
}

TEST(GltfAnimation, OneFrameHasNoTargetsAndNoAnimation) {
  test::ScratchDir dir("one");
  GltfAnimation a = sphere_animation(0, 1);
  a.colour_fields.clear();
  write_gltf_animation(dir.file("one.glb"), a);
  const tinygltf::Model m = test::load_glb(dir.file("one.glb"));
  EXPECT_TRUE(m.meshes.at(0).primitives.at(0).targets.empty());
  EXPECT_TRUE(m.animations.empty());
  // No target names and no colour fields: left out, not written as null (tinygltf's writer
  // makes an empty list null).
  std::ifstream in(dir.file("one.glb"), std::ios::binary);
  const std::string glb(std::istreambuf_iterator<char>(in), {});
  ASSERT_GT(glb.size(), 20u);
  std::uint32_t n = 0;
  std::memcpy(&n, glb.data() + 12, 4);  // little-endian hosts
  const std::string json = glb.substr(20, n);
  EXPECT_EQ(json.find("null"), std::string::npos) << json;
}

TEST(GltfAnimation, ConsumingTheFramesWritesTheSameFile) {
  // The CLI hands its frames over (a large mesh's frames and buffer are hundreds of MB each):
  // the same bytes as from a copy, and the frames after the first freed.
  test::ScratchDir dir("consume");
  const GltfAnimation a = sphere_animation(40, 5);
  write_gltf_animation(dir.file("copy.glb"), a);
  GltfAnimation handed = a;
  const GltfStats stats = write_gltf_animation(dir.file("moved.glb"), std::move(handed));
  EXPECT_EQ(stats.bytes, std::filesystem::file_size(dir.file("copy.glb")));
  EXPECT_EQ(test::read_bytes(dir.file("moved.glb")), test::read_bytes(dir.file("copy.glb")));
  for (std::size_t k = 1; k < handed.frames.size(); ++k) EXPECT_EQ(handed.frames[k].size(), 0);
}

TEST(GltfAnimation, RejectsInconsistentInputAndUnwritablePaths) {
  test::ScratchDir dir("bad");
  const GltfAnimation good = sphere_animation(10, 5);
  GltfAnimation a = good;
  a.frame_numbers.pop_back();
  EXPECT_THROW(write_gltf_animation(dir.file("a.glb"), a), std::invalid_argument);
  a = good;
  a.frames[1].conservativeResize(10, Eigen::NoChange);  // (x = x.topRows(n) reads freed memory)
  EXPECT_THROW(write_gltf_animation(dir.file("a.glb"), a), std::invalid_argument);
  a = good;
  a.frames[2](3, 1) = std::nan("");
  EXPECT_THROW(write_gltf_animation(dir.file("a.glb"), a), std::invalid_argument);
  a = good;
  std::swap(a.frame_numbers[0], a.frame_numbers[1]);
  EXPECT_THROW(write_gltf_animation(dir.file("a.glb"), a), std::invalid_argument);
  a = good;
  a.colour_fields[0].values.resize(3);
  EXPECT_THROW(write_gltf_animation(dir.file("a.glb"), a), std::invalid_argument);
  EXPECT_THROW(write_gltf_animation("/nonexistent_shellcontract_dir/a.glb", good), UsageError);
  EXPECT_FALSE(std::filesystem::exists(dir.file("a.glb")));
}

// Issue 26's size bound: bear (27,648 faces, 13,826 vertices) with 50 frames after the first,
// and two colour fields, under 30 MB. The size depends only on the counts (no compression).
TEST(GltfAnimation, BearWithFiftyFramesIsUnder30MB) {
  const std::string bear = std::string(test::PAPER_MESH_DIR) + "/bear.off";
  if (!std::filesystem::exists(bear))
    GTEST_SKIP() << bear << " missing (scripts/fetch_paper_meshes.sh)";
  const Mesh mesh = read_input_mesh(bear);
  const Positions x = positions_from_mesh(mesh);
  GltfAnimation a;
  a.faces = test::faces_of(mesh);
  for (int f = 0; f <= 50; ++f) {
    a.frame_numbers.push_back(f);
    a.frames.push_back(test::fake_frame(x, f, 50));
  }
  a.colour_fields.push_back({"height", x.col(2)});
  a.colour_fields.push_back({"x", x.col(0)});
  test::ScratchDir dir("bear");
  const GltfStats stats = write_gltf_animation(dir.file("bear.glb"), a);
  std::cout << "bear, 51 frames (0..50), 2 colour fields: " << stats.bytes << " bytes ("
            << static_cast<double>(stats.bytes) / 1e6 << " MB)\n";
  EXPECT_EQ(a.faces.rows(), 27648);
  EXPECT_EQ(x.rows(), 13826);
  EXPECT_LT(stats.bytes, 30u * 1000u * 1000u);
}

TEST(VertexNormals, UnitOutwardOnASphere) {
  const test::TriMesh s = test::icosphere(2, 3.0);
  const Positions n = vertex_normals(s.x, s.faces);
  for (Eigen::Index i = 0; i < n.rows(); ++i) {
    EXPECT_NEAR(n.row(i).norm(), 1.0, 1e-12);
    EXPECT_GT(n.row(i).dot(s.x.row(i).normalized()), 0.99) << "vertex " << i;
  }
}

TEST(VertexNormals, AFaceIndexOutOfRangeIsRefused) {
  // Before: index 3 of 3 vertices read past the array silently; 100000 and -100000 crashed.
  const Positions x = (Positions(3, 3) << 0, 0, 0, 1, 0, 0, 0, 1, 0).finished();
  for (const int bad : {3, 100000, -1, -100000}) {
    Faces f(1, 3);
    f << 0, 1, bad;
    EXPECT_THROW(vertex_normals(x, f), std::invalid_argument) << bad;
  }
  Faces ok(1, 3);
  ok << 0, 1, 2;
  EXPECT_NEAR(vertex_normals(x, ok)(2, 2), 1.0, 1e-15);
}

}  // namespace
}  // namespace shellcontract
