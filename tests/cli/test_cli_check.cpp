// `shellcontract check` as a user runs it: exit codes and messages (docs/cli.md, "Exit codes").
// Runs the built executable (SHELLCONTRACT_CLI_PATH); skipped when it has not been built.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace {

using shellcontract::test::RunResult;
using shellcontract::test::run_cli;

class CliCheck : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(SHELLCONTRACT_CLI_PATH))
      GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
  }
};

std::string mesh_path(const std::string& name) { return std::string(shellcontract::test::MESH_DIR) + "/" + name; }

/// The number printed right after `key` in `text`; NaN if the key is absent.
double number_after(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  if (at == std::string::npos) return std::nan("");
  return std::stod(text.substr(at + key.size()));
}

TEST_F(CliCheck, UnitCubeIsUsableWithKnownCounts) {
  const RunResult r = run_cli({"check", mesh_path("cube.off")});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const char* s : {"vertices: 8\n", "faces: 12\n", "edges: 18\n", "components: 1\n", "euler_characteristic: 2\n",
                        "genus: 0\n", "closed: yes\n", "manifold: yes\n", "self_intersecting_pairs: 0\n", "usable: yes\n"})
    EXPECT_NE(r.output.find(s), std::string::npos) << "missing '" << s << "' in:\n" << r.output;
  // Volume 1 and diagonal sqrt(3) (printed with 17 digits; compared up to rounding).
  EXPECT_NEAR(number_after(r.output, "\nvolume: "), 1.0, 1e-14) << r.output;
  EXPECT_NEAR(number_after(r.output, "\nbounding_box_diagonal: "), std::sqrt(3.0), 1e-14) << r.output;
}

TEST_F(CliCheck, DiagonalOfACubeFarFromUnitScaleIsItsOwn) {
  // A cube of side 1e-200 or 1e200: the diagonal's squares under- or overflow a double, and the
  // report printed 0 and inf for diagonals sqrt(3) * side.
  for (const double side : {1e-200, 1e200}) {
    const std::string path = ::testing::TempDir() + "/check_scaled_cube.off";
    {
      std::ofstream out(path);
      out.precision(17);
      out << "OFF\n8 12 0\n";
      for (const std::array<int, 3>& c : std::vector<std::array<int, 3>>{{0, 0, 0},
                                                                         {1, 0, 0},
                                                                         {1, 1, 0},
                                                                         {0, 1, 0},
                                                                         {0, 0, 1},
                                                                         {1, 0, 1},
                                                                         {1, 1, 1},
                                                                         {0, 1, 1}})
        out << c[0] * side << ' ' << c[1] * side << ' ' << c[2] * side << '\n';
      out << "3 0 3 2\n3 0 2 1\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n"
             "3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n";
    }
    const RunResult r = run_cli({"check", path});
    const double diagonal = number_after(r.output, "\nbounding_box_diagonal: ");
    EXPECT_NEAR(diagonal / (std::sqrt(3.0) * side), 1.0, 1e-14) << side << ":\n" << r.output;
    std::remove(path.c_str());
  }
}

TEST_F(CliCheck, TorusHasGenusOne) {
  const RunResult r = run_cli({"check", mesh_path("torus.off")});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("euler_characteristic: 0\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("genus: 1\n"), std::string::npos) << r.output;
}

TEST_F(CliCheck, JsonReportsZeroAreaFace) {
  const RunResult r = run_cli({"check", mesh_path("zero_area_face.off"), "--json"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"zero_area_faces\": [13]"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"vertices\": 9"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("warning: 1 face has (nearly) zero area: 13"), std::string::npos) << r.output;
}

// A face with collinear corners is a zero-area face, not a face that intersects itself: CGAL
// reports it as the pair 13-13, which `check` listed among the self-intersecting pairs (the two
// left are faces that touch along the degenerate face's line: test_self_intersection.cpp).
TEST_F(CliCheck, ZeroAreaFaceIsNoSelfIntersectingPair) {
  const RunResult r = run_cli({"check", mesh_path("zero_area_face.off")});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\nzero_area_faces: 1 (13)\n"
                          "self_intersecting_pairs: 2 (0-1 0-12)\n"
                          "usable: yes\n"),
            std::string::npos)
      << r.output;
  const RunResult j = run_cli({"check", mesh_path("zero_area_face.off"), "--json"});
  EXPECT_NE(j.output.find("\"self_intersecting_pairs\": 2,\n"
                          "  \"self_intersections\": [[0, 1], [0, 12]],\n"),
            std::string::npos)
      << j.output;
}

TEST_F(CliCheck, BadUsageExitsOne) {
  EXPECT_EQ(run_cli({"check"}).exit_code, 1);
  EXPECT_EQ(run_cli({"check", "--no-such-option", mesh_path("cube.off")}).exit_code, 1);
  const RunResult help = run_cli({"check", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("--json"), std::string::npos) << help.output;
}

// An OBJ's errors name the file and the line, with exit 2 (before: "CGAL could not read it").
TEST_F(CliCheck, ObjErrorsNameTheFileAndTheLine) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("shellcontract_check_obj_" + std::to_string(::getpid()) + ".obj")).string();
  std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 9\n";
  const RunResult r = run_cli({"check", path});
  std::filesystem::remove(path);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(path + ": vertex index out of range: face 3 (line 8) refers to vertex 9"), std::string::npos)
      << r.output;
}

struct BadFile {
  const char* file;
  std::vector<std::string> message;  ///< problem name, then where (meshes/README.md, bad/)
};

void PrintTo(const BadFile& b, std::ostream* os) { *os << b.file; }

class CliCheckBad : public ::testing::TestWithParam<BadFile> {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(SHELLCONTRACT_CLI_PATH))
      GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
  }
};

TEST_P(CliCheckBad, ExitsTwoWithMessage) {
  const std::string path = mesh_path(std::string("bad/") + GetParam().file);
  const RunResult r = run_cli({"check", path});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(path), std::string::npos) << "file not named in:\n" << r.output;
  for (const std::string& s : GetParam().message)
    EXPECT_NE(r.output.find(s), std::string::npos) << "missing '" << s << "' in:\n" << r.output;
}

INSTANTIATE_TEST_SUITE_P(
    Files, CliCheckBad,
    ::testing::Values(
        BadFile{"empty.off", {"empty file"}},
        BadFile{"truncated.off", {"truncated file", "face 5 (line 16)"}},
        BadFile{"garbage.off", {"parse error", "line 1"}},
        BadFile{"nan.off", {"non-finite coordinate", "vertex 3 (line 6)"}},
        BadFile{"index_out_of_range.off", {"vertex index out of range", "face 4 (line 15)", "vertex 8"}},
        BadFile{"repeated_vertex.off", {"degenerate face", "face 7 (line 18)"}},
        BadFile{"duplicate_face.off", {"duplicate face", "face 12 (line 23)"}},
        BadFile{"open_sheet.off", {"open boundary", "vertex 0 and vertex 1"}},
        BadFile{"nonmanifold_edge.off", {"non-manifold edge", "edge (0, 1)"}},
        BadFile{"nonmanifold_vertex.off", {"non-manifold vertex", "vertex 0"}},
        BadFile{"inconsistent_orientation.off", {"inconsistent orientation", "face 2 (line 13)"}},
        BadFile{"cube.xyz", {"unknown extension"}},
        BadFile{"missing.off", {"cannot open file"}}));

}  // namespace
