// `shellcontract run` on a mesh split along its UV seams (Blender's PLY export of a textured
// sphere, tests/support/seam_split.hpp): it runs welded, says so in a note, and every output
// gives the file's vertices back, each copy at its welded vertex's position: -o (through the
// PLY document: header, s, t and faces as read), the plain writer, the frames of --export-dir
// (the same writer as -o), the .glb's texture coordinates, --fields, a checkpoint's resume, and
// `check --against` of the result; and `regions -o`, on the file's vertices too.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "sim/checkpoint.hpp"
#include "support/cli_runner.hpp"
#include "support/seam_split.hpp"

namespace {

using shellcontract::test::RunResult;
using shellcontract::test::run_cli;
using shellcontract::test::SeamSplitMesh;
namespace fs = std::filesystem;

class CliSeams : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
    dir_ = fs::temp_directory_path() / ("shellcontract_cli_seams_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    in_ = file("ball.ply");
    std::ofstream(in_) << mesh_.ply();
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  std::vector<std::string> run_args(const std::string& out, std::vector<std::string> extra = {}) const {
    std::vector<std::string> a = {"run", in_, "-o", out, "--frames", "8", "--target-volume", "0.8", "-q"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  }
  fs::path dir_;
  SeamSplitMesh mesh_ = shellcontract::test::seam_split_sphere();
  std::string in_;
};

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

std::vector<std::string> tokens(const std::string& text) {
  std::vector<std::string> t;
  std::istringstream s(text);
  for (std::string w; s >> w;) t.push_back(w);
  return t;
}

/// Checks an ascii PLY written from the split sphere's file: the header as it was, s, t and the
/// faces token for token, every copy at the position of the vertices it was welded with, and
/// the positions moved (or, `moved` false, where they were). Returns its positions.
Eigen::MatrixXd expect_split_ply(const std::string& written, const std::string& input, const SeamSplitMesh& m,
                                 bool moved = true) {
  const std::size_t h = input.find("end_header\n") + 11;
  EXPECT_EQ(written.substr(0, h), input.substr(0, h));
  const std::vector<std::string> a = tokens(input.substr(h)), b = tokens(written.substr(h));
  EXPECT_EQ(a.size(), b.size());
  const auto n = static_cast<Eigen::Index>(m.x.rows());
  Eigen::MatrixXd x(n, 3);
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    if (i < 5 * static_cast<std::size_t>(n) && i % 5 < 3)
      x(static_cast<Eigen::Index>(i / 5), static_cast<Eigen::Index>(i % 5)) = std::strtod(b[i].c_str(), nullptr);
    else
      EXPECT_EQ(b[i], a[i]) << "token " << i;  // s, t and the faces
  }
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < i; ++j)
      if (m.closed_vertex[static_cast<std::size_t>(i)] == m.closed_vertex[static_cast<std::size_t>(j)]) {
        EXPECT_EQ(x.row(i), x.row(j)) << "copies " << j << " and " << i;
      }
  if (moved)
    EXPECT_GT((x - m.x).cwiseAbs().maxCoeff(), 1e-3);
  else  // the rest state, scaled to the unit diagonal and back: a few ulps
    EXPECT_LT((x - m.x).cwiseAbs().maxCoeff(), 1e-12);
  return x;
}

TEST_F(CliSeams, ASeamSplitPlyRunsWeldedAndItsResultKeepsEveryCopyAndAttribute) {
  const RunResult r = run_cli(run_args(file("out.ply"), {"--summary", file("s.json")}));
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 5) << r.output;
  const std::size_t copies = static_cast<std::size_t>(mesh_.x.rows()) - mesh_.closed_vertices;
  EXPECT_NE(r.output.find("note: " + std::to_string(copies) + " seam vertices were welded"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  EXPECT_NE(read_text(file("s.json")).find("\"welded_vertices\": " + std::to_string(copies)), std::string::npos);
  const Eigen::MatrixXd x = expect_split_ply(read_text(file("out.ply")), read_text(in_), mesh_);
  // The result is checked against its input by the file's vertices and polygons.
  const RunResult against = run_cli({"check", file("out.ply"), "--against", in_});
  EXPECT_EQ(against.exit_code, 0) << against.output;
  // The plain writer (another format) gives the same vertices, in the file's order.
  const RunResult off = run_cli(run_args(file("out.off")));
  ASSERT_EQ(off.exit_code, r.exit_code) << off.output;
  std::istringstream o(read_text(file("out.off")));
  std::string magic;
  std::size_t nv = 0, nf = 0, ne = 0;
  o >> magic >> nv >> nf >> ne;
  ASSERT_EQ(nv, static_cast<std::size_t>(mesh_.x.rows()));
  ASSERT_EQ(nf, mesh_.tris.size());
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (Eigen::Index k = 0; k < 3; ++k) {
      std::string c;
      o >> c;
      EXPECT_EQ(std::strtod(c.c_str(), nullptr), x(i, k)) << i;
    }
}

TEST_F(CliSeams, FramesGltfAndFieldsOfASeamSplitRunKeepTheFilesVertices) {
  const RunResult r = run_cli(run_args(file("out.ply"), {"--export-every", "4", "--export-dir", file("frames"),
                                                         "--gltf", file("out.glb"), "--fields", file("f")}));
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 5) << r.output;
  const std::string input = read_text(in_), result = read_text(file("out.ply"));
  expect_split_ply(result, input, mesh_);
  // The frames go through -o's writer: the last is the result, byte for byte.
  EXPECT_EQ(read_text(file("frames/out_8.ply")), result);
  expect_split_ply(read_text(file("frames/out_4.ply")), input, mesh_);
  expect_split_ply(read_text(file("frames/out_0.ply")), input, mesh_, /*moved=*/false);
  const std::string glb = read_text(file("out.glb"));
  EXPECT_NE(glb.find("\"TEXCOORD_0\""), std::string::npos);
  const std::string fields = read_text(file("f_end.ply"));
  EXPECT_NE(fields.find("element vertex " + std::to_string(mesh_.x.rows()) + "\n"), std::string::npos) << fields.substr(0, 400);
}

