// `shellcontract run` keeps a textured asset whole: the OBJ result has the input's
// lines but for `v` and `vn`, its positions are those of the OFF the same run writes, its normals
// those of its own polygons; a PLY result keeps its extra vertex properties; the exported frames
// are written as the result is.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "support/textured_obj.hpp"

namespace {

using shellcontract::test::RunResult;
using shellcontract::test::run_cli;
namespace fs = std::filesystem;
using Rows = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

class CliAttributes : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
    dir_ = fs::temp_directory_path() / ("shellcontract_attributes_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

std::vector<double> numbers_after_key(const std::string& line) {
  std::istringstream in(line);
  std::string key;
  in >> key;
  std::vector<double> v;
  for (std::string t; in >> t;) v.push_back(std::strtod(t.c_str(), nullptr));
  return v;
}

/// The vertices of an OFF file as the project writes it (header, counts, one vertex a line).
Rows off_vertices(const std::string& path) {
  std::ifstream f(path);
  std::string magic;
  std::size_t nv = 0, nf = 0, ne = 0;
  f >> magic >> nv >> nf >> ne;
  Rows x(static_cast<Eigen::Index>(nv), 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    std::string a, b, c;  // through strtod: the same rounding as the document's reader
    f >> a >> b >> c;
    x.row(i) << std::strtod(a.c_str(), nullptr), std::strtod(b.c_str(), nullptr), std::strtod(c.c_str(), nullptr);
  }
  return x;
}

const std::vector<std::string> RUN = {"--frames", "8", "--target-volume", "0.8", "-q"};

std::vector<std::string> run_args(const std::string& in, const std::string& out) {
  std::vector<std::string> a = {"run", in, "-o", out};
  a.insert(a.end(), RUN.begin(), RUN.end());
  return a;
}

TEST_F(CliAttributes, ObjKeepsUvsGroupsMaterialsAndQuadsWithTheRunsPositionsAndNewNormals) {
  const shellcontract::test::TexturedObj t = shellcontract::test::textured_uv_sphere();
  const std::string in = file("ball.obj");
  std::ofstream(in) << t.text;
  std::vector<std::string> with_gltf = run_args(in, file("out.obj"));
  with_gltf.insert(with_gltf.end(), {"--gltf", file("out.glb")});
  const RunResult obj = run_cli(with_gltf);
  ASSERT_TRUE(obj.exit_code == 0 || obj.exit_code == 5) << obj.output;
  // The .glb carries the texture coordinates and names its fields (tests/export reads one back
  // in full; here: the CLI hands them over). Its JSON chunk is text.
  const std::string glb = read_text(file("out.glb"));
  for (const char* s :
       {"\"TEXCOORD_0\"", "\"_MEAN_CURVATURE\"", "\"_GAUSSIAN_CURVATURE\"", "\"_PRESSURE\"",
        "\"_ENERGY_DENSITY\"", "\"values_attribute\"", "\"frame\""})
    EXPECT_NE(glb.find(s), std::string::npos) << s << " missing in the .glb";
  // No COLOR_n: glTF multiplies COLOR_0 with the base colour, which tinted the texture.
  EXPECT_EQ(glb.find("\"COLOR_"), std::string::npos) << "the fields must not be vertex colours";
  const RunResult off = run_cli(run_args(in, file("out.off")));
  ASSERT_EQ(off.exit_code, obj.exit_code) << off.output;
  const Rows x = off_vertices(file("out.off"));
  ASSERT_EQ(x.rows(), t.x.rows());
  ASSERT_GT((x - t.x).cwiseAbs().maxCoeff(), 1e-3);  // the run moved the vertices

  const std::vector<std::string> a = lines_of(t.text), b = lines_of(read_text(file("out.obj")));
  ASSERT_EQ(a.size(), b.size());
  Eigen::Index v = 0, j = 0;
  Rows normals(x.rows(), 3);
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].rfind("v ", 0) == 0) {
      const std::vector<double> p = numbers_after_key(b[i]), q = numbers_after_key(a[i]);
      ASSERT_EQ(p.size(), q.size()) << b[i];
      for (int k = 0; k < 3; ++k) EXPECT_EQ(p[static_cast<std::size_t>(k)], x(v, k)) << b[i];
      for (std::size_t k = 3; k < p.size(); ++k) EXPECT_EQ(p[k], q[k]) << b[i];  // the vertex colour
      ++v;
    } else if (a[i].rfind("vn ", 0) == 0) {
      const std::vector<double> n = numbers_after_key(b[i]);
      ASSERT_EQ(n.size(), 3u) << b[i];
      ASSERT_LT(j, normals.rows());
      normals.row(j++) << n[0], n[1], n[2];
    } else {
      EXPECT_EQ(b[i], a[i]) << "line " << i + 1;  // vt, f (quads too), g, o, s, usemtl, mtllib, comments
    }
  }
  EXPECT_EQ(v, t.x.rows());
  ASSERT_EQ(j, t.x.rows());
  // The normals of the result's own polygons: each vertex's normal is the normalized sum of the
  // vector areas of the polygons around it (every vn here belongs to one vertex).
  Rows expect = Rows::Zero(x.rows(), 3);
  for (const auto& p : t.polygons) {
    Eigen::RowVector3d area = Eigen::RowVector3d::Zero();
    for (std::size_t k = 1; k + 1 < p.size(); ++k) {
      const Eigen::Vector3d e1 = (x.row(static_cast<Eigen::Index>(p[k][0])) - x.row(static_cast<Eigen::Index>(p[0][0]))).transpose();
      const Eigen::Vector3d e2 = (x.row(static_cast<Eigen::Index>(p[k + 1][0])) - x.row(static_cast<Eigen::Index>(p[0][0]))).transpose();
      area += e1.cross(e2).transpose();
    }
    for (const auto& c : p) expect.row(static_cast<Eigen::Index>(c[0])) += area;
  }
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    EXPECT_NEAR((normals.row(i) - expect.row(i).normalized()).norm(), 0.0, 1e-12) << "normal " << i;
}

