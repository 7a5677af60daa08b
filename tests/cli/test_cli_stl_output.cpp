// `run -o X.stl` of a mesh with two vertices at one position (two closed shells touching at a
// point): an STL keeps no vertex identity, and a reader merges equal positions, so the result
// would read back as another mesh (a non-manifold vertex, refused by `check`). Refused before the
// run, with exit code 1, as `repair` refuses such an STL (src/mesh/stl_positions.hpp).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace {

namespace fs = std::filesystem;
using shellcontract::test::run_cli;
using shellcontract::test::RunResult;

/// Two closed tetrahedra, vertex 0 and vertex 4 both at the origin: usable, one shell each.
constexpr const char* TOUCHING =
    "OFF\n8 8 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 0 0\n-1 0 0\n0 -1 0\n0 0 -1\n"
    "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 4 5 6\n3 4 7 5\n3 4 6 7\n3 5 7 6\n";

class CliStlOutput : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH))
      GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_stl_output_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(out("touch.off")) << TOUCHING;
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string out(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(CliStlOutput, RunRefusesAnStlResultWhoseVerticesWouldMerge) {
  ASSERT_EQ(run_cli({"check", out("touch.off")}).exit_code, 0);
  const RunResult r = run_cli({"run", out("touch.off"), "-o", out("t.stl"), "-n", "0", "-q"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("-o " + out("t.stl") +
                          ": an STL keeps no vertex identity, and vertices 0 and 4 "
                          "would both be stored at (0, 0, 0)"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(out("t.stl")));
  // Before the run: no frame is computed (frames of the same format would be refused alike).
  const RunResult frames = run_cli({"run", out("touch.off"), "-o", out("t.stl"), "-n", "5", "-q",
                                    "--export-dir", out("frames"), "--log", out("t.csv")});
  EXPECT_EQ(frames.exit_code, 1) << frames.output;
  EXPECT_NE(frames.output.find("and its frames: an STL keeps no vertex identity"),
            std::string::npos)
      << frames.output;
  EXPECT_FALSE(fs::exists(out("t.csv")));
  EXPECT_TRUE(!fs::exists(out("frames")) || fs::is_empty(out("frames")));
}

// The formats that keep vertex identity take the mesh; the STL was written and `check` refused it.
TEST_F(CliStlOutput, OtherFormatsKeepTheTouchingVertices) {
  for (const char* name : {"t.off", "t.obj", "t.ply"}) {
    const RunResult r = run_cli({"run", out("touch.off"), "-o", out(name), "-n", "0", "-q"});
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.output;
    EXPECT_EQ(run_cli({"check", out(name)}).exit_code, 0) << name;
  }
}

// repair --json prints its report on stdout also when the output is refused after the repair
// (here the STL whose vertices would merge, exit 1): it printed nothing, and a consumer parsing
// stdout read an empty document (review exitcodes F13).
TEST_F(CliStlOutput, RepairJsonReportsAlsoWhenTheOutputIsRefused) {
  const RunResult r = run_cli({"repair", out("touch.off"), "-o", out("t.stl"), "--json"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("an STL keeps no vertex identity"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"usable\": true"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out("t.stl")));
}

}  // namespace
