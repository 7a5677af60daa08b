// `run --measure-regions`: alone it selects the regions (--regions auto) to report how far they
// sink, in a run that does not contract them, the baseline of the local contraction's
// measurements (lab/scripts/measure_regions.py); with a region source the regions contract as
// usual. Before, --regions' help said its default became auto only with --aniso, and an --inward
// given beside --measure-regions alone was dropped without a word.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: temporary files of this process's own

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace {

namespace fs = std::filesystem;
using shellcontract::test::RunResult;
using shellcontract::test::run_cli;

class CliMeasureRegions : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_measure_regions_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  /// Runs bumpy_sphere.off for a few frames with `extra`; returns the summary's text.
  std::string run(const std::string& name, const std::vector<std::string>& extra, std::string* output = nullptr) {
    std::vector<std::string> args = {"run", std::string(shellcontract::test::MESH_DIR) + "/bumpy_sphere.off",
                                     "-o", path(name + ".off"), "-n", "8", "--summary", path(name + ".json")};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = run_cli(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    if (output) *output = r.output;
    return slurp(path(name + ".json"));
  }
  static std::string slurp(const std::string& file) {
    std::ifstream f(file, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
  }
  /// The text of a summary's "key": value (up to the next comma or line end).
  static std::string field(const std::string& json, const std::string& key) {
    std::smatch m;
    const std::regex re("\"" + key + "\": ([^\n]*?),?\n");
    return std::regex_search(json, m, re) ? m[1].str() : std::string();
  }
  /// The text with every run of blanks and line breaks as one space (help text wraps anywhere).
  static std::string squeezed(const std::string& text) {
    std::string s;
    for (char c : text)
      if (c != ' ' && c != '\n' && c != '\t') s += c;
      else if (!s.empty() && s.back() != ' ') s += ' ';
    return s;
  }
  fs::path dir_;
};

TEST_F(CliMeasureRegions, AloneItSelectsTheRegionsAndContractsNothing) {
  const std::string control = run("control", {"-q"});
  const std::string measured = run("measured", {"-q", "--measure-regions"});
  const std::string sinks = field(measured, "region_sinks");
  EXPECT_NE(sinks, "") << measured;
  EXPECT_NE(sinks, "[]") << "no region was selected: " << measured;
  EXPECT_EQ(field(control, "region_sinks"), "[]") << control;
  // Nothing contracts the regions: the shape is the control's.
  EXPECT_EQ(field(measured, "final_volume_ratio"), field(control, "final_volume_ratio"));
  EXPECT_EQ(slurp(path("measured.off")), slurp(path("control.off")));
}

TEST_F(CliMeasureRegions, WithARegionSourceTheRegionsContract) {
  const std::string control = run("control", {"-q"});
  const std::string measured = run("measured", {"-q", "--measure-regions", "--regions", "auto"});
  EXPECT_NE(field(measured, "region_sinks"), "[]") << measured;
  EXPECT_NE(field(measured, "final_volume_ratio"), field(control, "final_volume_ratio")) << measured;
}

TEST_F(CliMeasureRegions, AnInwardTermGivenBesideItAloneIsAWarning) {
  std::string output;
  run("measured", {"-q", "--measure-regions", "--inward", "force"}, &output);
  EXPECT_NE(squeezed(output).find("warning: --inward has no effect: --measure-regions without --regions"),
            std::string::npos)
      << output;
}

TEST_F(CliMeasureRegions, TheHelpSaysItSelectsTheRegions) {
  const RunResult r = run_cli({"run", "--help"});
  ASSERT_EQ(r.exit_code, 0);
  const std::string help = squeezed(r.output);
  EXPECT_NE(help.find("default none, auto with --aniso or --measure-regions"), std::string::npos) << help;
  EXPECT_NE(help.find("without --regions, --region-weights, --region-at or --aniso it selects --regions auto and "
                      "contracts nothing"),
            std::string::npos)
      << help;
}

}  // namespace
