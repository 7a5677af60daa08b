// The summary's `options` record the values the run used, in a form its options take back
// (review6 F7): a ramp longer than half the frames is recorded as the run shortened it (was the
// option's 100 while 15 ran), and the regions that --region-at or --region-weights make are
// recorded under those options alone (`regions` was "auto" or "weights", which a rerun beside
// them refuses). A rerun with the recorded values gives the same result, to the byte. The options
// without effect in the run are recorded empty: a rerun leaves them out.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <string>
#include <utility>
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

/// The summary's options, key and text, in the file's order (each is a string there).
std::vector<std::pair<std::string, std::string>> summary_options(const fs::path& summary) {
  const std::string text = file_text(summary);
  const std::size_t begin = text.find("\"options\": {");
  const std::size_t end = text.find('}', begin);
  std::vector<std::pair<std::string, std::string>> options;
  if (begin == std::string::npos || end == std::string::npos) return options;
  const std::regex entry("\"([a-z0-9-]+)\": \"([^\"]*)\"");
  const std::string body = text.substr(begin, end - begin);
  for (std::sregex_iterator i(body.begin(), body.end(), entry), last; i != last; ++i)
    options.emplace_back((*i)[1], (*i)[2]);
  return options;
}

// Before: the summary recorded every option with its table value, also those the run ignored
// (--mu-a without --aniso, --k-a, the dimple and the shrink without regions, a ramp with no
// target, --delta with --collisions off, --poisson without --young), so a reader could not tell
// which numbers shaped the run. Now empty, by the rules of the "has no effect" warnings: each
// option recorded empty, given, is such a warning, and the other recorded options rerun the run.
TEST_F(SummaryOptions, OptionsWithoutEffectAreRecordedEmptyAndTheOthersRerunTheRun) {
  // Each of these has no effect here (no regions, no aniso, unit masses, no collisions, StVK).
  const std::vector<std::string> ignored{"--mu-a",          "3",     "--fiber-target",     "0.5",
                                         "--k-a",           "0.3",   "--dimple",           "volume",
                                         "--region-shrink", "0.5",   "--region-max-area",  "0.1",
                                         "--inward",        "force", "--density",          "2",
                                         "--delta",         "0.01",  "--target-ramp",      "7",
                                         "--c10",           "0.7",   "--collision-rounds", "3"};
  std::vector<std::string> args{"-n", "3", "--mass", "unit", "--collisions", "off", "--mu", "2"};
  args.insert(args.end(), ignored.begin(), ignored.end());
  const auto a = run_cli([&] {
    std::vector<std::string> all{"run",
                                 std::string(test::MESH_DIR) + "/ico2.off",
                                 "-o",
                                 (dir_ / "a.off").string(),
                                 "-q",
                                 "--summary",
                                 (dir_ / "a.json").string()};
    all.insert(all.end(), args.begin(), args.end());
    return all;
  }());
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const auto recorded = summary_options(dir_ / "a.json");
  ASSERT_GT(recorded.size(), 40u);
  std::vector<std::string> empty, rerun;
  for (const auto& [key, value] : recorded) {
    if (value.empty()) {
      empty.push_back(key);
      continue;
    }
    // The switches take no value: on is the switch, off is leaving it out.
    if (key == "measure-regions" || key == "inversion-aware") {
      if (value == "on") rerun.push_back("--" + key);
      continue;
    }
    rerun.insert(rerun.end(), {"--" + key, value});
  }
  for (std::size_t i = 0; i < ignored.size(); i += 2) {
    const std::string key = ignored[i].substr(2);
    EXPECT_EQ(summary_option(dir_ / "a.json", key), "") << key;
    EXPECT_NE(a.output.find("warning: " + ignored[i] + " has no effect"), std::string::npos)
        << key << ": " << a.output;
  }
  // Not given but without effect too: the summary does not record their table values either.
  for (const char* key : {"poisson", "fiber", "warm-start", "speculative-broad-phase", "c01"})
    EXPECT_EQ(summary_option(dir_ / "a.json", key), "") << key;
  // Where they act they are recorded: the membrane given, the masses, the collisions switch.
  EXPECT_EQ(summary_option(dir_ / "a.json", "mu"), "2");
  EXPECT_EQ(summary_option(dir_ / "a.json", "mass"), "unit");
  EXPECT_EQ(summary_option(dir_ / "a.json", "collisions"), "off");
  // Each option recorded empty, given here, is a "has no effect" warning (values for those the
  // first run was not given).
  const std::map<std::string, std::vector<std::string>> values{{"poisson", {"0.3"}},
                                                               {"fiber", {"1,0,0"}},
                                                               {"inversion-aware", {}},
                                                               {"warm-start", {"on"}},
                                                               {"speculative-broad-phase", {"on"}},
                                                               {"c01", {"0.1"}}};
  std::vector<std::string> every = args;
  for (const std::string& key : empty) {
    if (key == "young" || key == "thickness" || key == "region-weights" || key == "region-at")
      continue;  // no shell material; the regions' own sources, not given
    if (std::find(ignored.begin(), ignored.end(), "--" + key) != ignored.end()) continue;
    const auto value = values.find(key);
    if (value == values.end()) {
      ADD_FAILURE() << key << " recorded empty: give it a value here to check its warning";
      continue;
    }
    every.push_back("--" + key);
    every.insert(every.end(), value->second.begin(), value->second.end());
  }
  std::vector<std::string> given{"run", std::string(test::MESH_DIR) + "/ico2.off", "-o",
                                 (dir_ / "e.off").string(), "-q"};
  given.insert(given.end(), every.begin(), every.end());
  const auto e = run_cli(given);
  ASSERT_EQ(e.exit_code, 0) << e.output;
  for (const std::string& key : empty) {
    if (key != "young" && key != "thickness" && key != "region-weights" && key != "region-at") {
      EXPECT_NE(e.output.find("warning: --" + key + " has no effect"), std::string::npos)
          << key << " recorded empty: " << e.output;
    }
  }
  // The recorded options, without the empty ones, are the same run; none of them is a warning.
  std::vector<std::string> all{"run", std::string(test::MESH_DIR) + "/ico2.off", "-o",
                               (dir_ / "b.off").string(), "-q"};
  all.insert(all.end(), rerun.begin(), rerun.end());
  const auto b = run_cli(all);
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_EQ(b.output.find("has no effect"), std::string::npos) << b.output;
  EXPECT_EQ(file_text(dir_ / "b.off"), file_text(dir_ / "a.off"));
}

}  // namespace
}  // namespace shellcontract
