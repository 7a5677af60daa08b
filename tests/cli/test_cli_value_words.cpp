// Values that make no sense, said in words that name the option and its value (review15's L8,
// L11, L12, L13): `regions` thresholds out of range, a --density too small to give a vertex a
// mass, ratios and distances too large for a double ("inf" before), and runs that nothing drives
// or whose stop ratio they cannot reach, warned before the run instead of ending "ok" or exit 5
// without a word.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "support/scratch_dir.hpp"
#include "test_paths.hpp"

namespace {

namespace fs = std::filesystem;
using shellcontract::test::run_cli;
using shellcontract::test::RunResult;

class CliValueWords : public shellcontract::test::ScratchDirTest {
 protected:
  CliValueWords() : ScratchDirTest("shellcontract_cli_value_words_") {}
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    ScratchDirTest::SetUp();
  }
  static std::string mesh(const std::string& name) {
    return std::string(shellcontract::test::MESH_DIR) + "/" + name;
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// `run` on ico2 for a few frames with the summary, and the extra options.
  RunResult run(const std::vector<std::string>& extra, const std::string& frames = "5") {
    std::vector<std::string> args{"run", mesh("ico2.off"), "-o",        path("o.off"),
                                  "-n",  frames,           "--summary", path("s.json")};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_cli(args);
  }
  std::string summary() const {
    std::ifstream in(path("s.json"));
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  static bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  }
};

// Before: "region options: area fractions must satisfy 0 <= min <= max <= 1" and "max concave
// fraction must be in [0, 1]", naming neither the option nor the value; NaN said ">= 0", not the
// fraction's range; an empty value "the argument for option ... is invalid".
TEST_F(CliValueWords, RegionsNamesTheOptionTheValueAndTheRange) {
  const struct {
    std::vector<std::string> args;
    std::vector<std::string> said;
  } cases[] = {
      {{"--max-area-fraction", "0", "--min-area-fraction", "0.3"},
       {"--max-area-fraction 0 is below --min-area-fraction 0.3"}},
      {{"--max-area-fraction", "0.001"},
       {"--max-area-fraction 0.001 is below --min-area-fraction 0.002"}},
      {{"--max-concave-fraction", "1.5"}, {"--max-concave-fraction 1.5", "[0, 1]"}},
      {{"--max-area-fraction", "nan"}, {"--max-area-fraction: 'nan' is not a number"}},
      {{"--min-area-fraction", "2"}, {"--min-area-fraction 2", "[0, 1]"}},
      {{"--min-cap-angle", "200"}, {"--min-cap-angle 200", "[0, 180]"}},
      {{"--contrast", "-1"}, {"--contrast -1", ">= 0"}},
      {{"--max-compactness", "0"}, {"--max-compactness 0", "> 0"}},
      {{"--min-faces", "0"}, {"--min-faces 0", ">= 1"}},
      {{"--fit-tolerance", ""}, {"--fit-tolerance: empty; give a value or leave the option out"}},
      {{"--min-faces="}, {"--min-faces: empty"}},
  };
  for (const auto& c : cases) {
    std::vector<std::string> args{"regions", mesh("ico2.off"), "--face-list", path("f.txt")};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const RunResult r = run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << c.args[0] << ": " << r.output;
    for (const std::string& s : c.said) EXPECT_TRUE(has(r.output, s)) << s << '\n' << r.output;
    EXPECT_FALSE(has(r.output, "region options")) << r.output;
    EXPECT_FALSE(fs::exists(path("f.txt"))) << c.args[0];
  }
}

// Before: --region-max-area below the finder's smallest region gave the `regions` command's
// "region options: area fractions must satisfy ...", which names no option of `run`.
TEST_F(CliValueWords, RunSaysARegionMaxAreaBelowTheSmallestRegion) {
  const RunResult r = run({"--regions", "auto", "--region-max-area", "0.001"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "--region-max-area 0.001 is below")) << r.output;
  EXPECT_FALSE(has(r.output, "region options")) << r.output;
  EXPECT_FALSE(has(r.output, "--max-area-fraction")) << r.output;
  EXPECT_FALSE(fs::exists(path("o.off")));
}

// Before: 1e-320 (inside the documented (0, 1e12]) gave exit 3 "non-finite positions at step 1"
// and no warning: the masses were 0, their inverses infinite. Now below 1e-100 is bad usage,
// naming the range, and nothing is written; the bound itself runs (to a blow-up the mass-scaling
// warning explains, or to the end), never with NaN in the result.
TEST_F(CliValueWords, ADensityTooSmallToGiveAMassIsRefusedNamingTheRange) {
  for (const char* d : {"1e-320", "1e-310", "1e-101", "0"}) {
    const RunResult r = run({"--density", d});
    EXPECT_EQ(r.exit_code, 1) << d << ": " << r.output;
    EXPECT_TRUE(has(r.output, "--density")) << r.output;
    EXPECT_TRUE(has(r.output, "1e-100")) << r.output;
    EXPECT_FALSE(has(r.output, "non-finite")) << r.output;
    EXPECT_FALSE(fs::exists(path("o.off"))) << d;
  }
  const RunResult r = run({"--density", "1e-100", "-p", "0", "--target-volume", "0.9"});
  EXPECT_NE(r.exit_code, 1) << r.output;
  EXPECT_FALSE(has(r.output, "non-finite")) << r.output;
}

// Before: --density 0.002 on bumpy_sphere (inside the documented range) swung between about 0.3
// and 0.6 for its 200 frames and ended "ok" with no word of it: the enclosed air's spring is
// integrated explicitly, and a shell this light overshoots its balance every step. Now the run
// says so before its first step, with the density that keeps the step within the bound
// (docs/math/air-pressure.md section 4, about 0.0045 there); the default run and 0.005, which
// settles at 0.50, are quiet.
TEST_F(CliValueWords, ADensityTooLightForTheStepIsNamedBeforeTheRun) {
  const auto bumpy = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> args{"run", mesh("bumpy_sphere.off"), "-o", path("o.off"), "-n", "1"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_cli(args);
  };
  const std::string said = "that the enclosed air is sure to take back in one step";
  const RunResult light = bumpy({"--density", "0.002"});
  EXPECT_EQ(light.exit_code, 0) << light.output;
  EXPECT_TRUE(has(light.output, said)) << light.output;
  EXPECT_TRUE(has(light.output, "A --density 0.0045 or more")) << light.output;
  for (const std::vector<std::string>& quiet : {std::vector<std::string>{},
                                                {"--density", "0.005"},
                                                {"--density", "0.002", "--air-balance", "0"}}) {
    const RunResult r = bumpy(quiet);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_FALSE(has(r.output, said)) << r.output;
  }
}

// Before: "V/V0 ended inf times larger than the target" (the factor overflowed a double).
TEST_F(CliValueWords, ARatioTooLargeForADoubleIsSaidInWords) {
  for (const char* option : {"--target-volume", "--stop-volume-ratio"}) {
    const RunResult r = run({option, "1e-320"}, "2");
    EXPECT_EQ(r.exit_code, 5) << option << ": " << r.output;
    EXPECT_TRUE(has(r.output, "times larger than the")) << r.output;
    EXPECT_FALSE(has(r.output, "inf")) << r.output;
    EXPECT_FALSE(has(summary(), "inf times")) << summary();
  }
}

// Before: "the 1st --region-at point ... is inf from the surface" and "(inf from the point
// given)" in the table.
TEST_F(CliValueWords, ADistanceTooLargeForADoubleIsSaidInWords) {
  const RunResult r =
      run_cli({"regions", mesh("ico2.off"), "--region-at", "1.7e308,1.7e308,1.7e308"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "from the surface")) << r.output;
  EXPECT_TRUE(has(r.output, "from the point given")) << r.output;
  EXPECT_FALSE(has(r.output, "inf")) << r.output;
}

// Before: -p 0 alone exited 0 with the input as the result and no word; with a stop ratio, and
// with a stop ratio under a pressure that inflates, every frame ran and the run ended exit 5.
TEST_F(CliValueWords, ARunThatNothingDrivesIsWarnedBeforeItRuns) {
  const struct {
    std::vector<std::string> args;
    std::string said;
  } cases[] = {
      {{"-p", "0"}, "nothing drives this run"},
      {{"-p", "0:0, 3:0"}, "nothing drives this run"},
      {{"-p", "0", "--stop-volume-ratio", "0.9"}, "--stop-volume-ratio 0.9 cannot be reached"},
      {{"-p", "-4", "--stop-volume-ratio", "0.9"}, "--stop-volume-ratio 0.9 cannot be reached"},
      {{"-p", "0:0, 3:-2", "--stop-volume-ratio", "0.9"},
       "--stop-volume-ratio 0.9 cannot be reached"},
  };
  for (const auto& c : cases) {
    const RunResult r = run(c.args);
    const std::string what = c.args[1] + (c.args.size() > 2 ? " " + c.args[2] : "");
    // On a "warning:" line of its own.
    const std::size_t at = r.output.find(c.said);
    ASSERT_NE(at, std::string::npos) << what << '\n' << r.output;
    const std::size_t line = r.output.rfind('\n', at);
    EXPECT_EQ(r.output.compare(line == std::string::npos ? 0 : line + 1, 9, "warning: "), 0)
        << what << '\n'
        << r.output;
    // Printed before the run: ahead of the last line, which names the result written.
    EXPECT_LT(r.output.find(c.said), r.output.rfind(path("o.off"))) << what << '\n' << r.output;
    EXPECT_TRUE(has(summary(), c.said)) << what << '\n' << summary();
  }
}

// What drives a run, alone, gets no such warning: a pressure either way (without a stop ratio),
// a keyed pressure that acts at some frame, a target volume, regions that contract, the isometric
// bending.
TEST_F(CliValueWords, ARunThatSomethingDrivesGetsNoSuchWarning) {
  const std::vector<std::vector<std::string>> drivers = {
      {"-p", "4"},
      {"-p", "-4"},
      {"-p", "0:0, 3:4"},
      {"-p", "0", "--target-volume", "0.9"},
      {"-p", "0", "--target-volume", "0:1, 5:0.9"},
      {"-p", "0", "--region-at", "0,0,0.5"},
      {"-p", "0", "--bending", "isometric"},
      {"-p", "4", "--stop-volume-ratio", "0.9"},
  };
  for (const std::vector<std::string>& d : drivers) {
    const RunResult r = run(d);
    EXPECT_FALSE(has(r.output, "nothing drives")) << d[1] << '\n' << r.output;
    EXPECT_FALSE(has(r.output, "cannot be reached")) << d[1] << '\n' << r.output;
  }
}

}  // namespace
