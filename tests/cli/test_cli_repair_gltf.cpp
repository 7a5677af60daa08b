// `shellcontract repair IN -o OUT.glb / OUT.gltf`: a mesh that `check` refuses comes out as a
// glTF 2.0 file that `check` accepts, read back here with the project's glTF reader; a usable
// .glb into a .glb is the input's bytes. Before, every glTF OUTPUT was "cannot write 'fixed.glb':
// unknown extension '.glb'" (exit 1) after the repair had run.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/gltf_reader.hpp"
#include "shellcontract/export.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/cli_runner.hpp"
#include "support/gltf_files.hpp"
#include "support/scratch_dir.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

using Json = nlohmann::json;

class CliRepairGltf : public test::ScratchDirTest {
 protected:
  CliRepairGltf() : ScratchDirTest("shellcontract_cli_repair_gltf_") {}
  std::string out(const std::string& name) const { return (dir_ / name).string(); }
};

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// The JSON of a .glb (its first chunk) or a .gltf.
Json gltf_json(const std::string& bytes) {
  if (bytes.compare(0, 4, "glTF") != 0) return Json::parse(bytes);
  std::uint32_t length = 0;
  for (int i = 0; i < 4; ++i)
    length |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[12 + i])) << (8 * i);
  return Json::parse(bytes.substr(20, length));
}

/// A tetrahedron, outward, written by the run's glTF writer (write_gltf_animation, one frame);
/// without its last face (`open`) it is what `check` refuses.
std::string tetra_glb(const std::string& path, bool open) {
  GltfAnimation a;
  a.name = "tetra";
  Positions x(4, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  a.frames = {x};
  a.frame_numbers = {0};
  a.faces.resize(open ? 3 : 4, 3);
  a.faces.row(0) << 0, 2, 1;
  a.faces.row(1) << 0, 1, 3;
  a.faces.row(2) << 0, 3, 2;
  if (!open) a.faces.row(3) << 1, 2, 3;
  write_gltf_animation(path, a);
  return path;
}

/// Six times the signed volume of the soup's triangles as the file winds them.
double signed_volume6(const GltfSoup& s) {
  double v = 0.0;
  for (const auto& f : s.faces) {
    const auto& a = s.points[f[0]];
    const auto& b = s.points[f[1]];
    const auto& c = s.points[f[2]];
    v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
         a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  return v;
}

/// What every glTF that repair writes for a rebuilt or converted mesh holds: one scene, node,
/// mesh and triangle primitive; POSITION whose min and max are its positions' bounds; NORMAL;
/// unsigned 32-bit indices; a .gltf's buffer embedded as a data URI. Returns the soup read back.
GltfSoup expect_bare_gltf(const std::string& path, std::size_t faces) {
  const std::string bytes = slurp(path);
  const bool glb = path.size() > 4 && path.compare(path.size() - 4, 4, ".glb") == 0;
  EXPECT_EQ(bytes.compare(0, 4, "glTF") == 0, glb) << path;
  const Json j = gltf_json(bytes);
  EXPECT_EQ(j["asset"]["version"], "2.0");
  EXPECT_EQ(j["scenes"].size(), 1u);
  EXPECT_EQ(j["nodes"].size(), 1u);
  EXPECT_EQ(j["meshes"].size(), 1u);
  const Json& prim = j["meshes"][0]["primitives"][0];
  EXPECT_EQ(j["meshes"][0]["primitives"].size(), 1u);
  EXPECT_TRUE(prim["attributes"].contains("NORMAL")) << prim.dump();
  const Json& indices = j["accessors"][prim["indices"].get<std::size_t>()];
  EXPECT_EQ(indices["componentType"], 5125);  // UNSIGNED_INT
  EXPECT_EQ(indices["count"], 3 * faces);
  if (!glb) {
    EXPECT_EQ(
        j["buffers"][0]["uri"].get<std::string>().rfind("data:application/octet-stream;base64,", 0),
        0u);
  }

  const GltfSoup s = read_gltf(path, bytes);
  EXPECT_EQ(s.faces.size(), faces);
  EXPECT_GT(signed_volume6(s), 0.0) << path << ": the faces are wound inward";
  const Json& position = j["accessors"][prim["attributes"]["POSITION"].get<std::size_t>()];
  // The node moves the stored positions by its translation only (none: glTF's default).
  const Json& node = j["nodes"][0];
  EXPECT_FALSE(node.contains("matrix") || node.contains("rotation") || node.contains("scale"));
  std::array<double, 3> moved{0.0, 0.0, 0.0};
  if (node.contains("translation"))
    for (std::size_t c = 0; c < 3; ++c) moved[c] = node["translation"][c].get<double>();
  for (std::size_t c = 0; c < 3; ++c) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& p : s.points)
      lo = std::min(lo, p[c] - moved[c]), hi = std::max(hi, p[c] - moved[c]);
    EXPECT_EQ(position["min"][c].get<double>(), lo) << path << " coordinate " << c;
    EXPECT_EQ(position["max"][c].get<double>(), hi) << path << " coordinate " << c;
  }
  // The usability check (read_input_mesh, as `check`): closed, manifold, outward as written.
  InputReport report;
  EXPECT_NO_THROW(read_input_mesh(path, &report)) << path;
  EXPECT_EQ(report.faces, faces);
  EXPECT_FALSE(report.reoriented) << path;
  EXPECT_GT(report.volume, 0.0);
  return s;
}

