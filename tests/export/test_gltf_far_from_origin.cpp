// The .glb of a mesh far from the origin keeps its shape (review14 D1): positions are stored as
// float32 relative to the rest bounding box's centre, which is the node's translation (JSON
// doubles), so positions + translation give every frame to float precision relative to the mesh's
// size. Stored absolute, a 2-unit sphere at northing 5e6 (float spacing 0.5) became a cloud of a
// few hundred points. And values float32 cannot hold are refused before a byte is written, with a
// message for the user (review14 D3): before, positions beyond its range were written as inf with
// exit 0, and a curvature field's inf was refused as "a non-finite value".
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "export_fixtures.hpp"
#include "gltf_reader.hpp"
#include "shellcontract/export.hpp"
#include "support/cgal_volume.hpp"
#include "support/cli_runner.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

const Eigen::RowVector3d FAR_AWAY(500000.0, 5000000.0, 100.0);  // UTM-like metres

/// Node 0's translation (zero without one).
Eigen::RowVector3d node_translation(const tinygltf::Model& m) {
  const tinygltf::Node& n = m.nodes.at(0);
  if (n.translation.empty()) return Eigen::RowVector3d::Zero();
  EXPECT_EQ(n.translation.size(), 3u);
  EXPECT_TRUE(n.matrix.empty() && n.rotation.empty() && n.scale.empty());
  return Eigen::RowVector3d(n.translation[0], n.translation[1], n.translation[2]);
}

/// Frame k (0: the base) as a reader places it: POSITION + target k - 1, summed in float as a
/// renderer does, then moved by the node's translation in double.
Positions placed_frame(const tinygltf::Model& m, std::size_t k) {
  const tinygltf::Primitive& p = m.meshes.at(0).primitives.at(0);
  test::Floats x = test::read_floats(m, p.attributes.at("POSITION"));
  if (k > 0) x += test::read_floats(m, p.targets.at(k - 1).at("POSITION"));
  Positions out = x.cast<double>();
  out.rowwise() += node_translation(m);
  return out;
}

double diagonal(const Positions& x) {
  return (x.colwise().maxCoeff() - x.colwise().minCoeff()).norm();
}

/// An OFF file of the triangles, with every digit.
void write_off(const std::string& path, const Positions& x, const Faces& faces) {
  std::ofstream off(path);
  off << "OFF\n" << x.rows() << ' ' << faces.rows() << " 0\n";
  char line[128];
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", x(i, 0), x(i, 1), x(i, 2));
    off << line;
  }
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    off << "3 " << faces(f, 0) << ' ' << faces(f, 1) << ' ' << faces(f, 2) << '\n';
}

GltfAnimation far_sphere(int frames) {
  const test::TriMesh s = test::icosphere(3, 1.0);
  Positions x = s.x;
  x.rowwise() += FAR_AWAY;
  GltfAnimation a;
  a.faces = s.faces;
  for (int f = 0; f <= frames; ++f) {
    a.frame_numbers.push_back(f);
    a.frames.push_back(test::fake_frame(x, f, frames));
  }
  return a;
}

TEST(GltfFarFromOrigin, EveryFrameKeepsFloatPrecisionRelativeToTheMeshSize) {
  test::ScratchDir dir("gltf_far");
  const GltfAnimation a = far_sphere(6);
  const std::string path = dir.file("far.glb");
  write_gltf_animation(path, a);
  const tinygltf::Model m = test::load_glb(path);
  // The translation is the rest bounding box's centre, as written in double.
  const Vec3 centre = gltf_centre(a.frames[0]);
  EXPECT_EQ(node_translation(m), centre.transpose());
  const double size = diagonal(a.frames[0]);
  // A few float roundings of coordinates the size of the mesh: far below the float spacing at
  // northing 5e6 (0.5), which an absolute float32 position has.
  const double tol = 8.0 * size * std::numeric_limits<float>::epsilon();
  for (std::size_t k = 0; k < a.frames.size(); ++k)
    EXPECT_LE((placed_frame(m, k) - a.frames[k]).cwiseAbs().maxCoeff(), tol) << "frame " << k;
  // POSITION's bounds are those of the stored (relative) values, as glTF requires.
  const tinygltf::Accessor& pos =
      m.accessors.at(static_cast<std::size_t>(m.meshes[0].primitives[0].attributes.at("POSITION")));
  ASSERT_EQ(pos.maxValues.size(), 3u);
  EXPECT_LE(pos.maxValues[1], size);
}

TEST(GltfFarFromOrigin, AMeshCentredOnTheOriginHasNoTranslation) {
  test::ScratchDir dir("gltf_far");
  GltfAnimation a = far_sphere(1);
  for (Positions& x : a.frames) x.rowwise() -= gltf_centre(a.frames[0]).transpose();
  write_gltf_animation(dir.file("centred.glb"), a);
  const tinygltf::Model m = test::load_glb(dir.file("centred.glb"));
  EXPECT_TRUE(m.nodes.at(0).translation.empty());
}