TEST_F(CliAttributes, PlyKeepsItsTextureCoordinatesAndColours) {
  // The textured sphere's triangles as an ascii PLY with per-vertex (s, t) and a colour.
  const shellcontract::test::TexturedObj t = shellcontract::test::textured_uv_sphere(6, 10);
  std::size_t triangles = 0;
  for (const auto& p : t.polygons) triangles += p.size() - 2;
  std::ostringstream o;
  o.precision(17);
  o << "ply\nformat ascii 1.0\ncomment kept\nelement vertex " << t.x.rows()
    << "\nproperty double x\nproperty double y\nproperty double z\nproperty float s\nproperty float t\n"
       "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face " << triangles
    << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (Eigen::Index i = 0; i < t.x.rows(); ++i)
    o << t.x(i, 0) << ' ' << t.x(i, 1) << ' ' << t.x(i, 2) << ' ' << 0.5 * static_cast<double>(i % 3) << ' '
      << 0.25 * static_cast<double>(i % 4) << ' ' << (i * 7) % 256 << ' ' << (i * 13) % 256 << ' ' << 255 - i % 256 << '\n';
  for (const auto& p : t.polygons)
    for (std::size_t k = 1; k + 1 < p.size(); ++k) o << "3 " << p[0][0] << ' ' << p[k][0] << ' ' << p[k + 1][0] << '\n';
  const std::string in = file("ball.ply");
  std::ofstream(in) << o.str();
  const RunResult ply = run_cli(run_args(in, file("out.ply")));
  ASSERT_TRUE(ply.exit_code == 0 || ply.exit_code == 5) << ply.output;
  const RunResult off = run_cli(run_args(in, file("out.off")));
  ASSERT_EQ(off.exit_code, ply.exit_code) << off.output;
  const Rows x = off_vertices(file("out.off"));

  const std::string a = o.str(), b = read_text(file("out.ply"));
  const std::size_t h = a.find("end_header\n") + 11;
  ASSERT_EQ(b.substr(0, h), a.substr(0, h));  // the header, comment and property list as they were
  const std::vector<std::string> ta = [&] { std::vector<std::string> v; std::istringstream s(a.substr(h)); for (std::string w; s >> w;) v.push_back(w); return v; }();
  const std::vector<std::string> tb = [&] { std::vector<std::string> v; std::istringstream s(b.substr(h)); for (std::string w; s >> w;) v.push_back(w); return v; }();
  ASSERT_EQ(ta.size(), tb.size());
  const std::size_t vertex_tokens = 8 * static_cast<std::size_t>(t.x.rows());
  for (std::size_t i = 0; i < ta.size(); ++i) {
    if (i < vertex_tokens && i % 8 < 3)
      EXPECT_EQ(std::strtod(tb[i].c_str(), nullptr), x(static_cast<Eigen::Index>(i / 8), static_cast<Eigen::Index>(i % 8))) << "token " << i;
    else
      EXPECT_EQ(tb[i], ta[i]) << "token " << i;  // s, t, colours, faces
  }
}

