// Options that have no effect with the others are a warning on stderr (docs/cli.md), also those of
// the outputs: before, `--density` under `--mass unit`, `--fields-colour` without `--fields` and
// `--export-failure` without `--export-dir` or `--gltf` were dropped without a word (and the result
// of `--mass unit --density 3` was byte for byte that of `--mass unit`). And a warning that is not
// the tool's: more --threads than the machine has printed TBB's "TBB Warning: The number of workers
// is currently limited to ..." past -q.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace {

namespace fs = std::filesystem;
using shellcontract::test::RunResult;
using shellcontract::test::run_cli;

class CliIgnoredOptions : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_ignored_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  RunResult run(const std::vector<std::string>& extra) {
    std::vector<std::string> args{"run", std::string(shellcontract::test::MESH_DIR) + "/ico1.off", "-o",
                                  (dir_ / "o.off").string(), "-n", "2", "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_cli(args);
  }
  fs::path dir_;
};

TEST_F(CliIgnoredOptions, EachOptionWithoutEffectIsAWarningNamingIt) {
  const struct {
    std::vector<std::string> args;
    std::string warning;
  } cases[] = {
      {{"--mass", "unit", "--density", "3"}, "--density has no effect"},
      {{"--fields-colour", "energy"}, "--fields-colour has no effect"},
      {{"--export-failure", "stop"}, "--export-failure has no effect"},
      // Before: silently set by the shell material (summary mu 0.769 for --mu 1).
      {{"--mu", "1", "--young", "1000"}, "--mu has no effect"},
      {{"--lambda", "1", "--thickness", "0.01"}, "--lambda has no effect"},
      // Before: no word, and E 1000 and E 100000 gave the same bytes (the membrane reads only
      // c10 and c01; the summary recorded the mu and lambda nothing used).
      {{"--material", "mooney-rivlin", "--young", "1000", "--thickness", "0.01"},
       "--young and --thickness set only the bending k_B here: the Mooney-Rivlin membrane takes "
       "--c10"},
      {{"--material", "mooney-rivlin", "--young", "1000", "--thickness", "0.01", "--k-b", "0.1"},
       "--young has no effect: the Mooney-Rivlin membrane takes --c10"},
      // Before: no word under --inward projection, where k_A scales with mu_A as the energy does
      // and the positions are the same to the bit
      // (GoldenPaths.InwardProjectionUnderPbdDoesNotDependOnMuA).
      // The step alone: mu_A still enters the solver's skip floor (review9 D6: --mu-a 100
      // against 1 moved a vertex by 2.7e-6), which "no effect" denied.
      {{"--aniso", "arap", "--solver", "pbd", "--inward", "projection", "--mu-a", "4"},
       "--mu-a has no effect on the PBD projection's step (only on which faces near rest it "
       "skips): a PBD projection does not depend on the stiffness"},
  };
  for (const auto& c : cases) {
    const RunResult r = run(c.args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("warning: " + c.warning), std::string::npos) << c.args[0] << ": " << r.output;
  }
}