TEST_F(CliRepairGltf, AnOpenGlbIsRepairedIntoAClosedOutwardGlbAndGltf) {
  const std::string in = tetra_glb(out("open.glb"), true);
  ASSERT_EQ(test::run_cli({"check", in}).exit_code, 2);
  for (const std::string ext : {".glb", ".gltf"}) {
    const std::string o = out("fixed" + ext);
    const test::RunResult r = test::run_cli({"repair", in, "-o", o});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("1 hole filled with 1 face"), std::string::npos) << r.output;
    // The run writer's mesh has normals and a name: both named, not dropped silently.
    EXPECT_NE(r.output.find("dropped from " + o), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("vertex attributes NORMAL"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("node and mesh names (tetra, tetra)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("application data (extras) on 1 object"), std::string::npos)
        << r.output;
    const GltfSoup s = expect_bare_gltf(o, 4);
    EXPECT_EQ(s.points.size(), 4u);
    EXPECT_EQ(test::run_cli({"check", o}).exit_code, 0);
  }
  const test::RunResult j = test::run_cli({"repair", in, "-o", out("again.glb"), "--json"});
  EXPECT_NE(j.output.find("\"written_as\": \"repaired\""), std::string::npos) << j.output;
  EXPECT_NE(j.output.find("\"binary\": true"), std::string::npos) << j.output;
}

TEST_F(CliRepairGltf, AUsableGlbIntoAGlbIsTheInputsBytes) {
  const std::string in = tetra_glb(out("closed.glb"), false);
  const test::RunResult r = test::run_cli({"repair", in, "-o", out("copy.GLB")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(slurp(out("copy.GLB")), slurp(in));
  EXPECT_NE(r.output.find("(the input's bytes, unchanged)"), std::string::npos) << r.output;
  // Into a .gltf: its vertices and triangles (converted), the rest named.
  const test::RunResult c = test::run_cli({"repair", in, "-o", out("closed.gltf"), "--json"});
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("\"written_as\": \"converted\""), std::string::npos) << c.output;
  expect_bare_gltf(out("closed.gltf"), 4);
}

TEST_F(CliRepairGltf, ARepairedTexturedGltfNamesWhatItDrops) {
  test::GltfScene scene;
  scene.primitives.push_back(test::octahedron_primitive(true, true));
  scene.primitives[0].indices.resize(21);  // the last face left out: a hole
  scene.png = "not decoded: any bytes";
  const std::string in = write("holed.gltf", test::gltf_text(test::gltf_parts(scene)));
  ASSERT_EQ(test::run_cli({"check", in}).exit_code, 2);
  const test::RunResult r = test::run_cli({"repair", in, "-o", out("fixed.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* s :
       {"vertex attributes NORMAL, TEXCOORD_0", "1 material (skin)", "1 texture", "1 image"})
    EXPECT_NE(r.output.find(s), std::string::npos) << s << " not in:\n" << r.output;
  expect_bare_gltf(out("fixed.glb"), 8);
}

TEST_F(CliRepairGltf, AnOffIntoGlbNamesItsQuadsAndItsRoundedDigits) {
  // Usable with quads: converted, each quad as two triangles in its winding.
  const test::RunResult q = test::run_cli(
      {"repair", std::string(test::MESH_DIR) + "/cube_quads.off", "-o", out("cube.gltf")});
  ASSERT_EQ(q.exit_code, 0) << q.output;
  EXPECT_NE(
      q.output.find("6 polygons with more than 3 corners (glTF holds triangles: 12 triangles"),
      std::string::npos)
      << q.output;
  expect_bare_gltf(out("cube.gltf"), 12);
  // Open, with a coordinate that a float does not hold: repaired, and the lost digits named.
  const std::string in =
      write("open.off", "OFF\n4 3 0\n0.1 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n");
  const test::RunResult r = test::run_cli({"repair", in, "-o", out("open.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("the positions' digits beyond 32-bit floats (1 vertex rounded"),
            std::string::npos)
      << r.output;
  expect_bare_gltf(out("open.glb"), 4);
}

TEST_F(CliRepairGltf, ATinyMeshAwayFromTheOriginIsWrittenWithItsShape) {
  // Usable in doubles (check works at a unit diagonal). Stored absolute as float32 every vertex
  // became (1, 1, 1) and the file was refused; relative to its centre it keeps its shape.
  const std::string in = write("tiny.off",
                               "OFF\n4 4 0\n1 1 1\n1.000000000001 1 1\n1 1.000000000001 1\n"
                               "1 1 1.000000000001\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  ASSERT_EQ(test::run_cli({"check", in}).exit_code, 0);
  const test::RunResult r = test::run_cli({"repair", in, "-o", out("tiny.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const GltfSoup s = expect_bare_gltf(out("tiny.glb"), 4);
  ASSERT_EQ(s.points.size(), 4u);
  const double size = 1e-12, tol = 8.0 * size * std::numeric_limits<float>::epsilon();
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t c = 0; c < 3; ++c)
      EXPECT_NEAR(s.points[i][c], 1.0 + (i == c + 1 ? 1e-12 : 0.0), tol) << i << ", " << c;
}

TEST_F(CliRepairGltf, PositionsBeyondFloatRangeAreNotWritten) {
  // 1e39 from the centre: no float32 holds it, relative or not.
  const std::string in = write(
      "big.off", "OFF\n4 3 0\n0 0 0\n1e39 0 0\n0 1e39 0\n0 0 1e39\n3 0 2 1\n3 0 1 3\n3 0 3 2\n");
  const test::RunResult r = test::run_cli({"repair", in, "-o", out("big.glb")});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("span more than glTF's 32-bit floats hold"), std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(out("big.glb")));
  // Nothing else either: no temporary left beside the input.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_),
                          std::filesystem::directory_iterator()),
            1);
}

TEST_F(CliRepairGltf, AMeshFarFromTheOriginKeepsItsShape) {
  // An open tetrahedron of unit size at UTM-like coordinates (float spacing 0.5 at northing 5e6).
  // Stored absolute as float32, its corners moved by up to a quarter of its size; relative to
  // its centre (the node's translation), by a few float roundings of its size.
  const std::array<std::array<double, 3>, 4> corners{{{500000.3, 5000000.3, 100.3},
                                                      {500001.3, 5000000.3, 100.3},
                                                      {500000.3, 5000001.3, 100.3},
                                                      {500000.3, 5000000.3, 101.3}}};
  std::ostringstream off;
  off.precision(17);
  off << "OFF\n4 3 0\n";
  for (const auto& p : corners) off << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  off << "3 0 2 1\n3 0 1 3\n3 0 3 2\n";
  const std::string in = write("far.off", off.str());
  const test::RunResult r = test::run_cli({"repair", in, "-o", out("far.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const GltfSoup s = expect_bare_gltf(out("far.glb"), 4);
  ASSERT_EQ(s.points.size(), 4u);
  const double tol = 8.0 * std::sqrt(3.0) * std::numeric_limits<float>::epsilon();
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t c = 0; c < 3; ++c)
      EXPECT_NEAR(s.points[i][c], corners[i][c], tol) << "vertex " << i << " coordinate " << c;
}

TEST_F(CliRepairGltf, FloatPositionsComeBackBitForBit) {
  // Coordinates that float32 holds (a .glb's or an STL's) are stored as they are: relative to a
  // centre they would round, and the conversion would report lost digits it need not lose.
  const std::string in = write("floats.off",
                               "OFF\n4 3 0\n0.1875 0 0\n1.25 0 0\n0 1.5 0\n0 0 3.0625\n"
                               "3 0 2 1\n3 0 1 3\n3 0 3 2\n");
  const test::RunResult r = test::run_cli({"repair", in, "-o", out("floats.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("beyond 32-bit floats"), std::string::npos) << r.output;
  const GltfSoup s = expect_bare_gltf(out("floats.glb"), 4);
  const std::array<std::array<double, 3>, 4> corners{
      {{0.1875, 0, 0}, {1.25, 0, 0}, {0, 1.5, 0}, {0, 0, 3.0625}}};
  ASSERT_EQ(s.points.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(s.points[i][c], corners[i][c]);
}

TEST_F(CliRepairGltf, AGltfCopiedIntoAnotherFolderNamesTheBufferItLeavesBehind) {
  test::GltfScene scene;
  scene.primitives.push_back(test::octahedron_primitive(false, false));
  const test::GltfParts parts = test::gltf_parts(scene);
  write("octa.bin", parts.bin);
  const std::string text = test::gltf_text(parts, "octa.bin");
  const std::string in = write("octa.gltf", text);
  ASSERT_EQ(test::run_cli({"check", in}).exit_code, 0);
  std::filesystem::create_directories(dir_ / "elsewhere");
  const std::string moved = (dir_ / "elsewhere" / "octa.gltf").string();
  const test::RunResult r = test::run_cli({"repair", in, "-o", moved});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(slurp(moved), text);
  EXPECT_NE(r.output.find("warning: " + moved + ": names 'octa.bin', a file beside " + in),
            std::string::npos)
      << r.output;
  const test::RunResult beside = test::run_cli({"repair", in, "-o", out("copy.gltf")});
  ASSERT_EQ(beside.exit_code, 0) << beside.output;
  EXPECT_EQ(beside.output.find("warning"), std::string::npos) << beside.output;
}

TEST_F(CliRepairGltf, TheInputAsOutputIsRefusedAndLeftAsItWas) {
  const std::string in = tetra_glb(out("open.glb"), true);
  const std::string before = slurp(in);
  const test::RunResult r = test::run_cli({"repair", in, "-o", in});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("is the input file"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(in), before);
}

}  // namespace
}  // namespace shellcontract
