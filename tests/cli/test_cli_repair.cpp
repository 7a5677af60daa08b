// `shellcontract repair` and `run --repair` as a user runs them (README, Exit codes): what is
// written, what is refused, and that a usable mesh runs exactly as without --repair.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/cli_runner.hpp"
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

TEST_F(CliRepair, OpenCubeIsRepairedWrittenAndThenUsable) {
  const std::string in = write("open_cube.off", OPEN_CUBE);
  const std::string o = out("closed.off");
  ASSERT_EQ(run_cli({"check", in}).exit_code, 2);
  const RunResult r = run_cli({"repair", in, "-o", o});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("1 holes filled"), std::string::npos) << r.output;
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

TEST_F(CliRepair, RunRepairRunsAnOpenMesh) {
  const std::string in = write("open_cube.off", OPEN_CUBE);
  EXPECT_EQ(run_cli({"run", in, "-o", out("a.off"), "--frames", "3", "-q"}).exit_code, 2);
  const RunResult r = run_cli({"run", in, "-o", out("b.off"), "--frames", "3", "-q", "--repair"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("holes filled"), std::string::npos) << r.output;
  EXPECT_EQ(run_cli({"check", out("b.off")}).exit_code, 0);
}

TEST_F(CliRepair, RunRepairLeavesAUsableMeshsRunUnchanged) {
  const std::string in = mesh_path("bumpy_sphere.off");
  ASSERT_EQ(run_cli({"run", in, "-o", out("plain.off"), "--frames", "5", "-q"}).exit_code, 0);
  ASSERT_EQ(run_cli({"run", in, "-o", out("repair.off"), "--frames", "5", "-q", "--repair"}).exit_code, 0);
  EXPECT_EQ(slurp(out("plain.off")), slurp(out("repair.off")));
}

}  // namespace
