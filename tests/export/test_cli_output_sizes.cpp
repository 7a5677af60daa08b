// The sizes of a run's large outputs, before the run (cli/output_sizes.hpp), through limited_cli:
// the tool with the largest .glb and the size warned of lowered (no test writes 4 GiB). A --gltf
// whose bound is over the limit is refused before the run (exit 1, naming the bound and the
// --export-every that fits); one at the limit runs; outputs over the warned size get one line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::run_cli;
using test::run_command;

test::RunResult run_limited(std::uint64_t glb_max, std::uint64_t big,
                            const std::vector<std::string>& args) {
  std::string cmd =
      quoted(SHELLCONTRACT_LIMITED_CLI) + " " + std::to_string(glb_max) + " " + std::to_string(big);
  for (const std::string& a : args) cmd += " " + quoted(a);
  return run_command(cmd + " 2>&1");
}

class CliOutputSizes : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_LIMITED_CLI))
      GTEST_SKIP() << SHELLCONTRACT_LIMITED_CLI << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_output_sizes_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  /// A run of an icosphere of 10,242 vertices (its frames, not the JSON, make most of the .glb,
  /// as on the meshes that come near the limit), 12 frames kept.
  std::vector<std::string> run_args(const std::string& name) {
    const fs::path mesh = dir_ / "ico5.off";
    if (!fs::exists(mesh)) {
      const test::TriMesh s = test::icosphere(5, 0.5);
      std::ofstream out(mesh);
      out << std::setprecision(17) << "OFF\n" << s.x.rows() << ' ' << s.faces.rows() << " 0\n";
      for (Eigen::Index i = 0; i < s.x.rows(); ++i)
        out << s.x(i, 0) << ' ' << s.x(i, 1) << ' ' << s.x(i, 2) << '\n';
      for (Eigen::Index f = 0; f < s.faces.rows(); ++f)
        out << "3 " << s.faces(f, 0) << ' ' << s.faces(f, 1) << ' ' << s.faces(f, 2) << '\n';
    }
    return {"run",
            mesh.string(),
            "-o",
            (dir_ / (name + ".off")).string(),
            "-n",
            "11",
            "--export-every",
            "1",
            "-q",
            "--collisions",
            "off",
            "--gltf",
            (dir_ / (name + ".glb")).string()};
  }
  fs::path dir_;
};

TEST_F(CliOutputSizes, AGltfOverTheLimitIsRefusedBeforeTheRunAndOneAtItRuns) {
  const auto plain = run_cli(run_args("plain"));
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  const std::uint64_t real = fs::file_size(dir_ / "plain.glb");
  // A limit one byte below the real file: the bound (an upper bound) is over it.
  const auto refused = run_limited(real - 1, 0, run_args("over"));
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_NE(refused.output.find("--gltf"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("12 kept frames of 10242 vertices"), std::string::npos)
      << refused.output;
  EXPECT_NE(refused.output.find("--export-every "), std::string::npos) << refused.output;
  EXPECT_FALSE(fs::exists(dir_ / "over.off")) << "the run ran before the refusal";
  EXPECT_FALSE(fs::exists(dir_ / "over.glb"));
  // The bound is close: a limit 2 % above the real file takes it.
  const auto fits = run_limited(real + real / 50, 0, run_args("fits"));
  EXPECT_EQ(fits.exit_code, 0) << fits.output;
  EXPECT_EQ(fs::file_size(dir_ / "fits.glb"), real);
}

TEST_F(CliOutputSizes, TheRefusalNamesAnEveryThatFits) {
  const auto plain = run_cli(run_args("plain"));
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  const std::uint64_t real = fs::file_size(dir_ / "plain.glb");
  const auto refused = run_limited(real * 2 / 3, 0, run_args("over"));
  ASSERT_EQ(refused.exit_code, 1) << refused.output;
  const std::size_t at = refused.output.find("--export-every ");
  ASSERT_NE(at, std::string::npos) << refused.output;
  const std::string every = std::to_string(std::stoi(refused.output.substr(at + 15)));
  std::vector<std::string> args = run_args("named");
  args[7] = every;  // --export-every N as the message says
  const auto named = run_limited(real * 2 / 3, 0, args);
  EXPECT_EQ(named.exit_code, 0) << "--export-every " << every << ": " << named.output;
}

TEST_F(CliOutputSizes, OutputsOverTheWarnedSizeGetAWarningBeforeTheRun) {
  std::vector<std::string> args = run_args("big");
  args.insert(args.end(), {"--export-dir", (dir_ / "frames").string()});
  const auto warned = run_limited(0, 1000, args);
  EXPECT_EQ(warned.exit_code, 0) << warned.output;
  EXPECT_NE(warned.output.find("warning: the outputs will take up to about"), std::string::npos)
      << warned.output;
  EXPECT_NE(warned.output.find("--export-dir"), std::string::npos) << warned.output;
  // Below the size (the tool's 1 GiB): no such line.
  const auto quiet = run_cli(run_args("small"));
  EXPECT_EQ(quiet.exit_code, 0) << quiet.output;
  EXPECT_EQ(quiet.output.find("warning: the outputs"), std::string::npos) << quiet.output;
}

}  // namespace
}  // namespace shellcontract