TEST(GltfFarFromOrigin, TheGlbOfARunFarFromTheOriginMatchesItsResult) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("gltf_far_run");
  const test::TriMesh s = test::icosphere(2, 1.0);
  Positions x = s.x;
  x.rowwise() += FAR_AWAY;
  write_off(dir.file("far.off"), x, s.faces);
  const auto r = test::run_cli({"run", dir.file("far.off"), "-o", dir.file("out.off"), "-n", "8",
                                "-q", "--target-volume", "0.7", "--gltf", dir.file("run.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const tinygltf::Model m = test::load_glb(dir.file("run.glb"));
  const Positions rest = test::cgal_read_positions(dir.file("far.off"));
  const Positions result = test::cgal_read_positions(dir.file("out.off"));
  const double tol = 8.0 * diagonal(rest) * std::numeric_limits<float>::epsilon();
  EXPECT_LE((placed_frame(m, 0) - rest).cwiseAbs().maxCoeff(), tol);
  const std::size_t last = m.meshes[0].primitives[0].targets.size();
  ASSERT_GT(last, 0u);
  EXPECT_LE((placed_frame(m, last) - result).cwiseAbs().maxCoeff(), tol);
  // The run moved the mesh far more than the tolerance: a wrong frame would be seen.
  EXPECT_GT((result - rest).cwiseAbs().maxCoeff(), 100.0 * tol);
}

/// Whether writing `a` throws std::invalid_argument whose message holds every one of `words`,
/// and leaves no file.
void expect_refused(const GltfAnimation& a, const std::vector<std::string>& words) {
  test::ScratchDir dir("gltf_range");
  const std::string path = dir.file("refused.glb");
  try {
    write_gltf_animation(path, a);
    ADD_FAILURE() << "written";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    for (const std::string& w : words) EXPECT_NE(what.find(w), std::string::npos) << what;
    EXPECT_EQ(what.find("non-finite"), std::string::npos) << what;
  }
  EXPECT_FALSE(fs::exists(path));
}

TEST(GltfFloatRange, PositionsBeyondFloat32AreRefused) {
  GltfAnimation a = far_sphere(2);
  for (Positions& x : a.frames) x *= 1e39;  // a sphere of radius 1e39: beyond float's 3.4e38
  expect_refused(a, {"32-bit floats", "vertex ", "beyond the largest 32-bit float"});
}

TEST(GltfFloatRange, PositionsBelowTheSmallestNormalFloatAreRefused) {
  GltfAnimation a = far_sphere(2);
  for (Positions& x : a.frames) x *= 1e-40;  // relative to its centre, subnormal or zero
  expect_refused(a, {"32-bit floats", "smallest normal 32-bit float"});
}

TEST(GltfFloatRange, AFieldBeyondFloat32IsRefusedByName) {
  GltfAnimation a = far_sphere(2);
  const Eigen::Index nv = a.frames[0].rows();
  a.colour_fields.push_back({"gaussian_curvature", Eigen::VectorXd::Constant(nv, 1e40)});
  expect_refused(a, {"gaussian_curvature", "beyond the largest 32-bit float", "input's units"});
  // A per-frame field: floats already, whose inf is a double value float could not hold.
  GltfAnimation b = far_sphere(2);
  std::vector<Eigen::VectorXf> mean(b.frames.size(), Eigen::VectorXf::Ones(nv));
  mean[1](3) = std::numeric_limits<float>::infinity();
  b.frame_fields.push_back({"mean_curvature", mean});
  expect_refused(b, {"mean_curvature", "vertex 3 of frame 1", "beyond the largest 32-bit float"});
}

TEST(GltfFloatRange, ARunOfAVerySmallMeshRefusesItsGlbWithAMessageAndKeepsItsResult) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("gltf_small_run");
  const test::TriMesh s = test::icosphere(2, 1e-20);  // Gaussian curvature 1e40: beyond float
  write_off(dir.file("small.off"), s.x, s.faces);
  const auto r = test::run_cli({"run", dir.file("small.off"), "-o", dir.file("out.off"), "-n", "3",
                                "-q", "--gltf", dir.file("run.glb")});
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("beyond the largest 32-bit float"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("non-finite"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir.file("run.glb")));
  EXPECT_TRUE(fs::exists(dir.file("out.off")));  // the result is written all the same
}

TEST(GltfFloatRange, ARunOfAMeshBeyondFloat32IsRefusedBeforeItStarts) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("gltf_big_run");
  const test::TriMesh s = test::icosphere(2, 1e39);  // positions beyond float's 3.4e38
  write_off(dir.file("big.off"), s.x, s.faces);
  const auto r = test::run_cli({"run", dir.file("big.off"), "-o", dir.file("out.off"), "-n", "3",
                                "-q", "--gltf", dir.file("run.glb")});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--gltf cannot hold this mesh"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir.file("run.glb")));
  EXPECT_FALSE(fs::exists(dir.file("out.off")));  // refused before the run: nothing computed
}

}  // namespace
}  // namespace shellcontract