// An STL keeps no vertex identity: the copies of a seam vertex, at one position, read back as
// that vertex, the welded mesh. The refusal of two vertices at one position in an STL
// (stl_positions.hpp) lets copies of one vertex through: the STL is written and reads back usable.
TEST_F(CliSeams, AnStlOfASeamSplitRunIsWrittenAndReadsBackWelded) {
  const RunResult r =
      run_cli(run_args(file("out.stl"), {"--export-every", "4", "--export-dir", file("frames")}));
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 5) << r.output;
  EXPECT_EQ(run_cli({"check", file("out.stl")}).exit_code, 0);
  EXPECT_EQ(run_cli({"check", file("frames/out_4.stl")}).exit_code, 0);
}

TEST_F(CliSeams, ASeamSplitRunResumedFromItsCheckpointEqualsTheWholeRun) {
  const RunResult whole = run_cli(run_args(file("whole.ply")));
  ASSERT_TRUE(whole.exit_code == 0 || whole.exit_code == 5) << whole.output;
  // Saved at frames 3 and 6 of 8: the checkpoint holds frame 6.
  const RunResult saved = run_cli(run_args(file("saved.ply"), {"--checkpoint", file("c.ckpt"), "--checkpoint-every", "3"}));
  ASSERT_EQ(saved.exit_code, whole.exit_code) << saved.output;
  ASSERT_EQ(shellcontract::read_checkpoint(file("c.ckpt")).sim.frame, 6);
  const RunResult resumed = run_cli({"run", "--resume", file("c.ckpt"), "-o", file("resumed.ply"), "-q"});
  ASSERT_EQ(resumed.exit_code, whole.exit_code) << resumed.output;
  EXPECT_EQ(read_text(file("resumed.ply")), read_text(file("whole.ply")));
}

TEST_F(CliSeams, TheRegionsPlyOfASeamSplitMeshHasTheFilesVerticesAndFaces) {
  // A cap at the pole, where each pole triangle has its own copy of the pole vertex.
  const RunResult r = run_cli({"regions", in_, "--region-at", "0,0,1", "-o", file("r.ply"), "--face-list", file("f.txt")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::istringstream in(read_text(file("r.ply")));
  std::size_t nv = 0, nf = 0;
  for (std::string line; std::getline(in, line) && line != "end_header";) {
    std::istringstream l(line);
    std::string word, element;
    l >> word >> element;
    if (word == "element") (element == "vertex" ? l >> nv : l >> nf);
  }
  ASSERT_EQ(nv, static_cast<std::size_t>(mesh_.x.rows()));
  ASSERT_EQ(nf, mesh_.tris.size());
  // x y z H K per vertex: the file's positions (regions does not move them), and each copy
  // with the curvature of the vertices it was welded with.
  std::vector<std::array<double, 2>> hk(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    for (Eigen::Index k = 0; k < 3; ++k) {
      std::string c;
      in >> c;
      EXPECT_EQ(std::strtod(c.c_str(), nullptr), mesh_.x(static_cast<Eigen::Index>(i), k)) << "vertex " << i;
    }
    in >> hk[i][0] >> hk[i][1];
    for (std::size_t j = 0; j < i; ++j)
      if (mesh_.closed_vertex[i] == mesh_.closed_vertex[j]) {
        EXPECT_EQ(hk[i], hk[j]) << "copies " << j << " and " << i;
      }
  }
  // Each face on the file's corners (from any of them, in the file's direction), with the
  // region that the face list gives its index.
  std::vector<int> listed(nf, -1);
  std::istringstream list(read_text(file("f.txt")));
  int region = 0;
  for (std::string line; std::getline(list, line); ++region) {
    std::istringstream ids(line);
    for (std::size_t f; ids >> f;) listed.at(f) = region;
  }
  ASSERT_GE(region, 1) << "a region at the pole";
  std::size_t in_region = 0;
  for (std::size_t f = 0; f < nf; ++f) {
    std::size_t degree = 0, rgba = 0;
    std::array<std::size_t, 3> c{};
    int id = -2;
    in >> degree >> c[0] >> c[1] >> c[2];
    for (int k = 0; k < 4; ++k) in >> rgba;
    in >> id;
    ASSERT_EQ(degree, 3u) << "face " << f;
    std::array<std::size_t, 3> want = mesh_.tris[f];
    std::rotate(want.begin(), std::find(want.begin(), want.end(), c[0]), want.end());
    EXPECT_EQ(c, want) << "face " << f;
    EXPECT_EQ(id, listed[f]) << "face " << f;
    in_region += id >= 0;
  }
  EXPECT_GT(in_region, 0u);
}

}  // namespace
