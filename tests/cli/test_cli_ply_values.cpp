// A PLY whose x, y, z are integer-typed, as `run` reads and writes it. Before, '0.5' for an
// `int x` was read as 0.5, and the PLY result kept the file's integer types: every position
// rounded (a unit-size mesh flattened to x = 0) with exit 0, a file `check` then refused.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "mesh/off_scan.hpp"
#include "mesh/ply_reader.hpp"
#include "support/cli_runner.hpp"

namespace {

using shellcontract::test::run_cli;
using shellcontract::test::RunResult;
namespace fs = std::filesystem;

class CliPlyValues : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH))
      GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_ply_values_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name), std::ios::binary) << text;
    return file(name);
  }
  fs::path dir_;
};

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// meshes/octahedron.off at 10 times its size, x and y as `int`, z as `short`, with a colour.
std::string int_octahedron() {
  return "ply\nformat ascii 1.0\nelement vertex 6\nproperty int x\nproperty int y\nproperty short "
         "z\n"
         "property uchar red\nelement face 8\nproperty list uchar int vertex_indices\nend_header\n"
         "10 0 0 1\n-10 0 0 2\n0 10 0 3\n0 -10 0 4\n0 0 10 5\n0 0 -10 6\n"
         "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n";
}

TEST_F(CliPlyValues, AnIntegerTypedPlyResultHoldsTheResultsPositions) {
  const std::string in = write("oct.ply", int_octahedron());
  const RunResult ply = run_cli({"run", in, "-o", file("out.ply"), "-n", "5", "-q"});
  ASSERT_EQ(ply.exit_code, 0) << ply.output;
  const RunResult off = run_cli({"run", in, "-o", file("out.off"), "-n", "5", "-q"});
  ASSERT_EQ(off.exit_code, 0) << off.output;
  const std::string out = read_text(file("out.ply"));
  EXPECT_NE(
      out.find("property double x\nproperty double y\nproperty double z\nproperty uchar red\n"),
      std::string::npos)
      << out;
  // The same positions as the OFF of the same run (both written to read back bitwise), and
  // not integers.
  const shellcontract::PlyData p = shellcontract::read_ply("out.ply", out);
  const shellcontract::OffScan o = shellcontract::scan_off("out.off", read_text(file("out.off")));
  ASSERT_EQ(p.points.size(), 6u);
  ASSERT_EQ(o.points.size(), 6u);
  bool fractional = false;
  for (std::size_t i = 0; i < 6; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(p.points[i][k], o.points[i][k]) << "vertex " << i << " axis " << k;
      fractional |= p.points[i][k] != static_cast<double>(static_cast<long long>(p.points[i][k]));
    }
  EXPECT_TRUE(fractional) << "the run moved no vertex off the lattice";
  const RunResult check = run_cli({"check", file("out.ply")});
  EXPECT_EQ(check.exit_code, 0) << check.output;
}

TEST_F(CliPlyValues, DecimalsInAnIntegerPropertyAreRefusedNamingTheLine) {
  std::string text = int_octahedron();
  text.replace(text.find("10 0 0 1\n"), 9, "9.5 0 0 1\n");
  const std::string in = write("oct.ply", text);
  const RunResult r = run_cli({"run", in, "-o", file("out.ply"), "-n", "2", "-q"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(
      r.output.find(
          in +
          ": parse error: line 11: property 'x' of 'vertex' element 0 is '9.5', not an integer"),
      std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(file("out.ply")));
}

TEST_F(CliPlyValues, AValueTooManyOnAVertexLineIsNamedAtThatLine) {
  std::string text = int_octahedron();
  text.replace(text.find("0 10 0 3\n"), 9, "0 10 0 3 4\n");
  const RunResult r = run_cli({"check", write("oct.ply", text)});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(
                "'vertex' element 2 (line 13) has 5 values, but its header declares 4 properties"),
            std::string::npos)
      << r.output;
}

}  // namespace
