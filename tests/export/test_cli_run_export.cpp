// The two exports of a real CLI run agree: `shellcontract run --export-every 5
// --export-dir DIR --gltf FILE.glb` on bumpy_sphere, and every keyframe of the .glb read back with
// tinygltf (base + morph displacement) equals the frame sequence's file of the same frame to float
// precision, in the same order, with the same frame numbers; its last keyframe is the result.
// (tests/export/test_export_consistency.cpp checks the same on made-up motion.)
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "export_fixtures.hpp"
#include "gltf_reader.hpp"
#include "support/cgal_volume.hpp"
#include "support/cli_runner.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

TEST(CliRunExport, TheGlbOfARunEqualsItsFrameSequence) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("cli_run");
  const std::string frames = dir.file("frames");
  fs::create_directories(frames);
  const auto r = test::run_cli({"run", std::string(test::MESH_DIR) + "/bumpy_sphere.off", "-o",
                                dir.file("run.off"), "-n", "23", "-q", "--export-every", "5",
                                "--export-dir", frames, "--gltf", dir.file("run.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;

  const tinygltf::Model m = test::load_glb(dir.file("run.glb"));
  ASSERT_EQ(m.meshes.size(), 1u);
  const tinygltf::Primitive& p = m.meshes[0].primitives.at(0);
  // Every 5th frame, the first and the last: 0, 5, 10, 15, 20, 23.
  const std::vector<int> want_frames = {0, 5, 10, 15, 20, 23};
  ASSERT_EQ(p.targets.size() + 1, want_frames.size());
  const tinygltf::Value& numbers = m.meshes[0].extras.Get("frame_numbers");
  ASSERT_EQ(numbers.ArrayLen(), want_frames.size());

  const test::Floats base = test::read_positions(m, p.attributes.at("POSITION"));
  const Positions first = test::cgal_read_positions(frames + "/run_00.off");
  const double extent = first.cwiseAbs().maxCoeff();
  // One float rounding of the base, of the displacement and of their sum.
  const double tol = 4.0 * extent * std::numeric_limits<float>::epsilon();
  double motion = 0.0;
  for (std::size_t k = 0; k < want_frames.size(); ++k) {
    EXPECT_EQ(numbers.Get(static_cast<int>(k)).GetNumberAsInt(), want_frames[k]);
    char name[32];
    std::snprintf(name, sizeof name, "/run_%02d.off", want_frames[k]);
    const Positions file = test::cgal_read_positions(frames + name);
    test::Floats xk = base;
    if (k > 0) xk += test::read_floats(m, p.targets[k - 1].at("POSITION"));
    ASSERT_EQ(xk.rows(), file.rows());
    EXPECT_LE((xk.cast<double>() - file).cwiseAbs().maxCoeff(), tol) << "frame " << want_frames[k];
    motion = std::max(motion, (file - first).cwiseAbs().maxCoeff());
  }
  // The last keyframe is the result the run wrote.
  test::Floats last = base + test::read_floats(m, p.targets.back().at("POSITION"));
  EXPECT_LE((last.cast<double>() - test::cgal_read_positions(dir.file("run.off"))).cwiseAbs().maxCoeff(), tol);
  // The run moved far more than the tolerance: a frame out of place would be seen.
  EXPECT_GT(motion, 100.0 * tol);
}

}  // namespace
}  // namespace shellcontract
