// `shellcontract repair` and `run --repair` as a user runs them (README, Exit codes): what is
// written, what is refused, and that a usable mesh runs exactly as without --repair.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>

#include "support/cli_runner.hpp"
#include "support/seam_split.hpp"
#include "support/textured_obj.hpp"
#include "test_paths.hpp"

namespace {

namespace fs = std::filesystem;
using shellcontract::test::RunResult;
using shellcontract::test::run_cli;

class CliRepair : public ::testing::Test {
 protected:
  fs::path dir;
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
    dir = fs::temp_directory_path() / ("shellcontract_cli_repair_" + std::to_string(::getpid()) + "_" +
                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
  }
  void TearDown() override {
    if (!dir.empty()) fs::remove_all(dir);
  }
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir / name).string();
    std::ofstream(path) << text;
    return path;
  }
  std::string out(const std::string& name) { return (dir / name).string(); }
};

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

std::string mesh_path(const std::string& name) { return std::string(shellcontract::test::MESH_DIR) + "/" + name; }

/// meshes/cube.off without its bottom square (faces 0 and 1).
const char* OPEN_CUBE =
    "OFF\n8 10 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
    "3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n";

/// meshes/cube.off as a binary STL (80-byte header, facet count, 50 bytes per facet), the last
/// `missing` facets left out (missing = 1: an open box).
std::string binary_stl_cube(std::size_t missing = 0) {
  const float x[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int f[12][3] = {{0, 3, 2}, {0, 2, 1}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                        {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  std::string s = "binary cube";
  s.resize(80, ' ');
  const std::uint32_t n = 12 - static_cast<std::uint32_t>(missing);
  s.append(reinterpret_cast<const char*>(&n), 4);  // little-endian, as the machines the tests run on
  for (std::uint32_t t = 0; t < n; ++t) {
    const float normal[3] = {0, 0, 0};
    s.append(reinterpret_cast<const char*>(normal), 12);
    for (const int v : f[t]) s.append(reinterpret_cast<const char*>(x[v]), 12);
    s.append(2, '\0');
  }
  return s;
}

/// The textured sphere without its polygon `skip`'s `f` line: a hole.
std::string without_face(const std::string& obj, std::size_t skip) {
  std::istringstream in(obj);
  std::string out;
  std::size_t face = 0;
  for (std::string line; std::getline(in, line);)
    if (line.rfind("f ", 0) != 0 || face++ != skip) out += line + "\n";
  return out;
}

TEST_F(CliRepair, OpenCubeIsRepairedWrittenAndThenUsable) {
  const std::string in = write("open_cube.off", OPEN_CUBE);
  const std::string o = out("closed.off");
  ASSERT_EQ(run_cli({"check", in}).exit_code, 2);
  const RunResult r = run_cli({"repair", in, "-o", o});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // One hole: the count and its words agree ("1 hole", not "1 holes").
  EXPECT_NE(r.output.find("\n1 hole filled with 2 faces and 0 vertices (largest: 4 boundary edges)\n"),
            std::string::npos)
      << r.output;
  const RunResult c = run_cli({"check", o});
  EXPECT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("faces: 12\n"), std::string::npos) << c.output;
}

TEST_F(CliRepair, JsonReportCountsTheHole) {
  const RunResult r = run_cli({"repair", write("open_cube.off", OPEN_CUBE), "-o", out("closed.ply"), "--json"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"holes_filled\": 1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"usable\": true"), std::string::npos) << r.output;
}

TEST_F(CliRepair, SingleTriangleIsRefusedNamingTheFileAndNothingIsWritten) {
  const std::string in = write("triangle.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  const std::string o = out("never.off");
  const RunResult r = run_cli({"repair", in, "-o", o});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(in + ": cannot repair: "), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(o));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1) << "a file besides the input";
}

TEST_F(CliRepair, PointCloudIsRefusedNamingTheFile) {
  const std::string in = write("points.off", "OFF\n4 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
  const RunResult r = run_cli({"repair", in, "-o", out("never.off")});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(in + ": cannot repair: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("0 faces"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out("never.off")));
}

TEST_F(CliRepair, MissingOutputIsBadUsage) {
  EXPECT_EQ(run_cli({"repair", mesh_path("cube.off")}).exit_code, 1);
  EXPECT_EQ(run_cli({"repair", mesh_path("cube.off"), "-o", mesh_path("cube.off")}).exit_code, 1);
}

// --max-hole-edges was read into an unsigned type, so -1 became its wrapped value: accepted,
// every hole filled, exit 0. A negative count is bad usage now, before anything is written;
// 0 still means "fill every hole" (docs/cli.md).
TEST_F(CliRepair, ANegativeMaxHoleEdgesIsBadUsageAndNothingIsWritten) {
  const std::string in = write("open_cube.off", OPEN_CUBE);
  for (const char* n : {"-1", "-4", "-9223372036854775808"}) {
    const RunResult r = run_cli({"repair", in, "-o", out("closed.off"), "--max-hole-edges", n});
    EXPECT_EQ(r.exit_code, 1) << n << ": " << r.output;
    EXPECT_NE(r.output.find("--max-hole-edges"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(">= 0"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out("closed.off"))) << n;
  }
  for (const char* n : {"1.5", "nan", "inf", "ten"})
    EXPECT_EQ(run_cli({"repair", in, "-o", out("closed.off"), "--max-hole-edges", n}).exit_code, 1) << n;
  const RunResult zero = run_cli({"repair", in, "-o", out("closed.off"), "--max-hole-edges", "0"});
  EXPECT_EQ(zero.exit_code, 0) << zero.output;
  EXPECT_NE(zero.output.find("1 hole filled"), std::string::npos) << zero.output;
}

// An output name of no format repair writes was refused only when written: after the repair, so
// an input that cannot be repaired gave exit 2 "cannot repair" for what is bad usage, and the
// message listed .off, .obj, .ply and .stl but not the .glb and .gltf that repair also writes.
// Now it is refused before the input is read, as `run` refuses -o, naming every format.
TEST_F(CliRepair, AnOutputOfNoFormatIsBadUsageBeforeTheRepairNamingEveryFormat) {
  const std::string usable = mesh_path("cube.off");
  const std::string unrepairable = write("flat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  for (const std::string& in : {usable, unrepairable})
    for (const char* name : {"r.txt", "r", "r.off.bak"}) {
      const RunResult r = run_cli({"repair", in, "-o", out(name)});
      EXPECT_EQ(r.exit_code, 1) << in << " -o " << name << ": " << r.output;
      EXPECT_NE(r.output.find("-o '" + out(name) + "'"), std::string::npos) << r.output;
      for (const char* ext : {".off", ".obj", ".ply", ".stl", ".glb", ".gltf"})
        EXPECT_NE(r.output.find(ext), std::string::npos) << ext << " not named: " << r.output;
      EXPECT_EQ(r.output.find("cannot repair"), std::string::npos) << r.output;
      EXPECT_FALSE(fs::exists(out(name)));
    }
  // Every format named is written, in any case of the extension.
  for (const char* name : {"r.GLB", "r.gltf", "r.Stl"})
    EXPECT_EQ(run_cli({"repair", usable, "-o", out(name)}).exit_code, 0) << name;
}

TEST_F(CliRepair, RunRepairRunsAnOpenMesh) {
  const std::string in = write("open_cube.off", OPEN_CUBE);
  EXPECT_EQ(run_cli({"run", in, "-o", out("a.off"), "--frames", "3", "-q"}).exit_code, 2);
  const RunResult r = run_cli({"run", in, "-o", out("b.off"), "--frames", "3", "-q", "--repair"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("  1 hole filled with 2 faces"), std::string::npos) << r.output;
  EXPECT_EQ(run_cli({"check", out("b.off")}).exit_code, 0);
}

// A face that names a vertex the file lacks: check and run refuse the file, as before; repair
// drops the face (repair.md, step 4) and fills the hole it leaves. Before, repair refused the
// file at its strict read ("cannot repair: the file cannot be read (... vertex index out of
// range ...)"), so the drop was never reached.
TEST_F(CliRepair, AFaceNamingAMissingVertexIsDroppedAndItsHoleFilled) {
  const std::string in = mesh_path("bad/index_out_of_range.off");
  const RunResult c = run_cli({"check", in});
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find("vertex index out of range: face 4 (line 15) refers to vertex 8"),
            std::string::npos)
      << c.output;
  EXPECT_EQ(run_cli({"run", in, "-o", out("never.off"), "--frames", "2", "-q"}).exit_code, 2);
  EXPECT_FALSE(fs::exists(out("never.off")));
  const RunResult r = run_cli({"repair", in, "-o", out("cube.off")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("1 face naming a missing vertex dropped (face 4, line 15)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("1 hole filled"), std::string::npos) << r.output;
  EXPECT_EQ(run_cli({"check", out("cube.off")}).exit_code, 0);
  const RunResult j = run_cli({"repair", in, "-o", out("cube.ply"), "--json"});
  EXPECT_EQ(j.exit_code, 0) << j.output;
  EXPECT_NE(j.output.find("\"missing_vertex_faces_dropped\": 1"), std::string::npos) << j.output;
  const RunResult run =
      run_cli({"run", in, "-o", out("run.off"), "--frames", "2", "-q", "--repair"});
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("  1 face naming a missing vertex dropped (face 4, line 15)"),
            std::string::npos)
      << run.output;
  EXPECT_EQ(run_cli({"check", out("run.off")}).exit_code, 0);
}

TEST_F(CliRepair, ObjFacesNamingMissingVerticesAreDroppedWithTheirLines) {
  // The unit cube; of its faces, the two of the side y = 0 name vertex 9 (of 8) and the relative
  // vertex -9 (lines 13 and 14), one of the side y = 1 names vertex 0 (line 17; OBJ counts from 1).
  std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
  obj += "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 9 6\nf -9 6 5\nf 2 3 7\nf 2 7 6\n";
  obj += "f 0 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
  const std::string in = write("cube.obj", obj);
  const RunResult c = run_cli({"check", in});
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find("vertex index out of range"), std::string::npos) << c.output;
  const RunResult r = run_cli({"repair", in, "-o", out("cube.off")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("3 faces naming a missing vertex dropped (face 4, line 13; face 5, line "
                          "14; face 8, line 17)"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(run_cli({"check", out("cube.off")}).exit_code, 0);
}

TEST_F(CliRepair, RunRepairLeavesAUsableMeshsRunUnchanged) {
  const std::string in = mesh_path("bumpy_sphere.off");
  ASSERT_EQ(run_cli({"run", in, "-o", out("plain.off"), "--frames", "5", "-q"}).exit_code, 0);
  ASSERT_EQ(run_cli({"run", in, "-o", out("repair.off"), "--frames", "5", "-q", "--repair"}).exit_code, 0);
  EXPECT_EQ(slurp(out("plain.off")), slurp(out("repair.off")));
}

// --------------------------------------------- what the output keeps (a usable input is not rewritten)

// Review 7 (F4): --regions FILE and --region-weights FILE number the faces and vertices of the
// input as read; a repair that changed the mesh renumbered them, and the ids fell on other faces
// without a word. Refused as bad usage (exit 1) naming the file, nothing written. A usable mesh,
// which --repair leaves as read, keeps its face list.
TEST_F(CliRepair, RunRepairThatChangedTheMeshRefusesIdsOfTheInput) {
  const std::string in = write("open.off", OPEN_CUBE);
  const std::string faces = write("faces.txt", "0 1\n");
  const std::string weights = write("weights.txt", "1\n1\n1\n1\n0\n0\n0\n0\n");
  for (const auto& [option, file, ids] :
       {std::tuple<std::string, std::string, std::string>{"--regions", faces, "faces"},
        {"--region-weights", weights, "vertices"}}) {
    SCOPED_TRACE(option);
    const RunResult r =
        run_cli({"run", in, "-o", out("a.off"), "--frames", "2", "-q", "--repair", option, file});
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find(option + " " + file + " numbers the " + ids + " of " + in +
                            " as read, and --repair renumbered them"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("run `shellcontract repair` first"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out("a.off")));
  }
  const std::string ico = write("ico.txt", "0 1 2\n");
  const RunResult usable = run_cli({"run", mesh_path("ico1.off"), "-o", out("b.off"), "--frames",
                                    "2", "-q", "--repair", "--regions", ico});
  EXPECT_EQ(usable.exit_code, 0) << usable.output;
}

TEST_F(CliRepair, AUsableTexturedObjIsCopiedByteForByte) {
  const std::string text = shellcontract::test::textured_uv_sphere().text;
  const std::string in = write("sphere.obj", text);
  const RunResult r = run_cli({"repair", in, "-o", out("copy.obj")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Before: "nothing changed", and the file was rewritten by CGAL's writer without its UVs,
  // normals, groups and materials, and with its quads split.
  EXPECT_EQ(slurp(out("copy.obj")), text);
  EXPECT_NE(r.output.find("nothing changed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(the input's bytes, unchanged)"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("dropped"), std::string::npos) << r.output;
}

TEST_F(CliRepair, ACopiedSeamSplitMeshCountsTheVerticesItWrote) {
  // The copy holds the file's vertices, seam copies included; the count had been the welded mesh's.
  const shellcontract::test::SeamSplitMesh m = shellcontract::test::seam_split_sphere();
  ASSERT_GT(static_cast<std::size_t>(m.x.rows()), m.closed_vertices);
  const std::string in = write("split.ply", m.ply());
  const RunResult r = run_cli({"repair", in, "-o", out("copy.ply")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(slurp(out("copy.ply")), m.ply());
  const std::string expected = "wrote " + out("copy.ply") + ": " + std::to_string(m.x.rows()) + " vertices (" +
                               std::to_string(m.closed_vertices) + " once its seam copies are welded), " +
                               std::to_string(m.tris.size()) + " faces, usable";
  EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
}

TEST_F(CliRepair, AUsableBinaryStlStaysTheSameBinaryStl) {
  const std::string bytes = binary_stl_cube();
  const std::string in = write("cube.stl", bytes);
  ASSERT_EQ(run_cli({"check", in}).exit_code, 0);
  const RunResult r = run_cli({"repair", in, "-o", out("copy.STL")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(slurp(out("copy.STL")), bytes);  // before: an ASCII STL
}

TEST_F(CliRepair, AUsableObjInAnotherFormatKeepsItsPolygonsAndNamesWhatItDoesNotCarry) {
  const std::string in = write("sphere.obj", shellcontract::test::textured_uv_sphere().text);
  const RunResult r = run_cli({"repair", in, "-o", out("sphere.ply")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // 96 polygons as read (72 quads), not the 168 triangles of before.
  EXPECT_NE(slurp(out("sphere.ply")).find("element face 96\n"), std::string::npos);
  for (const char* s : {"not carried into " , "115 texture coordinates (vt)", "86 normals (vn)",
                        "2 groups (g upper, lower)", "2 materials (usemtl north, south)"})
    EXPECT_NE(r.output.find(s), std::string::npos) << s << " not in:\n" << r.output;
  const RunResult c = run_cli({"check", out("sphere.ply")});
  EXPECT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("triangulated_faces: 72\n"), std::string::npos) << c.output;

  const RunResult j = run_cli({"repair", in, "-o", out("sphere.stl"), "--json"});
  ASSERT_EQ(j.exit_code, 0) << j.output;
  EXPECT_NE(j.output.find("\"written_as\": \"converted\""), std::string::npos) << j.output;
  EXPECT_NE(j.output.find("72 polygons with more than 3 corners (STL holds triangles: 144 triangles"),
            std::string::npos) << j.output;
  EXPECT_EQ(run_cli({"check", out("sphere.stl")}).exit_code, 0);
}

TEST_F(CliRepair, AUsableInsideOutMeshKeepsItsWindingInAnotherFormat) {
  // As a copy would: the file's faces, not the ones read_input_mesh turns outward for a run.
  const RunResult r = run_cli({"repair", mesh_path("inside_out_sphere.off"), "-o", out("s.stl")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const RunResult c = run_cli({"check", out("s.stl")});
  EXPECT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("reoriented: yes"), std::string::npos) << c.output;
}

TEST_F(CliRepair, ARepairedTexturedObjNamesEverythingItDrops) {
  const std::string in = write("holed.obj", without_face(shellcontract::test::textured_uv_sphere().text, 4));
  ASSERT_EQ(run_cli({"check", in}).exit_code, 2);
  const RunResult r = run_cli({"repair", in, "-o", out("fixed.obj")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Before: the attributes went without a word.
  for (const char* s : {"dropped from ", "115 texture coordinates (vt)", "86 normals (vn)", "2 groups (g upper, lower)",
                        "2 materials (usemtl north, south)", "the material library (mtllib sphere.mtl)",
                        "72 polygons with more than 3 corners (triangulated)"})
    EXPECT_NE(r.output.find(s), std::string::npos) << s << " not in:\n" << r.output;
  const RunResult j = run_cli({"repair", in, "-o", out("fixed2.obj"), "--json"});
  EXPECT_NE(j.output.find("\"written_as\": \"repaired\""), std::string::npos) << j.output;
  EXPECT_NE(j.output.find("\"dropped\": [\"115 texture coordinates (vt)\""), std::string::npos) << j.output;
}

TEST_F(CliRepair, ARepairedBinaryStlStaysBinary) {
  const std::string in = write("open.stl", binary_stl_cube(1));
  ASSERT_EQ(run_cli({"check", in}).exit_code, 2);
  const RunResult r = run_cli({"repair", in, "-o", out("closed.stl")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string bytes = slurp(out("closed.stl"));
  std::uint32_t n = 0;
  ASSERT_GE(bytes.size(), 84u);
  std::memcpy(&n, bytes.data() + 80, 4);
  EXPECT_EQ(n, 12u);
  EXPECT_EQ(bytes.size(), 84u + 50u * 12u);  // before: "solid ..." text
  EXPECT_EQ(run_cli({"check", out("closed.stl")}).exit_code, 0);
  EXPECT_NE(r.output.find("the 80-byte header ('binary cube')"), std::string::npos) << r.output;
  // A PLY holds doubles: binary too.
  ASSERT_EQ(run_cli({"repair", in, "-o", out("closed.ply")}).exit_code, 0);
  EXPECT_NE(slurp(out("closed.ply")).find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_EQ(run_cli({"check", out("closed.ply")}).exit_code, 0);
}

// Repair splits a pinched vertex into two at the same position; an STL stores positions only, and
// reading it merges them again: before, the STL was written and announced usable, and `check`
// refused it.
TEST_F(CliRepair, AnStlThatWouldMergeTwoVerticesIsNotWritten) {
  const std::string in = write("pinch.off",
                               "OFF\n7 8 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n-1 0 0\n0 -1 0\n0 0 -1\n"
                               "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 0 4 5\n3 0 6 4\n3 0 5 6\n3 4 6 5\n");
  ASSERT_EQ(run_cli({"check", in}).exit_code, 2);
  const RunResult r = run_cli({"repair", in, "-o", out("pinch.stl")});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("cannot write '" + out("pinch.stl") + "': an STL keeps no vertex identity"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(out("pinch.stl")));
  // The same mesh in a format with vertex numbers is usable, and a usable copy of it cannot be an STL either.
  ASSERT_EQ(run_cli({"repair", in, "-o", out("split.off")}).exit_code, 0);
  EXPECT_EQ(run_cli({"check", out("split.off")}).exit_code, 0);
  EXPECT_EQ(run_cli({"repair", out("split.off"), "-o", out("again.stl")}).exit_code, 1);
  EXPECT_FALSE(fs::exists(out("again.stl")));
}

}  // namespace
