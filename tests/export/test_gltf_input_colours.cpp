// The --gltf animation and the input's own vertex colours and texture coordinates (review6 F2,
// review7 F8): a vertex-painted PLY, OBJ or glTF plays with its colours (COLOR_0, each glTF
// vertex the colour of its input vertex; a welded seam's copies of other colours split), and a
// texture coordinate or colour that a glTF's float32 cannot hold is refused before the run
// (exit 2, naming the file and the element), not found by the writer after it. Also the
// animation's frame rate (--gltf-fps, review6 F6).
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "export_fixtures.hpp"
#include "gltf_reader.hpp"
#include "shellcontract/export.hpp"
#include "support/cli_runner.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

const double OCTA[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
const int OCTA_FACES[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                              {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
// Each vertex its own colour (uchar), alpha below 255 for two.
const int RGBA[7][4] = {{255, 0, 0, 255},  {0, 255, 0, 255},  {0, 0, 255, 128}, {255, 255, 0, 255},
                        {12, 34, 56, 255}, {200, 100, 50, 7}, {9, 99, 199, 255}};

/// An ASCII PLY of the octahedron with uchar red, green, blue (and alpha) per vertex. With
/// `seam`, vertex 0 has a copy, vertex 6 (at its position, of another colour), used by faces 3
/// and 7: the file is open only along that split, which the reader welds.
std::string coloured_ply(bool alpha, bool seam) {
  std::ostringstream o;
  const int nv = seam ? 7 : 6;
  o << "ply\nformat ascii 1.0\nelement vertex " << nv
    << "\nproperty float x\nproperty float y\nproperty float z\n"
       "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    << (alpha ? "property uchar alpha\n" : "")
    << "element face 8\nproperty list uchar int vertex_indices\nend_header\n";
  for (int v = 0; v < nv; ++v) {
    const double* p = OCTA[v < 6 ? v : 0];
    o << p[0] << ' ' << p[1] << ' ' << p[2];
    for (int c = 0; c < (alpha ? 4 : 3); ++c) o << ' ' << RGBA[v][c];
    o << '\n';
  }
  for (int f = 0; f < 8; ++f) {
    o << '3';
    for (const int v : OCTA_FACES[f]) o << ' ' << (seam && v == 0 && (f == 3 || f == 7) ? 6 : v);
    o << '\n';
  }
  return o.str();
}

/// The file vertex of face f's corner v in coloured_ply.
int file_vertex(bool seam, int f, int v) { return seam && v == 0 && (f == 3 || f == 7) ? 6 : v; }

test::RunResult run_glb(const std::string& input, const test::ScratchDir& dir,
                        std::vector<std::string> extra = {}) {
  std::vector<std::string> args{"run",
                                input,
                                "-o",
                                dir.file("out" + fs::path(input).extension().string()),
                                "-n",
                                "4",
                                "-q",
                                "--gltf",
                                dir.file("run.glb")};
  args.insert(args.end(), extra.begin(), extra.end());
  return test::run_cli(args);
}

/// Per corner of every face of the .glb's one primitive: (position, colour), as text rounded so
/// that equal floats compare equal.
using Corner = std::tuple<float, float, float, float, float, float, float>;

TEST(GltfInputColours, APlysColoursAreTheAnimationsColor0) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  for (const bool alpha : {false, true}) {
    SCOPED_TRACE(alpha ? "rgba" : "rgb");
    test::ScratchDir dir("colours_ply");
    std::ofstream(dir.file("painted.ply")) << coloured_ply(alpha, false);
    const auto r = run_glb(dir.file("painted.ply"), dir);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const tinygltf::Model m = test::load_glb(dir.file("run.glb"));
    const tinygltf::Primitive& p = m.meshes.at(0).primitives.at(0);
    ASSERT_TRUE(p.attributes.count("COLOR_0")) << "the input's colours were dropped";
    const tinygltf::Accessor& acc =
        m.accessors.at(static_cast<std::size_t>(p.attributes.at("COLOR_0")));
    EXPECT_EQ(acc.type, alpha ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3);
    const test::Floats c = test::read_floats(m, p.attributes.at("COLOR_0"));
    // Nothing to split (no texture coordinates, no seam): glTF vertex i is file vertex i.
    ASSERT_EQ(c.rows(), 6);
    for (int v = 0; v < 6; ++v)
      for (int k = 0; k < (alpha ? 4 : 3); ++k)
        EXPECT_FLOAT_EQ(c(v, k), static_cast<float>(RGBA[v][k] / 255.0))
            << "vertex " << v << " component " << k;
    // The fields stay custom attributes beside it, never another COLOR_n.
    EXPECT_FALSE(p.attributes.count("COLOR_1"));
    EXPECT_TRUE(p.attributes.count("_MEAN_CURVATURE"));
  }
}

TEST(GltfInputColours, ASeamsCopiesOfOtherColoursAreSplit) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("colours_seam");
  std::ofstream(dir.file("seam.ply")) << coloured_ply(true, true);
  const auto r = run_glb(dir.file("seam.ply"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const tinygltf::Model m = test::load_glb(dir.file("run.glb"));
  const tinygltf::Primitive& p = m.meshes.at(0).primitives.at(0);
  ASSERT_TRUE(p.attributes.count("COLOR_0"));
  const test::Floats x = test::read_positions(m, p.attributes.at("POSITION"));
  const test::Floats c = test::read_floats(m, p.attributes.at("COLOR_0"));
  EXPECT_EQ(c.rows(), 7) << "the welded vertex 0 is one glTF vertex per colour";
  const std::vector<std::uint32_t> idx = test::read_indices(m, p.indices);
  ASSERT_EQ(idx.size(), 24u);
  // Every face (in file order) has its file corners' positions and colours, in some rotation.
  for (int f = 0; f < 8; ++f) {
    std::vector<Corner> got, want;
    for (int k = 0; k < 3; ++k) {
      const auto g = static_cast<Eigen::Index>(idx[static_cast<std::size_t>(3 * f + k)]);
      got.emplace_back(x(g, 0), x(g, 1), x(g, 2), c(g, 0), c(g, 1), c(g, 2), c(g, 3));
      const int v = file_vertex(true, f, OCTA_FACES[f][k]);
      const double* q = OCTA[v < 6 ? v : 0];
      want.emplace_back(
          static_cast<float>(q[0]), static_cast<float>(q[1]), static_cast<float>(q[2]),
          static_cast<float>(RGBA[v][0] / 255.0), static_cast<float>(RGBA[v][1] / 255.0),
          static_cast<float>(RGBA[v][2] / 255.0), static_cast<float>(RGBA[v][3] / 255.0));
    }
    std::sort(got.begin(), got.end());
    std::sort(want.begin(), want.end());
    EXPECT_EQ(got, want) << "face " << f;
  }
}

TEST(GltfInputColours, AnObjsVertexColoursAreTheAnimationsColor0) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("colours_obj");
  {
    std::ofstream o(dir.file("painted.obj"));
    for (int v = 0; v < 6; ++v)
      o << "v " << OCTA[v][0] << ' ' << OCTA[v][1] << ' ' << OCTA[v][2] << ' ' << RGBA[v][0] / 255.0
        << ' ' << RGBA[v][1] / 255.0 << ' ' << RGBA[v][2] / 255.0 << '\n';
    for (const auto& f : OCTA_FACES)
      o << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
  }
  const auto r = run_glb(dir.file("painted.obj"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const tinygltf::Model m = test::load_glb(dir.file("run.glb"));
  const tinygltf::Primitive& p = m.meshes.at(0).primitives.at(0);
  ASSERT_TRUE(p.attributes.count("COLOR_0"));
  const test::Floats c = test::read_floats(m, p.attributes.at("COLOR_0"));
  ASSERT_EQ(c.rows(), 6);
  ASSERT_EQ(c.cols(), 3);
  for (int v = 0; v < 6; ++v)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c(v, k), RGBA[v][k] / 255.0, 1e-6) << "vertex " << v;
}

/// An ASCII PLY of the octahedron with per-vertex texture coordinates s, t (float or double),
/// vertex 3's s being `s3`.
std::string textured_ply(const std::string& type, const std::string& s3) {
  std::ostringstream o;
  o << "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty "
       "float z\nproperty "
    << type << " s\nproperty " << type
    << " t\nelement face 8\nproperty list uchar int vertex_indices\nend_header\n";
  for (int v = 0; v < 6; ++v)
    o << OCTA[v][0] << ' ' << OCTA[v][1] << ' ' << OCTA[v][2] << ' ' << (v == 3 ? s3 : "0.5")
      << " 0.25\n";
  for (const auto& f : OCTA_FACES) o << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  return o.str();
}

TEST(GltfInputColours, AnUnwritableTextureCoordinateIsRefusedBeforeTheRunNamingTheVertex) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  // NaN; and 1e300, finite as the file's double but inf as the glTF's float32 (before: written
  // as inf with exit 0).
  for (const char* s3 : {"nan", "1e300"}) {
    SCOPED_TRACE(s3);
    test::ScratchDir dir("uv_refused");
    std::ofstream(dir.file("uv.ply")) << textured_ply("double", s3);
    const auto r = run_glb(dir.file("uv.ply"), dir);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(dir.file("uv.ply") +
                            ": not writable as a glTF: vertex 3: texture coordinate u"),
              std::string::npos)
        << r.output;
    // Before the run: nothing written, no progress.
    EXPECT_FALSE(fs::exists(dir.file("run.glb")));
    EXPECT_FALSE(fs::exists(dir.file("out.ply")));
  }
  // Without --gltf the same file runs (-o PLY keeps the values as they are).
  test::ScratchDir dir("uv_plain");
  std::ofstream(dir.file("uv.ply")) << textured_ply("double", "1e300");
  const auto r =
      test::run_cli({"run", dir.file("uv.ply"), "-o", dir.file("out.ply"), "-n", "2", "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(GltfInputColours, AnObjsTextureCoordinateOrColourIsNamedByItsLine) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  const auto obj = [](const std::string& vt2, const std::string& colour4) {
    std::ostringstream o;
    for (int v = 0; v < 6; ++v)
      o << "v " << OCTA[v][0] << ' ' << OCTA[v][1] << ' ' << OCTA[v][2] << ' '
        << (v == 4 ? colour4 : "0.5 0.5 0.5") << '\n';  // lines 1-6
    o << "vt 0 0\nvt " << vt2 << "\n";                  // lines 7, 8
    for (const auto& f : OCTA_FACES)
      o << "f " << f[0] + 1 << "/1 " << f[1] + 1 << "/2 " << f[2] + 1 << "/1\n";
    return o.str();
  };
  {
    test::ScratchDir dir("vt_refused");
    std::ofstream(dir.file("t.obj")) << obj("nan 0", "0.5 0.5 0.5");
    const auto r = run_glb(dir.file("t.obj"), dir);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(
        r.output.find("t.obj: not writable as a glTF: line 8 (vt 2): texture coordinate u nan"),
        std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(dir.file("run.glb")));
  }
  {
    test::ScratchDir dir("colour_refused");
    std::ofstream(dir.file("c.obj")) << obj("1 1", "0.5 -1e39 0.5");
    const auto r = run_glb(dir.file("c.obj"), dir);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(
        r.output.find("c.obj: not writable as a glTF: line 5 (v 5): colour component g -1e+39 is "
                      "beyond the largest 32-bit float"),
        std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(dir.file("run.glb")));
  }
}

TEST(GltfInputColours, TheWriterRefusesATextureCoordinateBeyondFloat32) {
  // A library caller's animation: 1e300 was written as inf (glTF forbids it).
  test::ScratchDir dir("uv_writer");
  GltfAnimation a;
  a.faces.resize(8, 3);
  Positions x(6, 3);
  for (int v = 0; v < 6; ++v) x.row(v) << OCTA[v][0], OCTA[v][1], OCTA[v][2];
  for (int f = 0; f < 8; ++f)
    a.faces.row(f) << OCTA_FACES[f][0], OCTA_FACES[f][1], OCTA_FACES[f][2];
  a.frames = {x};
  a.frame_numbers = {0};
  a.uv.resize(1, 2);
  a.uv << 1e300, 0.5;
  a.face_uv = Faces::Zero(8, 3);
  EXPECT_THROW(write_gltf_animation(dir.file("a.glb"), a), std::invalid_argument);
  a.uv << 0.25, 0.5;
  a.colour.resize(1, 4);
  a.colour << 0.5, 1e300, 0.5, 1.0;
  a.face_colour = Faces::Zero(8, 3);
  EXPECT_THROW(write_gltf_animation(dir.file("a.glb"), a), std::invalid_argument);
  a.colour << 0.5, 0.25, 0.5, 1.0;
  EXPECT_NO_THROW(write_gltf_animation(dir.file("a.glb"), a));
}

TEST(GltfInputColours, GltfFpsSetsTheKeyTimes) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("fps");
  std::ofstream(dir.file("o.ply")) << coloured_ply(false, false);
  for (const auto& [fps, given] :
       std::vector<std::pair<double, bool>>{{24.0, false}, {30.0, true}}) {
    SCOPED_TRACE(fps);
    std::vector<std::string> extra{"--export-every", "2"};
    if (given) extra.insert(extra.end(), {"--gltf-fps", "30"});
    const auto r = run_glb(dir.file("o.ply"), dir, extra);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const tinygltf::Model m = test::load_glb(dir.file("run.glb"));
    const test::Floats t = test::read_floats(m, m.animations.at(0).samplers.at(0).input);
    ASSERT_EQ(t.rows(), 3);  // frames 0, 2, 4
    for (Eigen::Index k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(t(k), static_cast<float>(2.0 * k / fps));
    EXPECT_DOUBLE_EQ(m.meshes[0].extras.Get("seconds_per_frame").GetNumberAsDouble(), 1.0 / fps);
  }
  for (const char* bad : {"0", "-24", "nan", "inf", "2000", "fast", ""}) {
    const auto r = run_glb(dir.file("o.ply"), dir, {"--gltf-fps", bad});
    EXPECT_EQ(r.exit_code, 1) << bad << ": " << r.output;
    EXPECT_NE(r.output.find("--gltf-fps"), std::string::npos) << r.output;
  }
  const auto r = test::run_cli(
      {"run", dir.file("o.ply"), "-o", dir.file("x.ply"), "-n", "1", "-q", "--gltf-fps", "30"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("--gltf-fps has no effect without --gltf"), std::string::npos)
      << r.output;
}

}  // namespace
}  // namespace shellcontract
