// A result stored as 32-bit floats far from the origin (docs/design/attributes.md, "Float32
// positions"). Before, a float PLY's result kept its float x, y, z and a glTF's its float
// POSITION whatever the coordinates: where the float32 spacing is beyond the contact gap the run
// keeps (2 delta of the diagonal), the rounding put the sheets of a pressed shell through each
// other in the file, with exit 0, and `validate` end said 0 (it checked the computed positions).
// The mesh is meshes/two_sheet.off (two discs 0.02 apart, pressed together by -p 50) moved
// 10000 along each axis, where the float32 spacing is 0.001 and the gap about 2.4e-4.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/off_scan.hpp"
#include "mesh/ply_reader.hpp"
#include "support/cli_runner.hpp"
#include "support/gltf_files.hpp"
#include "test_paths.hpp"

namespace {

using shellcontract::test::run_cli;
using shellcontract::test::RunResult;
namespace fs = std::filesystem;

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// meshes/two_sheet.off moved by `offset` along each axis.
shellcontract::OffScan two_sheet(double offset) {
  shellcontract::OffScan m = shellcontract::scan_off(
      "two_sheet.off", read_text(std::string(shellcontract::test::MESH_DIR) + "/two_sheet.off"));
  for (auto& p : m.points)
    for (double& c : p) c += offset;
  return m;
}

/// The mesh as a binary PLY of float x, y, z.
std::string float_ply(const shellcontract::OffScan& m) {
  std::string out =
      "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(m.points.size()) +
      "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
      std::to_string(m.faces.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : m.points)
    for (double c : p) {
      const auto f = static_cast<float>(c);
      out.append(reinterpret_cast<const char*>(&f), 4);
    }
  for (const auto& face : m.faces) {
    out += static_cast<char>(face.size());
    for (std::size_t v : face) {
      const auto i = static_cast<std::int32_t>(v);
      out.append(reinterpret_cast<const char*>(&i), 4);
    }
  }
  return out;
}

/// The mesh as a .gltf of one primitive, its node with `node_transform`.
std::string gltf(const shellcontract::OffScan& m, const std::string& node_transform) {
  shellcontract::test::GltfPrimitive p;
  for (const auto& q : m.points)
    p.positions.push_back(
        {static_cast<float>(q[0]), static_cast<float>(q[1]), static_cast<float>(q[2])});
  for (const auto& face : m.faces)
    for (std::size_t v : face) p.indices.push_back(static_cast<std::uint32_t>(v));
  shellcontract::test::GltfScene scene;
  scene.primitives.push_back(p);
  scene.node_transform = node_transform;
  return shellcontract::test::gltf_text(shellcontract::test::gltf_parts(scene));
}

/// The count that `check --against` prints as new_self_intersecting_pairs; -1 if none.
long check_against_count(const std::string& output) {
  std::smatch m;
  static const std::regex re("new_self_intersecting_pairs: ([0-9]+)");
  return std::regex_search(output, m, re) ? std::stol(m[1]) : -1;
}

class CliFloat32Gap : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH))
      GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_float32_gap_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& bytes) const {
    std::ofstream(file(name), std::ios::binary) << bytes;
    return file(name);
  }
  /// run IN -o OUT with the pressure that presses the two sheets together.
  RunResult press(const std::string& in, const std::string& out,
                  std::vector<std::string> more = {}) const {
    std::vector<std::string> args = {"run",           in, "-o", out, "-n", "60", "-p", "50",
                                     "--air-balance", "0"};
    args.insert(args.end(), more.begin(), more.end());
    return run_cli(args);
  }
  fs::path dir_;
};

TEST_F(CliFloat32Gap, AFarOffFloatPlyResultIsWrittenAsDoubleAndPassesCheckAgainstItsInput) {
  const std::string in = write("far.ply", float_ply(two_sheet(10000.0)));
  const RunResult run = press(in, file("out.ply"), {"--summary", file("s.json")});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("x, y, z are written as double, not as the input's 32-bit floats"),
            std::string::npos)
      << run.output;
  // The summary's `warnings` are every warning, those of writing the outputs too.
  EXPECT_NE(read_text(file("s.json")).find("x, y, z are written as double"), std::string::npos)
      << read_text(file("s.json"));
  const std::string out = read_text(file("out.ply"));
  EXPECT_NE(out.find("property double x\nproperty double y\nproperty double z\nelement face"),
            std::string::npos)
      << out.substr(0, 200);
  const RunResult check = run_cli({"check", "--against", in, file("out.ply")});
  EXPECT_EQ(check.exit_code, 0) << check.output;
  EXPECT_EQ(check_against_count(check.output), 0) << check.output;
  // The computed positions themselves: those of the same run written as an OFF (17 digits).
  const RunResult off = press(in, file("out.off"), {"-q"});
  ASSERT_EQ(off.exit_code, 0) << off.output;
  const shellcontract::PlyData p = shellcontract::read_ply("out.ply", out);
  const shellcontract::OffScan o = shellcontract::scan_off("out.off", read_text(file("out.off")));
  ASSERT_EQ(p.points.size(), o.points.size());
  for (std::size_t i = 0; i < p.points.size(); ++i)
    for (std::size_t k = 0; k < 3; ++k)
      ASSERT_EQ(p.points[i][k], o.points[i][k]) << "vertex " << i << " axis " << k;
}

TEST_F(CliFloat32Gap, AFloatPlyNearTheOriginKeepsItsFloats) {
  const std::string in = write("near.ply", float_ply(two_sheet(0.0)));
  const RunResult run = press(in, file("out.ply"), {"--validate", "end"});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.output.find("written as double"), std::string::npos) << run.output;
  const std::string out = read_text(file("out.ply"));
  EXPECT_NE(out.find("property float x\nproperty float y\nproperty float z\n"), std::string::npos)
      << out.substr(0, 200);
}

TEST_F(CliFloat32Gap, AFarOffGltfIsWarnedOfAndValidatedAsTheFileStoresIt) {
  const std::string in = write("far.gltf", gltf(two_sheet(10000.0), ""));
  const RunResult run =
      press(in, file("out.gltf"), {"--validate", "end", "--summary", file("s.json")});
  EXPECT_NE(run.output.find("result stores its positions as 32-bit floats"), std::string::npos)
      << run.output;
  const RunResult check = run_cli({"check", "--against", in, file("out.gltf")});
  const long written = check_against_count(check.output);
  ASSERT_GT(written, 0) << check.output;
  // The file passes through itself, so the run must say so: exit 4, and the summary's count is
  // the file's.
  EXPECT_EQ(run.exit_code, 4) << run.output;
  EXPECT_NE(read_text(file("s.json")).find("\"new_intersections\": " + std::to_string(written)),
            std::string::npos)
      << read_text(file("s.json"));
  // The warning given before the run is in the summary's `warnings` too.
  EXPECT_NE(read_text(file("s.json")).find("result stores its positions as 32-bit floats"),
            std::string::npos)
      << read_text(file("s.json"));
}

TEST_F(CliFloat32Gap, AGltfWhoseOffsetIsItsNodesTranslationIsNeitherWarnedOfNorFailed) {
  const std::string in =
      write("node.gltf", gltf(two_sheet(0.0), "\"translation\":[10000,10000,10000]"));
  const RunResult run = press(in, file("out.gltf"), {"--validate", "end"});
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.output.find("32-bit floats"), std::string::npos) << run.output;
  const RunResult check = run_cli({"check", "--against", in, file("out.gltf")});
  EXPECT_EQ(check_against_count(check.output), 0) << check.output;
}

}  // namespace
