// `shellcontract check OUT --against IN` and `--fail-on-self-intersections`: a result
// can fail. The intersecting meshes are made here by moving vertices of a clean mesh through the
// far side (so that the input has no pair and the result has some), and by a real run without
// collisions; the counts are compared with plain `check`'s own count of the same file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace {

using shellcontract::test::RunResult;
using shellcontract::test::run_cli;
namespace fs = std::filesystem;

class CliCheckAgainst : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
    dir_ = fs::temp_directory_path() / ("shellcontract_check_against_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

std::string mesh_path(const std::string& name) { return std::string(shellcontract::test::MESH_DIR) + "/" + name; }

/// The number printed right after `key`; -1 if absent.
long number_after(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  return at == std::string::npos ? -1 : std::stol(text.substr(at + key.size()));
}

/// An OFF file's tokens, without the keyword and the comments (meshes/ has "# ..." lines).
std::istringstream off_tokens(const std::string& path) {
  std::ifstream f(path);
  std::string text;
  for (std::string line; std::getline(f, line);) {
    line = line.substr(0, line.find('#'));
    if (line.find_first_not_of(" \t\r") == std::string::npos || line.rfind("OFF", 0) == 0) continue;
    text += line + '\n';
  }
  return std::istringstream(text);
}

/// An OFF file like `in` with vertices `moved` pushed to -1.6 times their position: through the
/// far side of a sphere centred at 0.
void write_poked(const std::string& in, const std::string& out, const std::vector<int>& moved) {
  std::istringstream f = off_tokens(in);
  std::size_t nv = 0, nf = 0, ne = 0;
  f >> nv >> nf >> ne;
  ASSERT_GT(nv, 0u);
  std::vector<std::array<double, 3>> x(nv);
  for (auto& p : x) f >> p[0] >> p[1] >> p[2];
  std::ostringstream o;
  o.precision(17);
  o << "OFF\n" << nv << ' ' << nf << " 0\n";
  for (const int i : moved)
    for (double& c : x.at(static_cast<std::size_t>(i))) c *= -1.6;
  for (const auto& p : x) o << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (std::string line; std::getline(f, line);)
    if (!line.empty()) o << line << '\n';
  std::ofstream(out) << o.str();
}

TEST_F(CliCheckAgainst, AResultWithNewIntersectionsExitsFourAndCountsThem) {
  const std::string in = mesh_path("ico2.off"), out = file("poked.off");
  write_poked(in, out, {0});
  const RunResult plain = run_cli({"check", out});
  ASSERT_EQ(plain.exit_code, 0) << plain.output;  // usable as an input: intersections are only reported
  const long pairs = number_after(plain.output, "self_intersecting_pairs: ");
  ASSERT_GT(pairs, 0) << plain.output;  // the poke made some (else the test proves nothing)

  const RunResult r = run_cli({"check", out, "--against", in});
  EXPECT_EQ(r.exit_code, 4) << r.output;
  EXPECT_EQ(number_after(r.output, "input_self_intersecting_pairs: "), 0) << r.output;
  EXPECT_EQ(number_after(r.output, "new_self_intersecting_pairs: "), pairs) << r.output;
  EXPECT_NE(r.output.find("passes: no"), std::string::npos) << r.output;

  const RunResult j = run_cli({"check", out, "--against", in, "--json"});
  EXPECT_EQ(j.exit_code, 4) << j.output;
  EXPECT_EQ(number_after(j.output, "\"new_self_intersecting_pairs\": "), pairs) << j.output;
  EXPECT_NE(j.output.find("\"passes\": false"), std::string::npos) << j.output;
}

TEST_F(CliCheckAgainst, IntersectionsTheInputAlreadyHadAreNotBlamed) {
  const std::string poked = file("poked.off"), more = file("more.off");
  write_poked(mesh_path("ico2.off"), poked, {0});
  // The same poke, and a second one elsewhere: only the second's pairs are new.
  write_poked(mesh_path("ico2.off"), more, {0, 100});
  const long before = number_after(run_cli({"check", poked}).output, "self_intersecting_pairs: ");
  const long after = number_after(run_cli({"check", more}).output, "self_intersecting_pairs: ");
  ASSERT_GT(after, before);

  const RunResult same = run_cli({"check", poked, "--against", poked});
  EXPECT_EQ(same.exit_code, 0) << same.output;
  EXPECT_EQ(number_after(same.output, "new_self_intersecting_pairs: "), 0) << same.output;
  EXPECT_NE(same.output.find("passes: yes"), std::string::npos) << same.output;

  const RunResult r = run_cli({"check", more, "--against", poked});
  EXPECT_EQ(r.exit_code, 4) << r.output;
  const long fresh = number_after(r.output, "new_self_intersecting_pairs: ");
  EXPECT_GT(fresh, 0) << r.output;
  EXPECT_LE(fresh, after) << r.output;
  EXPECT_EQ(number_after(r.output, "input_self_intersecting_pairs: "), before) << r.output;
}

TEST_F(CliCheckAgainst, FailOnSelfIntersectionsFailsAnyMeshThatHasThem) {
  const std::string poked = file("poked.off");
  write_poked(mesh_path("ico2.off"), poked, {0});
  const RunResult bad = run_cli({"check", poked, "--fail-on-self-intersections"});
  EXPECT_EQ(bad.exit_code, 4) << bad.output;
  EXPECT_NE(bad.output.find("passes: no"), std::string::npos) << bad.output;
  const RunResult clean = run_cli({"check", mesh_path("ico2.off"), "--fail-on-self-intersections"});
  EXPECT_EQ(clean.exit_code, 0) << clean.output;
  EXPECT_NE(clean.output.find("passes: yes"), std::string::npos) << clean.output;
}

TEST_F(CliCheckAgainst, ARunWithoutCollisionsIsCaughtAndACleanRunPasses) {
  // The bumpy sphere squeezed to 30 % of its volume: its bumps fold into each other without
  // collisions; with them they do not.
  const std::string in = mesh_path("bumpy_sphere.off"), off = file("off.off"), on = file("on.off");
  const std::vector<std::string> squeeze = {"--target-volume", "0.3", "--frames", "100", "-q"};
  std::vector<std::string> a1 = {"run", in, "-o", off, "--collisions", "off"};
  a1.insert(a1.end(), squeeze.begin(), squeeze.end());
  const RunResult r1 = run_cli(a1);
  ASSERT_TRUE(fs::exists(off)) << r1.output;
  const long pairs = number_after(run_cli({"check", off}).output, "self_intersecting_pairs: ");
  ASSERT_GT(pairs, 0) << "the run without collisions made no intersection; choose a harder case\n" << r1.output;
  const RunResult c1 = run_cli({"check", off, "--against", in});
  EXPECT_EQ(c1.exit_code, 4) << c1.output;
  EXPECT_EQ(number_after(c1.output, "new_self_intersecting_pairs: "), pairs) << c1.output;

  std::vector<std::string> a2 = {"run", in, "-o", on};
  a2.insert(a2.end(), squeeze.begin(), squeeze.end());
  const RunResult r2 = run_cli(a2);
  ASSERT_TRUE(fs::exists(on)) << r2.output;
  const RunResult c2 = run_cli({"check", on, "--against", in});
  EXPECT_EQ(c2.exit_code, 0) << c2.output;
  EXPECT_EQ(number_after(c2.output, "new_self_intersecting_pairs: "), 0) << c2.output;
}

TEST_F(CliCheckAgainst, QuadsSplitAlongTheOtherDiagonalAreTheSameQuads) {
  // cube_quads.off against itself with each quad's corners rotated by one: read alone,
  // read_input_mesh splits every quad along the other diagonal; --against splits each as the
  // input's quad (the same cycle from another corner: test_cli_check_against_splits.cpp), and
  // nothing is new (no pair at all here; the face lookup works through the polygons).
  std::istringstream f = off_tokens(mesh_path("cube_quads.off"));
  std::ostringstream rotated;
  std::size_t nv = 0, nf = 0, ne = 0;
  f >> nv >> nf >> ne;
  ASSERT_EQ(nf, 6u);
  rotated << "OFF\n" << nv << ' ' << nf << " 0\n";
  for (std::size_t i = 0; i < nv; ++i) {
    double a, b, c;
    f >> a >> b >> c;
    rotated << a << ' ' << b << ' ' << c << '\n';
  }
  for (std::size_t i = 0; i < nf; ++i) {
    int n, v0, v1, v2, v3;
    f >> n >> v0 >> v1 >> v2 >> v3;
    rotated << "4 " << v1 << ' ' << v2 << ' ' << v3 << ' ' << v0 << '\n';
  }
  std::ofstream(file("rotated.off")) << rotated.str();
  const RunResult r = run_cli({"check", file("rotated.off"), "--against", mesh_path("cube_quads.off")});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(number_after(r.output, "new_self_intersecting_pairs: "), 0) << r.output;
}

// Two files are read: a warning says which one it is about (before, the result's polygon warning
// came without a file name, and the input's was not printed at all).
TEST_F(CliCheckAgainst, EachWarningNamesItsFile) {
  const std::string in = mesh_path("cube_quads.off"), out = file("copy.off");
  fs::copy_file(in, out);
  const RunResult r = run_cli({"check", out, "--against", in});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // OUT's polygons are split as IN's (the triangles `run` simulated:
  // test_cli_check_against_splits.cpp).
  EXPECT_NE(
      r.output.find("warning: " + out +
                    ": 6 polygons with more than 3 vertices were split into 12 triangles (6 as " +
                    in + " splits its polygon of the same index;"),
      std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("warning: " + in + ": 6 polygons with more than 3 vertices were split into 12 triangles (6 by a fan from a corner;"),
            std::string::npos) << r.output;
  const RunResult j = run_cli({"check", out, "--against", in, "--json"});
  EXPECT_EQ(j.exit_code, 0) << j.output;
  EXPECT_NE(j.output.find("\"against_warnings\": [\"6 polygons"), std::string::npos) << j.output;
  // One file: the warning as before ("file:" on stdout names it).
  const RunResult one = run_cli({"check", out});
  EXPECT_NE(one.output.find("warning: 6 polygons"), std::string::npos) << one.output;
}

TEST_F(CliCheckAgainst, MeshesThatAreNotTheSameAreBadUsage) {
  const RunResult r = run_cli({"check", mesh_path("ico2.off"), "--against", mesh_path("ico1.off")});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("is not a result of"), std::string::npos) << r.output;
  // --json prints its object here too (before, only the message on stderr).
  const RunResult j = run_cli({"check", mesh_path("ico2.off"), "--against", mesh_path("ico1.off"), "--json"});
  EXPECT_EQ(j.exit_code, 1) << j.output;
  EXPECT_NE(j.output.find("\"error\": \""), std::string::npos) << j.output;
  const RunResult missing = run_cli({"check", mesh_path("ico2.off"), "--against", file("nothing.off"), "--json"});
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("nothing.off"), std::string::npos) << missing.output;
}

}  // namespace

namespace {

// A run's --gltf animation read as a mesh is its base shape, the run's input: `check RUN.glb
// --against IN` judged the input against itself and passed without a word. The reader says so,
// with where the end state is.
TEST_F(CliCheckAgainst, AnAnimationIsNamedAsItsBaseShape) {
  const RunResult made = run_cli({"run", mesh_path("ico2.off"), "-o", file("r.off"), "-n", "3",
                                  "--gltf", file("r.glb"), "-q"});
  ASSERT_EQ(made.exit_code, 0) << made.output;
  const RunResult checked = run_cli({"check", file("r.glb"), "--against", mesh_path("ico2.off")});
  EXPECT_EQ(checked.exit_code, 0) << checked.output;
  EXPECT_NE(checked.output.find("note: " + file("r.glb") +
                                ": the file's morph targets (an animation, on 1 primitive) are "
                                "not applied: the mesh read is its base shape"),
            std::string::npos)
      << checked.output;
  // A glTF without morph targets has no such note (CliGltf.CheckAndRunReadAGlbAndAGltf).
}

}  // namespace
