// A glTF whose primitives share one POSITION accessor (a mesh split into one primitive per
// material over one vertex buffer, as exporters write it) through `shellcontract run`: each
// element is one vertex (gltf_reader.hpp), so the run is the one of the unsplit mesh, and the
// result writes the run's positions into the shared accessor once. Before, each primitive had
// copies of its own: K = 3 and 7 primitives over an icosphere were refused as open (exit 2).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "export/gltf_reader.hpp"
#include "export_fixtures.hpp"
#include "support/cli_runner.hpp"
#include "support/gltf_shared_positions.hpp"

namespace shellcontract {
namespace {

using test::ScratchDir;

std::string write(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

tinygltf::Model load(const std::string& path, bool binary) {
  if (binary) return test::load_glb(path);
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&test::keep_image_undecoded, nullptr);
  std::string err, warn;
  EXPECT_TRUE(loader.LoadASCIIFromFile(&model, &err, &warn, path)) << path << ": " << err;
  return model;
}

/// The icosphere as `normal_of.size()` primitives on one POSITION accessor
/// (shared_position_parts), written as .glb or .gltf.
std::string split_sphere(const ScratchDir& dir, const std::string& name,
                         const std::vector<int>& normal_of, bool binary, bool materials = false) {
  const test::GltfParts parts =
      test::shared_position_parts(test::icosphere(2), normal_of, materials);
  return write(dir.file(name + (binary ? ".glb" : ".gltf")),
               binary ? test::glb_bytes(parts) : test::gltf_text(parts));
}

TEST(GltfSharedPositions, TheSharedAccessorHoldsTheRunsPositionsAsTheUnsplitMeshsRun) {
  ScratchDir dir("gltf_shared_positions");
  for (const bool binary : {true, false}) {
    const std::string ext = binary ? ".glb" : ".gltf";
    SCOPED_TRACE(ext);
    const std::string one = split_sphere(dir, "one", {-1}, binary);
    const std::string seven = split_sphere(dir, "seven", std::vector<int>(7, -1), binary);
    for (const std::string& in : {one, seven})
      for (const std::string& out : {in + ".out" + ext, in + ".out.obj"}) {
        const auto r = test::run_cli({"run", in, "-o", out, "-n", "8", "-q"});
        ASSERT_EQ(r.exit_code, 0) << r.output;
        EXPECT_EQ(r.output.find("welded"), std::string::npos) << r.output;
      }
    const tinygltf::Model a = load(one + ".out" + ext, binary),
                          b = load(seven + ".out" + ext, binary), in = load(seven, binary);
    // One POSITION accessor still, drawn by the seven primitives, nothing appended.
    ASSERT_EQ(b.meshes.at(0).primitives.size(), 7u);
    for (const tinygltf::Primitive& p : b.meshes[0].primitives)
      EXPECT_EQ(p.attributes.at("POSITION"), 0);
    EXPECT_EQ(b.accessors.size(), in.accessors.size());
    const test::Floats pa = test::read_floats(a, 0), pb = test::read_floats(b, 0),
                       p0 = test::read_floats(in, 0);
    ASSERT_EQ(pb.rows(), 162);
    EXPECT_GT((pb - p0).cwiseAbs().maxCoeff(), 1e-3f);  // the shell moved
    // The same mesh in the same vertex order: the same run, to the bit.
    EXPECT_EQ(pa, pb);
    for (int c = 0; c < 3; ++c) {  // the bounds are the new positions'
      EXPECT_EQ(b.accessors[0].minValues.at(static_cast<std::size_t>(c)), pb.col(c).minCoeff());
      EXPECT_EQ(b.accessors[0].maxValues.at(static_cast<std::size_t>(c)), pb.col(c).maxCoeff());
    }
    // A plain result of the split file is the unsplit one's.
    EXPECT_EQ(slurp(one + ".out.obj"), slurp(seven + ".out.obj"));
  }
}

TEST(GltfSharedPositions, PrimitivesWithTheirOwnNormalsAreEachWritten) {
  // Four primitives share POSITION, 0 and 1 with one NORMAL accessor, 2 and 3 with another (the
  // same values): an element that both pairs draw is two copies, welded as seam copies (before,
  // every primitive had copies of its own and the file was refused as open); the result writes the
  // run's positions once and each NORMAL accessor the area-weighted normals of the new shape at the
  // elements its primitive draws (the copies share one normal: their input normals agree).
  ScratchDir dir("gltf_shared_normals");
  const std::string in = split_sphere(dir, "normals", {0, 0, 1, 1}, true);
  const auto r = test::run_cli({"run", in, "-o", dir.file("out.glb"), "-n", "8", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("seam vertices were welded"), std::string::npos) << r.output;
  const tinygltf::Model b = load(dir.file("out.glb"), true), a = load(in, true);
  ASSERT_EQ(b.meshes.at(0).primitives.size(), 4u);
  const test::Floats x = test::read_floats(b, 0);
  ASSERT_EQ(x.rows(), 162);
  EXPECT_GT((x - test::read_floats(a, 0)).cwiseAbs().maxCoeff(), 1e-3f);
  // The area-weighted normal of each element over all the faces, at the written positions.
  std::vector<Eigen::Vector3d> sum(162, Eigen::Vector3d::Zero());
  std::vector<std::vector<std::uint32_t>> corners;
  for (const tinygltf::Primitive& p : b.meshes[0].primitives) {
    corners.push_back(test::read_indices(b, p.indices));
    const auto& c = corners.back();
    for (std::size_t t = 0; t + 2 < c.size(); t += 3) {
      const Eigen::Vector3d p0 = x.row(c[t]).cast<double>().transpose(),
                            p1 = x.row(c[t + 1]).cast<double>().transpose(),
                            p2 = x.row(c[t + 2]).cast<double>().transpose();
      const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
      for (int k = 0; k < 3; ++k) sum[c[t + static_cast<std::size_t>(k)]] += n;
    }
  }
  for (std::size_t p = 0; p < 4; ++p) {
    const int normal = b.meshes[0].primitives[p].attributes.at("NORMAL");
    EXPECT_EQ(normal, a.meshes[0].primitives[p].attributes.at("NORMAL"));
    const test::Floats n = test::read_floats(b, normal);
    for (const std::uint32_t e : corners[p]) {
      const Eigen::Vector3d want = sum[e].normalized();
      EXPECT_NEAR((n.row(e).cast<double>().transpose() - want).norm(), 0.0, 1e-5)
          << "primitive " << p << " element " << e;
    }
  }
}

TEST(GltfSharedPositions, EachFaceKeepsItsPrimitivesMaterialInTheAnimation) {
  // Three primitives, one material each, on one POSITION accessor: a vertex that two of them
  // draw names the first as its source, but every face is its own primitive's, and the --gltf
  // animation has one primitive per material with that material's faces (107, 107, 106).
  ScratchDir dir("gltf_shared_materials");
  const std::string in = split_sphere(dir, "materials", {-1, -1, -1}, true, true);
  const auto r = test::run_cli(
      {"run", in, "-o", dir.file("out.off"), "--gltf", dir.file("anim.glb"), "-n", "8", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const tinygltf::Model b = load(dir.file("anim.glb"), true);
  std::vector<std::pair<int, std::size_t>> drawn;
  for (const tinygltf::Mesh& m : b.meshes)
    for (const tinygltf::Primitive& p : m.primitives)
      drawn.emplace_back(p.material, b.accessors.at(static_cast<std::size_t>(p.indices)).count / 3);
  const std::vector<std::pair<int, std::size_t>> want = {{0, 107}, {1, 107}, {2, 106}};
  EXPECT_EQ(drawn, want);
}

}  // namespace
}  // namespace shellcontract
