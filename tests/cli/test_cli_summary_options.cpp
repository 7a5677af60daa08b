// The summary's `options` record the values the run used, in a form its options take back
// (review6 F7): a ramp longer than half the frames is recorded as the run shortened it (was the
// option's 100 while 15 ran), and the regions that --region-at or --region-weights make are
// recorded under those options alone (`regions` was "auto" or "weights", which a rerun beside
// them refuses). A rerun with the recorded values gives the same result, to the byte.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "support/summary_text.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

using test::file_text;
using test::summary_option;

class SummaryOptions : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_summary_options_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  /// Runs ico2 with `extra`, writing `name`.off and `name`.json; the exit code.
  int run(const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args{"run",
                                  std::string(test::MESH_DIR) + "/ico2.off",
                                  "-o",
                                  (dir_ / (name + ".off")).string(),
                                  "-q",
                                  "--summary",
                                  (dir_ / (name + ".json")).string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return r.exit_code;
  }
  fs::path dir_;
};

TEST_F(SummaryOptions, TheRampIsRecordedAsTheRunShortenedIt) {
  ASSERT_EQ(run("a", {"-n", "30", "--target-volume", "0.6"}), 0);
  const std::string ramp = summary_option(dir_ / "a.json", "target-ramp");
  EXPECT_EQ(ramp, "15") << "half of the 30 frames, as the run used it";
  // Rerun with the recorded value: the same run.
  ASSERT_EQ(run("b", {"-n", "30", "--target-volume", "0.6", "--target-ramp", ramp}), 0);
  EXPECT_EQ(file_text(dir_ / "a.off"), file_text(dir_ / "b.off"));
  // A ramp within the frames is recorded as given.
  ASSERT_EQ(run("c", {"-n", "30", "--target-volume", "0.6", "--target-ramp", "10"}), 0);
  EXPECT_EQ(summary_option(dir_ / "c.json", "target-ramp"), "10");
}

TEST_F(SummaryOptions, RegionsAtPointsOrFromWeightsAreRecordedUnderTheirOwnOptions) {
  ASSERT_EQ(run("at", {"-n", "2", "--region-at", "1,0,0"}), 0);
  EXPECT_EQ(summary_option(dir_ / "at.json", "region-at"), "1,0,0");
  EXPECT_EQ(summary_option(dir_ / "at.json", "regions"), "")
      << "--regions beside --region-at is refused: not given";
  {
    std::ofstream w(dir_ / "w.txt");
    for (int i = 0; i < 162; ++i) w << (i < 20 ? "1\n" : "0\n");  // ico2: 162 vertices
  }
  ASSERT_EQ(run("w", {"-n", "2", "--region-weights", (dir_ / "w.txt").string()}), 0);
  EXPECT_EQ(summary_option(dir_ / "w.json", "region-weights"), (dir_ / "w.txt").string());
  EXPECT_EQ(summary_option(dir_ / "w.json", "regions"), "");
  // Other region sources are recorded as before.
  ASSERT_EQ(run("auto", {"-n", "2", "--aniso", "arap"}), 0);
  EXPECT_EQ(summary_option(dir_ / "auto.json", "regions"), "auto");
  ASSERT_EQ(run("none", {"-n", "2"}), 0);
  EXPECT_EQ(summary_option(dir_ / "none.json", "regions"), "none");
}

}  // namespace
}  // namespace shellcontract
