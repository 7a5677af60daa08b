// `check OUT --against IN` reads a polygon result along the triangles `run` simulated, IN's split
// of each polygon, not along the diagonal OUT's folded shape prefers (review promises F7). The
// files are made here by hand: a pyramid whose base is a quad, and a small tetrahedron inside it
// (a second sheet), with the result's quad folded so far that the reader, left to itself, splits
// it along the other diagonal.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace {

using shellcontract::test::run_cli;
using shellcontract::test::RunResult;
namespace fs = std::filesystem;
using Vertices = std::vector<std::array<double, 3>>;
using Faces = std::vector<std::vector<int>>;

class CliCheckAgainstSplits : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH))
      GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
    dir_ = fs::temp_directory_path() / ("shellcontract_check_splits_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

/// The number printed right after `key`; -1 if absent.
long number_after(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  return at == std::string::npos ? -1 : std::stol(text.substr(at + key.size()));
}

/// The mesh as an OBJ, a PLY or an OFF (by the name's extension), polygons as given.
void write_mesh(const std::string& path, const Vertices& v, const Faces& faces) {
  std::ostringstream o;
  o.precision(17);
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".ply")
    o << "ply\nformat ascii 1.0\nelement vertex " << v.size()
      << "\nproperty double x\nproperty double y\nproperty double z\nelement face " << faces.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  if (ext == ".off") o << "OFF\n" << v.size() << ' ' << faces.size() << " 0\n";
  for (const auto& p : v)
    o << (ext == ".obj" ? "v " : "") << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& f : faces) {
    o << (ext == ".obj" ? "f" : std::to_string(f.size()));
    for (const int i : f) o << ' ' << (ext == ".obj" ? i + 1 : i);
    o << '\n';
  }
  std::ofstream(path) << o.str();
}

// The pyramid: base corners 0 (-1, -1, 0), 1 (1, -1, 0), 2 (1, 1, 0), 3 (-1, 1, 0), the quad
// 0 3 2 1 facing down; apex 4 (0, 0, 1). Read alone, the flat quad is split by the fan from its
// first corner: triangles 0 3 2 (face 0) and 0 2 1 (face 9, after the 9 polygons), along 0-2.
// Vertices 5 to 8: a regular tetrahedron of half-size 0.04 around `centre` (faces 5 to 8).
const Faces FACES = {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4},
                     {5, 6, 7},    {5, 7, 8}, {5, 8, 6}, {6, 8, 7}};

Vertices pyramid(const std::array<double, 3>& corner1, const std::array<double, 3>& centre) {
  Vertices v = {{-1, -1, 0}, corner1, {1, 1, 0}, {-1, 1, 0}, {0, 0, 1}};
  for (const auto& d :
       std::vector<std::array<double, 3>>{{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}})
    v.push_back({centre[0] + 0.04 * d[0], centre[1] + 0.04 * d[1], centre[2] + 0.04 * d[2]});
  return v;
}

// The result: corner 1 folded up about the diagonal 0-2, by about 135 degrees, to F (-0.25, 0.25,
// 0.35), inside the pyramid. The quad's Newell normal is then (0.7, -0.7, -3) (the sum of its
// triangles' doubled vector areas), and the simulated triangle 0 2 F, whose doubled vector area
// is (0.7, -0.7, 1), faces against it: the reader's fan from corner 0 fails, and the fan from
// corner 1 (vertex 3), triangles 3 2 F and 3 F 0, faces along it (dot products 4.99 and 4.99),
// so read alone the quad is split along 3-F. The two splits bound the tetrahedron 0 3 2 F.
const std::array<double, 3> FOLDED = {-0.25, 0.25, 0.35};
// Near the centroid of 3 F 0 (-0.75, 0.083, 0.117), 0.003 above its plane: the small
// tetrahedron straddles that triangle, and is over 0.25 from the simulated 0 2 F's plane, 0.08
// above the base and 0.05 under the side 3 0 4 (z = x + 1), so it crosses only a triangle of the
// split the run never had. The same place in IN, with its flat base, crosses nothing.
const std::array<double, 3> ON_THE_OTHER_SPLIT = {-0.75, 0.08, 0.12};
// The centroid of the simulated triangle 0 2 F: a tetrahedron there crosses it, and its centre is
// 0.28 from the planes of 3 2 F and 3 F 0 (the other split), which it does not reach.
const std::array<double, 3> ON_THE_SIMULATED_SPLIT = {-1.0 / 12, 1.0 / 12, 0.35 / 3};