// Before: no word (review10 #8). At pressure 0 both pressure models give no force at all: with a
// region sinking (so that the shell moves), the paper's model gives the energy model's bytes,
// which is what makes the warning true.
TEST_F(CliIgnoredOptions, ThePressureModelAtPressureZeroIsAWarningAndChangesNothing) {
  const auto bytes = [&](const std::vector<std::string>& model, std::string& output) {
    std::vector<std::string> args{"-p", "0", "--region-at=0,0,1"};
    args.insert(args.end(), model.begin(), model.end());
    const RunResult r = run(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    output = r.output;
    std::ifstream in(dir_ / "o.off", std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  std::string warned, quiet;
  const std::string paper = bytes({"--pressure-model", "paper"}, warned);
  const std::string energy = bytes({}, quiet);
  EXPECT_NE(warned.find("warning: --pressure-model has no effect"), std::string::npos) << warned;
  EXPECT_EQ(quiet.find("--pressure-model"), std::string::npos) << quiet;
  EXPECT_FALSE(paper.empty());
  EXPECT_EQ(paper, energy);
}

// Before: under --solver pbd, --young 1e6 against 1000, --thickness, Mooney-Rivlin's --c10 with
// --c01 0, and --mu 100 --lambda 100 against 1 1 gave the same result to rounding, with no word
// (review9 D6), while --mu-a was warned about. Each is one line, only when given.
TEST_F(CliIgnoredOptions, AStiffnessScaleUnderPbdIsOneWarningEach) {
  const std::string step = " has no effect on the PBD projection's step";
  const struct {
    std::vector<std::string> args;
    std::string warning;
  } cases[] = {
      {{"--young", "1e6"}, "--young" + step},
      {{"--thickness", "0.05"}, "--thickness" + step},
      {{"--material", "mooney-rivlin", "--c10", "50"}, "--c10" + step},
      {{"--mu", "100", "--lambda", "100"},
       "--mu and --lambda act under --solver pbd by their ratio"},
      {{"--material", "mooney-rivlin", "--c10", "5", "--c01", "1"},
       "--c10 and --c01 act under --solver pbd by their ratio"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> args{"--solver", "pbd"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const RunResult r = run(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const std::size_t at = r.output.find("warning: " + c.warning);
    EXPECT_NE(at, std::string::npos) << c.args[0] << ": " << r.output;
    EXPECT_EQ(r.output.find(c.warning, at + c.warning.size()), std::string::npos)
        << "twice: " << r.output;
  }
  // Where they act: under xpbd, and options that change lambda/mu or C01/C10 under pbd.
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--young", "1e6", "--thickness", "0.05"},
        std::vector<std::string>{"--solver", "pbd", "--mu", "2"},
        std::vector<std::string>{"--solver", "pbd", "--lambda", "0.5"},
        std::vector<std::string>{"--solver", "pbd", "--material", "mooney-rivlin", "--c01", "1"}}) {
    const RunResult r = run(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("PBD projection"), std::string::npos) << args[1] << ": " << r.output;
    EXPECT_EQ(r.output.find("under --solver pbd by their ratio"), std::string::npos) << r.output;
  }
}

TEST_F(CliIgnoredOptions, TheSameOptionsWhereTheyActGiveNoWarning) {
  const std::string fields = (dir_ / "f").string();
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--density", "3"},
        std::vector<std::string>{"--pressure-model", "paper"},
        std::vector<std::string>{"--fields", fields, "--fields-colour", "energy"},
        std::vector<std::string>{"--export-dir", (dir_ / "frames").string(), "--export-failure",
                                 "stop"}}) {
    const RunResult r = run(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("has no effect"), std::string::npos) << args[0] << ": " << r.output;
  }
}

// Before: `--pressure has no effect` was warned with --target-volume, and docs/cli.md said so;
// the pressure changes the way to the target volume and the shape there (volume-control.md,
// section 1), so a run at another pressure is another result at the same volume.
TEST_F(CliIgnoredOptions, ThePressureUnderATargetVolumeIsNoWarningAndShapesTheResult) {
  const auto bytes = [&] {
    std::ifstream in(dir_ / "o.off", std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const auto run30 = [&](std::vector<std::string> extra) {
    std::vector<std::string> args{"run", std::string(shellcontract::test::MESH_DIR) + "/ico2.off", "-o",
                                  (dir_ / "o.off").string(), "-n", "30", "-q", "--target-volume", "0.8"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_cli(args);
  };
  const RunResult zero = run30({"-p", "0"});
  ASSERT_EQ(zero.exit_code, 0) << zero.output;
  const std::string at_zero = bytes();
  const RunResult twenty = run30({"-p", "20", "--air-balance", "0.7"});
  ASSERT_EQ(twenty.exit_code, 0) << twenty.output;
  EXPECT_EQ(twenty.output.find("has no effect"), std::string::npos) << twenty.output;
  EXPECT_NE(bytes(), at_zero) << "the pressure changed nothing under the target volume";
}

// Before: an empty value turned the output off (or --resume into a fresh run), exit 0 and
// nothing said: a script's unset variable went unnoticed.
// Before: with a keyed --target-volume, --target-ramp was warned as having no effect, yet with
// regions it times their sink, and two ramps gave other shapes (the guarantees review: bumpy_sphere
// moved up to 8 % of its diagonal). Keys without regions are still warned about (test_schedule).
TEST_F(CliIgnoredOptions, TheRampWithKeysTimesTheRegionsSinkAndIsNoWarning) {
  const std::string mesh_dir = shellcontract::test::MESH_DIR;
  const auto run_ramp = [&](const std::string& ramp, const std::string& out) {
    return run_cli({"run", mesh_dir + "/bumpy_sphere.off", "-o", (dir_ / out).string(), "-n", "40",
                    "-q", "--target-volume", "0:1, 30:0.6", "--regions",
                    mesh_dir + "/bumpy_sphere.bumps.txt", "--target-ramp", ramp});
  };
  const RunResult fast = run_ramp("5", "r5.off");
  const RunResult slow = run_ramp("30", "r30.off");
  for (const RunResult* r : {&fast, &slow}) {
    ASSERT_EQ(r->exit_code, 0) << r->output;
    EXPECT_EQ(r->output.find("--target-ramp has no effect"), std::string::npos) << r->output;
  }
  const auto bytes = [&](const std::string& name) {
    std::ifstream in(dir_ / name, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_NE(bytes("r5.off"), bytes("r30.off")) << "the ramp no longer times the regions' sink";
}

TEST_F(CliIgnoredOptions, AnEmptyValueIsRefusedNamingTheOption) {
  for (const char* option : {"--log", "--summary", "--gltf", "--checkpoint", "--export-dir", "--fields", "--resume"}) {
    const RunResult r = run({option, ""});
    EXPECT_EQ(r.exit_code, 1) << option << ": " << r.output;
    EXPECT_NE(r.output.find(std::string(option) + ": empty"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "o.off")) << option;
  }
  const RunResult regions = run_cli({"regions", std::string(shellcontract::test::MESH_DIR) + "/ico1.off",
                                     "--face-list", ""});
  EXPECT_EQ(regions.exit_code, 1) << regions.output;
  EXPECT_NE(regions.output.find("--face-list: empty"), std::string::npos) << regions.output;
  const RunResult input = run_cli({"check", ""});
  EXPECT_EQ(input.exit_code, 1) << input.output;
  EXPECT_NE(input.output.find("INPUT: an empty file name"), std::string::npos) << input.output;
}

// Before: pushed through itself with collisions off, ico2 ended inside out (V/V0 -15.2) with
// status ok, exit 0 and no word: no face pair intersects there, so --validate end found nothing.
TEST_F(CliIgnoredOptions, AShellThatEndsInsideOutIsWarnedAbout) {
  const RunResult r = run_cli({"run", std::string(shellcontract::test::MESH_DIR) + "/ico2.off", "-o",
                               (dir_ / "o.off").string(), "-n", "20", "-q", "-p", "200", "--collisions", "off",
                               "--air-balance", "0", "--summary", (dir_ / "s.json").string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: V/V0 ended at -"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("the shell passed through itself and is inside out (--collisions off)"),
            std::string::npos) << r.output;
  // The default run of the same mesh ends above 0 and says nothing of the kind.
  const RunResult plain = run({});
  EXPECT_EQ(plain.output.find("inside out"), std::string::npos) << plain.output;
}

TEST_F(CliIgnoredOptions, MoreThreadsThanTheMachineHasRunQuietlyToTheSameBytes) {
  // 256 threads: more than this test's machines have (the test shows nothing on a bigger one).
  const RunResult many = run({"--threads", "256"});
  ASSERT_EQ(many.exit_code, 0) << many.output;
  EXPECT_EQ(many.output, "");
  const std::string bytes = [&] {
    std::ifstream in(dir_ / "o.off", std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  const RunResult one = run({"--threads", "1"});
  ASSERT_EQ(one.exit_code, 0) << one.output;
  std::ifstream in(dir_ / "o.off", std::ios::binary);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), bytes);
}

}  // namespace