TEST_F(CliAttributes, ExportedFramesOfAnObjAreWrittenAsItsResultIs) {
  // --export-dir's frames go through -o's writer: each is the input file with that frame's
  // positions and normals (vt, quads, groups, materials, the object kept), the last one the result.
  const shellcontract::test::TexturedObj t = shellcontract::test::textured_uv_sphere();
  const std::string in = file("ball.obj");
  std::ofstream(in) << t.text;
  std::vector<std::string> args = run_args(in, file("out.obj"));
  args.insert(args.end(), {"--export-every", "4", "--export-dir", file("frames")});
  const RunResult r = run_cli(args);
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 5) << r.output;
  EXPECT_EQ(read_text(file("frames/out_8.obj")), read_text(file("out.obj")));
  const std::vector<std::string> a = lines_of(t.text);
  for (const char* frame : {"frames/out_0.obj", "frames/out_4.obj"}) {
    const std::vector<std::string> b = lines_of(read_text(file(frame)));
    ASSERT_EQ(b.size(), a.size()) << frame;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (a[i].rfind("v ", 0) != 0 && a[i].rfind("vn ", 0) != 0) {
        EXPECT_EQ(b[i], a[i]) << frame << " line " << i + 1;
      }
  }
}

TEST_F(CliAttributes, AnObjTheDocumentCannotReadIsWrittenPlainWithAWarning) {
  // "f 1/1/1/1": CGAL's reader takes the vertex and skips the rest; the document refuses it.
  const std::string in = file("odd.obj");
  std::ofstream(in) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\n"
                       "f 1/1/1/1 3/1/1/1 2/1/1/1\nf 1/1/1/1 2/1/1/1 4/1/1/1\nf 1/1/1/1 4/1/1/1 3/1/1/1\nf 2/1/1/1 3/1/1/1 4/1/1/1\n";
  const RunResult r = run_cli({"run", in, "-o", file("odd_out.obj"), "--frames", "2", "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: the result is written without the input's attributes: " + in), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(file("odd_out.obj")));
}

TEST_F(CliAttributes, AMeshThatRepairChangedIsWrittenPlainWithAWarning) {
  // An unused vertex: check refuses it, --repair removes it, and the file's vertex numbering
  // no longer holds.
  const std::string in = file("spare.obj");
  std::ofstream(in) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 5 5 5\nvt 0 0\n"
                       "f 1/1 3/1 2/1\nf 1/1 2/1 4/1\nf 1/1 4/1 3/1\nf 2/1 3/1 4/1\n";
  const RunResult r = run_cli({"run", in, "-o", file("spare_out.obj"), "--repair", "--frames", "2", "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: the result is written without the input's attributes: --repair changed the mesh"
                          " (dropped: 1 texture coordinate (vt))"),
            std::string::npos) << r.output;
  EXPECT_EQ(read_text(file("spare_out.obj")).find("vt "), std::string::npos);  // the plain writer's
}

TEST_F(CliAttributes, AnotherFormatThanTheInputsIsWrittenPlainWithAWarningNamingWhatIsDropped) {
  // A square pyramid with texture coordinates, normals, a material and a quad base: a .ply result
  // is written by the plain writer (positions and triangles), which drops them all.
  const std::string in = file("pyramid.obj");
  std::ofstream(in) << "mtllib pyramid.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n"
                       "vt 0 0\nvt 1 0\nvn 0 0 1\nusemtl stone\n"
                       "f 1/1/1 4/2/1 3/1/1 2/2/1\nf 1/1/1 2/2/1 5/1/1\nf 2/1/1 3/2/1 5/1/1\n"
                       "f 3/1/1 4/2/1 5/1/1\nf 4/1/1 1/2/1 5/1/1\n";
  const RunResult r = run_cli({"run", in, "-o", file("pyramid.ply"), "--frames", "2", "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(
      r.output.find("warning: the result is written without the input's attributes: it is a "
                    ".ply file, the input a .obj file (dropped: 2 texture coordinates (vt); "
                    "1 normal (vn); 1 material (usemtl stone); the material library (mtllib "
                    "pyramid.mtl); 1 polygon with more than 3 corners (written as triangles))"),
      std::string::npos)
      << r.output;
  const std::string out = read_text(file("pyramid.ply"));
  EXPECT_EQ(out.find("property float s"), std::string::npos);  // the plain writer's
  EXPECT_EQ(out.find("nx"), std::string::npos);

  // A plain OFF has nothing but positions and polygons: another format drops nothing, no warning.
  const std::string off = file("pyramid.off");
  std::ofstream(off) << "OFF\n5 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 1\n"
                        "3 0 3 2\n3 0 2 1\n3 0 1 4\n3 1 2 4\n3 2 3 4\n3 3 0 4\n";
  const RunResult plain = run_cli({"run", off, "-o", file("plain.ply"), "--frames", "2", "-q"});
  EXPECT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_EQ(plain.output.find("without the input's attributes"), std::string::npos) << plain.output;
  EXPECT_TRUE(fs::exists(file("plain.ply")));
}

}  // namespace
