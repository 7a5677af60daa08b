// `shellcontract run`'s control of the volume and its checks before work, as a user meets them:
// exit code 5 with the result written, outputs refused before the simulation, option ranges.
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "support/cgal_volume.hpp"
#include "support/child_process.hpp"
#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

class CliRunControl : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_control_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string mesh(const std::string& name) { return std::string(test::MESH_DIR) + "/" + name; }
  std::string out(const std::string& name) { return (dir_ / name).string(); }
  std::string read(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  fs::path dir_;
};

TEST_F(CliRunControl, TargetVolumeIsReachedAndReported) {
  const auto r = run_cli({"run", mesh("ico2.off"), "-o", out("o.off"), "--target-volume", "0.7",
                          "--frames", "60", "--summary", out("s.json"), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The file the user gets, read and measured with CGAL (not the run's own V/V0), against the
  // acceptance's 0.005 written as a number.
  const double written = test::cgal_volume(test::cgal_read(out("o.off"))) /
                         test::cgal_volume(test::cgal_read(mesh("ico2.off")));
  EXPECT_NEAR(written, 0.7, 0.005);
  const std::string s = read(out("s.json"));
  EXPECT_NE(s.find("\"target_reached\": true"), std::string::npos) << s;
  EXPECT_NE(s.find("\"target-volume\": \"0.7\""), std::string::npos) << s;
  // The setup's stages and the peak memory (large-mesh issue, item 1).
  for (const char* key : {"\"read_and_check_seconds\"", "\"read_seconds\"", "\"check_seconds\"",
                          "\"regions_seconds\"", "\"prepare_seconds\"", "\"peak_memory_mb\""})
    EXPECT_NE(s.find(key), std::string::npos) << key;
}

TEST_F(CliRunControl, AZeroFrameRunWritesTheInputBackInItsOwnUnitsAndPlace) {
  // The run normalizes the mesh to a unit bounding-box diagonal and scales it back on output
  // (README "Options by task"). With no step in between, the output must be the input to
  // rounding, vertex for vertex, however large and far from the origin the mesh is: a wrong
  // scale, centre or vertex order shows at once. ico2 scaled by 37.25 and moved to
  // (1000.5, -250.25, 3): the rounding is a few ulps of the largest coordinate.
  const Mesh ico2 = test::cgal_read(mesh("ico2.off"));
  Mesh moved = ico2;
  for (const VertexIndex v : moved.vertices()) {
    const Point3& p = moved.point(v);
    moved.point(v) = Point3(37.25 * p.x() + 1000.5, 37.25 * p.y() - 250.25, 37.25 * p.z() + 3.0);
  }
  ASSERT_TRUE(CGAL::IO::write_polygon_mesh(out("in.off"), moved, CGAL::parameters::stream_precision(17)));
  const auto r = run_cli({"run", out("in.off"), "-o", out("o.off"), "--frames", "0", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Mesh input = test::cgal_read(out("in.off"));
  const Mesh written = test::cgal_read(out("o.off"));
  ASSERT_EQ(written.number_of_vertices(), input.number_of_vertices());
  ASSERT_EQ(written.number_of_faces(), input.number_of_faces());
  const double tol = 8.0 * 1040.0 * std::numeric_limits<double>::epsilon();
  double worst = 0.0;
  for (const VertexIndex v : input.vertices()) {
    const Point3& a = input.point(v);
    const Point3& b = written.point(v);
    worst = std::max({worst, std::abs(a.x() - b.x()), std::abs(a.y() - b.y()), std::abs(a.z() - b.z())});
  }
  EXPECT_LE(worst, tol) << "the 0-frame output is not the input";
  // The same faces in the same order, each up to a rotation of its corners.
  const auto corners = [](const Mesh& m, FaceIndex f) {
    std::array<std::size_t, 3> c{};
    int k = 0;
    for (const VertexIndex v : m.vertices_around_face(m.halfedge(f))) c[static_cast<std::size_t>(k++)] = v.idx();
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    return c;
  };
  for (const FaceIndex f : input.faces())
    EXPECT_EQ(corners(input, f), corners(written, f)) << "face " << f.idx();
}

TEST_F(CliRunControl, PeakMemoryIsTheToolsOwnNotItsParents) {
  // A caller holding 400 MB (a script, this test) forks and starts the tool on a small mesh, as
  // Python's subprocess does. The summary's peak must be the tool's: getrusage's maximum
  // resident size carries the forked copy's peak across exec and read 400 MB or more here.
  // (run_cli's popen spawns without copying the caller's memory; test::Child forks.)
  const std::size_t held = std::size_t{400} << 20;
  std::vector<char> ballast(held, 1);
  test::ChildSpec spec = test::cli_child({"run", mesh("ico2.off"), "-o", out("o.off"), "--frames",
                                          "1", "--summary", out("s.json"), "-q"});
  spec.out = test::ChildOut::Inherit;
  spec.err = test::ChildErr::Inherit;
  test::Child run(spec);
  ASSERT_GE(run.pid(), 0);
  const int status = run.finish();
  ASSERT_TRUE(run.reaped());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  const std::string s = read(out("s.json"));
  const std::size_t at = s.find("\"peak_memory_mb\": ");
  ASSERT_NE(at, std::string::npos) << s;
  const double mb = std::stod(s.substr(at + 18));
  EXPECT_GT(mb, 0.0);
  EXPECT_LT(mb, 200.0) << "the caller held " << (held >> 20) << " MB; ballast "
                       << static_cast<int>(ballast[held / 2]);
}

TEST_F(CliRunControl, TheSummaryNamesTheContactDistanceUsed) {
  // --delta auto keeps the default on ico2, whose edges are long (the share of the edge is
  // checked in tests/sim/test_contact_distance.cpp); a number is used as given; no collisions,
  // no contact distance.
  const auto contact_distance = [&](std::vector<std::string> options) {
    std::vector<std::string> args = {"run", mesh("ico2.off"), "-o", out("o.off"), "--frames", "1",
                                     "--summary", out("s.json"), "-q"};
    args.insert(args.end(), options.begin(), options.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const std::string s = read(out("s.json"));
    const std::size_t at = s.find("\"contact_distance\": ");
    EXPECT_NE(at, std::string::npos) << s;
    return std::make_pair(at == std::string::npos ? -1.0 : std::stod(s.substr(at + 20)),
                          s.find("\"delta\": \"auto\"") != std::string::npos);
  };
  EXPECT_EQ(contact_distance({"--delta", "auto"}), std::make_pair(1e-4, true));
  EXPECT_EQ(contact_distance({"--delta", "5e-5"}), std::make_pair(5e-5, false));
  EXPECT_EQ(contact_distance({"--collisions", "off"}), std::make_pair(0.0, false));
}

TEST_F(CliRunControl, NewSelfIntersectionsFoundByValidationExitWith4) {
  // README, exit code 4: "--validate found self-intersections that the input did not have".
  // bumpy_sphere under a constant pressure (no air) buckles and its sides meet; without
  // collision handling they pass through each other. The written result is checked with CGAL
  // here, independently of the run's own validation: it intersects itself, the input does not.
  // (two_sheet does not serve: its flat sheets pass through each other whole and the result,
  // inside out, does not intersect itself.)
  const std::vector<std::string> args = {"run", mesh("bumpy_sphere.off"), "--air-balance", "0",
                                         "-p", "4", "--frames", "100", "--validate", "end"};
  std::vector<std::string> off = args;
  off.insert(off.end(), {"-o", out("o.off"), "--collisions", "off", "--summary", out("s.json")});
  const auto r = run_cli(off);
  EXPECT_EQ(r.exit_code, 4) << r.output;
  EXPECT_NE(r.output.find("new self-intersections"), std::string::npos) << r.output;
  EXPECT_NE(read(out("s.json")).find("\"exit_code\": 4"), std::string::npos) << read(out("s.json"));
  ASSERT_TRUE(fs::exists(out("o.off")));
  EXPECT_FALSE(CGAL::Polygon_mesh_processing::does_self_intersect(test::cgal_read(mesh("bumpy_sphere.off"))));
  EXPECT_TRUE(CGAL::Polygon_mesh_processing::does_self_intersect(test::cgal_read(out("o.off"))));
  // The same run with collisions on keeps the sides apart and exits 0.
  std::vector<std::string> on = args;
  on.insert(on.end(), {"-o", out("held.off"), "-q"});
  const auto held = run_cli(on);
  EXPECT_EQ(held.exit_code, 0) << held.output;
  EXPECT_FALSE(CGAL::Polygon_mesh_processing::does_self_intersect(test::cgal_read(out("held.off"))));
}

TEST_F(CliRunControl, AStalledTargetExitsWith5AndWritesTheResult) {
  // No pressure and no bending: nothing moves the volume toward the stop ratio.
  const auto r =
      run_cli({"run", mesh("ico2.off"), "-o", out("o.off"), "--stop-volume-ratio", "0.5", "-p", "0",
               "--bending", "none", "--frames", "500", "--summary", out("s.json")});
  EXPECT_EQ(r.exit_code, 5) << r.output;
  EXPECT_NE(r.output.find("not reached"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(out("o.off")));
  EXPECT_NE(read(out("s.json")).find("\"target_reached\": false"), std::string::npos);
}

TEST_F(CliRunControl, ASmallTargetIsHeldToAShareOfItselfNotTo0005) {
  // ico1 driven to V/V0 0.001 in 6 frames collapses to far less. Within 0.005 of the target,
  // the absolute tolerance alone reported it reached with exit 0; the acceptance is
  // min(0.005, 5 % of R) (docs/math/volume-control.md), so it is exit 5, and says by how much.
  const auto r = run_cli({"run", mesh("ico1.off"), "-o", out("o.off"), "--target-volume", "0.001",
                          "-n", "6", "--summary", out("s.json")});
  EXPECT_EQ(r.exit_code, 5) << r.output;
  EXPECT_NE(r.output.find("target volume 0.001 not reached"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("times smaller than the target"), std::string::npos) << r.output;
  EXPECT_NE(read(out("s.json")).find("\"target_reached\": false"), std::string::npos);
  // The written file, measured with CGAL: the collapse that the old acceptance took as reached.
  ASSERT_TRUE(fs::exists(out("o.off")));
  const double written = test::cgal_volume(test::cgal_read(out("o.off"))) /
                         test::cgal_volume(test::cgal_read(mesh("ico1.off")));
  EXPECT_LT(std::abs(written - 0.001), 0.005);
  EXPECT_LT(written, 0.0005);
  // A small target the shell does reach still counts: ico2 at 0.05, within 5 % of it.
  const auto held = run_cli({"run", mesh("ico2.off"), "-o", out("held.off"), "--target-volume",
                             "0.05", "-q"});
  EXPECT_EQ(held.exit_code, 0) << held.output;
  const double held_ratio = test::cgal_volume(test::cgal_read(out("held.off"))) /
                            test::cgal_volume(test::cgal_read(mesh("ico2.off")));
  EXPECT_NEAR(held_ratio, 0.05, 0.0025);
}

TEST_F(CliRunControl, OutputsAreCheckedBeforeTheSimulation) {
  const std::string in = mesh("ico2.off");
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  const std::vector<Case> cases = {
      {{"-o", out("missing/o.off")}, "does not exist"},
      {{"-o", out("o.off"), "--summary", out("o.off")}, "is also the file of -o"},
      {{"-o", out("o.off"), "--log", out("./o.off")}, "is also the file of -o"},
      {{"-o", in}, "is the input file"},
      {{"-o", out("o.xyz")}, "unknown mesh format"},
      {{"-o", out("o")}, "no file extension to name the mesh format"},
      {{"-o", out("o.off"), "--summary", dir_.string()}, "is a folder"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = {"run", in, "--frames", "1000000"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
  }
  EXPECT_TRUE(fs::is_empty(dir_)) << "no output written";
}

TEST_F(CliRunControl, OutOfRangeOptionsAreRefusedWithTheirName) {
  for (const auto& [name, value] :
       std::vector<std::pair<std::string, std::string>>{{"--mu", "nan"},
                                                        {"--density", "inf"},
                                                        {"--fiber-target", "2"},
                                                        {"--iterations", "1000000000"},
                                                        {"--target-volume", "1.5"},
                                                        {"--mu", "-1"}}) {
    const auto r = run_cli({"run", mesh("ico2.off"), "-o", out("o.off"), name, value});
    EXPECT_EQ(r.exit_code, 1) << name << " " << value << ": " << r.output;
    EXPECT_NE(r.output.find(name), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(out("o.off")));
}

TEST_F(CliRunControl, HelpShowsCleanDefaults) {
  const auto r = run_cli({"run", "--help"});
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("(=0.3)"), std::string::npos) << "--poisson's default";
  EXPECT_EQ(r.output.find("99999"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("00001"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace shellcontract