TEST_F(CliCheckAgainstSplits, AFoldedQuadIsCheckedAlongTheDiagonalTheRunSimulated) {
  for (const std::string ext : {".obj", ".ply"}) {
    SCOPED_TRACE(ext);
    const std::string in = file("in" + ext), out = file("out" + ext);
    write_mesh(in, pyramid({1, -1, 0}, ON_THE_OTHER_SPLIT), FACES);
    write_mesh(out, pyramid(FOLDED, ON_THE_OTHER_SPLIT), FACES);
    // The premise: read alone, OUT is split along 3-F, whose triangle crosses the small
    // tetrahedron (the pairs the old `check --against` counted as new: it read OUT so).
    const RunResult alone = run_cli({"check", out});
    ASSERT_EQ(alone.exit_code, 0) << alone.output;
    ASSERT_GT(number_after(alone.output, "self_intersecting_pairs: "), 0) << alone.output;
    // The simulated triangles written as triangles cross nothing.
    Faces simulated(FACES.begin() + 1, FACES.end());
    simulated.insert(simulated.begin(), {0, 3, 2});
    simulated.push_back({0, 2, 1});
    write_mesh(file("simulated.off"), pyramid(FOLDED, ON_THE_OTHER_SPLIT), simulated);
    const RunResult tris = run_cli({"check", file("simulated.off")});
    ASSERT_EQ(number_after(tris.output, "self_intersecting_pairs: "), 0) << tris.output;

    const RunResult r = run_cli({"check", out, "--against", in});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(number_after(r.output, "self_intersecting_pairs: "), 0) << r.output;
    EXPECT_EQ(number_after(r.output, "new_self_intersecting_pairs: "), 0) << r.output;
    EXPECT_NE(
        r.output.find("warning: " + out +
                      ": 1 polygon with more than 3 vertices was split into 2 triangles (1 as " +
                      in + " splits its polygon of the same index;"),
        std::string::npos)
        << r.output;
  }
}

TEST_F(CliCheckAgainstSplits, AFoldedQuadWhoseSimulatedTriangleCrossesASheetFails) {
  for (const std::string ext : {".obj", ".ply"}) {
    SCOPED_TRACE(ext);
    const std::string in = file("in" + ext), out = file("out" + ext);
    write_mesh(in, pyramid({1, -1, 0}, ON_THE_OTHER_SPLIT), FACES);
    write_mesh(out, pyramid(FOLDED, ON_THE_SIMULATED_SPLIT), FACES);
    // Read alone (split along 3-F) it has no pair: the old `check --against` passed it.
    const RunResult alone = run_cli({"check", out});
    ASSERT_EQ(number_after(alone.output, "self_intersecting_pairs: "), 0) << alone.output;

    const RunResult r = run_cli({"check", out, "--against", in});
    EXPECT_EQ(r.exit_code, 4) << r.output;
    EXPECT_GT(number_after(r.output, "new_self_intersecting_pairs: "), 0) << r.output;
    // Each new pair is the simulated triangle 0 2 F (face 9) and a face of the small tetrahedron.
    const std::size_t listed = r.output.find("new_self_intersecting_pairs: ");
    ASSERT_NE(listed, std::string::npos);
    const std::string line = r.output.substr(listed, r.output.find('\n', listed) - listed);
    EXPECT_NE(line.find("-9"), std::string::npos) << r.output;
  }
}

// A pyramid upside down (apex 4 at 0, the quad 0 1 2 3 at z = 1 facing up), whose result moves
// corner 3 to (1, -1, 0.5), under corner 1. Along the simulated diagonal 0-2 the two cones from
// the apex over 0 1 2 and 0 2 3 have opposite volumes, det(q0, q1, q2) = 4 and
// det(q0, q2, q3) = -4: the mesh encloses no volume and is refused. Read alone, the quad's
// Newell normal (-1, 1, 0) is at right angles to 0 1 2's, so the fan from corner 1 splits it
// (along 1-3), and that mesh has a volume (1/3, inside out, flipped).
TEST_F(CliCheckAgainstSplits,
       WhereTheSimulatedTrianglesMakeNoUsableMeshTheOwnSplitIsCheckedWithAWarning) {
  const Faces faces = {{0, 1, 2, 3}, {1, 0, 4}, {2, 1, 4}, {3, 2, 4}, {0, 3, 4}};
  const std::string in = file("in.obj"), out = file("out.obj");
  write_mesh(in, {{-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}, {0, 0, 0}}, faces);
  write_mesh(out, {{-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {1, -1, 0.5}, {0, 0, 0}}, faces);
  const RunResult r = run_cli({"check", out, "--against", in});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: " + out + ": its polygons split along " + in +
                          "'s triangles (the ones 'run' simulated) do not make a usable mesh (" +
                          out + ": no positive volume:"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("1 by a fan from a corner"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("passes: yes"), std::string::npos) << r.output;
}

// OUT's polygons in another order than IN's: none is IN's polygon of the same index, each is
// split by its own shape (as before), and the warning says so; the faces are still IN's.
TEST_F(CliCheckAgainstSplits, PolygonsThatAreNotTheInputsOfTheSameIndexAreSplitByTheirShape) {
  const Vertices cube = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                         {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const Faces quads = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                       {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  write_mesh(file("in.obj"), cube, quads);
  write_mesh(file("out.obj"), cube, Faces(quads.rbegin(), quads.rend()));
  const RunResult r = run_cli({"check", file("out.obj"), "--against", file("in.obj")});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("(6 by a fan from a corner (6 are not the polygon of the same index in " +
                          file("in.obj") + ");"),
            std::string::npos)
      << r.output;
}

}  // namespace
