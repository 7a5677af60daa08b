// `shellcontract run --export-every N --export-dir DIR --gltf FILE` as a user runs it: the frames'
// names, the first and last frames, the summary's costs, and a result byte-identical to the run
// without export (exporting only reads positions).
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: temporary files of this process's own

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class CliExport : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_export_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string in() { return std::string(test::MESH_DIR) + "/bumpy_sphere.off"; }
  fs::path dir_;
};

TEST_F(CliExport, FramesAreWrittenAndTheResultIsUnchanged) {
  const auto plain = run_cli({"run", in(), "-o", (dir_ / "plain.off").string(), "-n", "23", "-q"});
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  const auto exported =
      run_cli({"run", in(), "-o", (dir_ / "run.off").string(), "-n", "23", "-q", "--export-every",
               "5", "--export-dir", (dir_ / "frames").string(), "--gltf",
               (dir_ / "run.glb").string(), "--summary", (dir_ / "s.json").string()});
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_EQ(slurp(dir_ / "plain.off"), slurp(dir_ / "run.off"))
      << "exporting changed the simulation";
  // Every 5th frame, the first and the last, zero-padded to the width of the frame count.
  for (const char* name :
       {"run_00.off", "run_05.off", "run_10.off", "run_15.off", "run_20.off", "run_23.off"})
    EXPECT_TRUE(fs::exists(dir_ / "frames" / name)) << name;
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_ / "frames")) ++files;
  EXPECT_EQ(files, 6);
  EXPECT_EQ(slurp(dir_ / "frames" / "run_23.off"), slurp(dir_ / "run.off"))
      << "the last frame is the result";
  EXPECT_NE(slurp(dir_ / "frames" / "run_00.off"), slurp(dir_ / "run.off"));
  EXPECT_GT(fs::file_size(dir_ / "run.glb"), 1000u);
  const std::string summary = slurp(dir_ / "s.json");
  EXPECT_NE(summary.find("\"frames_written\": 6"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"gltf_bytes\""), std::string::npos) << summary;
}

// Without --export-every, --export-dir (like --gltf) keeps about 100 frames: every
// ceil(frames / 100)-th, and the last (run --help, docs/cli.md). Its help said this of --gltf alone.
TEST_F(CliExport, ExportDirAloneKeepsAboutAHundredFrames) {
  const std::string ico = std::string(test::MESH_DIR) + "/ico2.off";
  const auto r = run_cli({"run", ico, "-o", (dir_ / "o.off").string(), "-n", "250", "-q",
                          "--collisions", "off", "--export-dir", (dir_ / "frames").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_ / "frames")) ++files;
  EXPECT_EQ(files, 85);  // 0, 3, ..., 249 and 250
  for (const char* name : {"o_000.off", "o_003.off", "o_249.off", "o_250.off"})
    EXPECT_TRUE(fs::exists(dir_ / "frames" / name)) << name;
  EXPECT_FALSE(fs::exists(dir_ / "frames" / "o_001.off"));
}

TEST_F(CliExport, ExportOptionsAreChecked) {
  const std::string out = (dir_ / "o.off").string();
  EXPECT_EQ(run_cli({"run", in(), "-o", out, "--export-every", "5"}).exit_code, 1);
  EXPECT_EQ(run_cli({"run", in(), "-o", out, "--gltf", (dir_ / "x.gltf").string()}).exit_code, 1);
  EXPECT_EQ(
      run_cli({"run", in(), "-o", out, "--gltf", (dir_ / "x.glb").string(), "--export-every", "0"})
          .exit_code,
      1);
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace shellcontract
