// The command line read the same way by every command (cli/command_line.cpp, docs/cli.md "Terms
// used throughout"): option names in full, a near miss answered with the name meant, a stray
// argument named, on|off and numbers in the documented grammar, lists under one rule.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "support/scratch_dir.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

class CliParsing : public test::ScratchDirTest {
 protected:
  CliParsing() : ScratchDirTest("shellcontract_cli_parsing_") {}
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    ScratchDirTest::SetUp();
  }
  static std::string mesh(const std::string& name) {
    return std::string(test::MESH_DIR) + "/" + name;
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  }
  /// A folder of one small vertex-face query file for bench ccd (three queries of eight rows).
  std::string query_dir() const {
    fs::create_directories(dir_ / "q");
    std::ofstream queries(dir_ / "q" / "vertex-face.csv");
    for (int row = 0; row < 3 * 8; ++row) queries << row % 8 << ",1152921504606846976,3,4,-1,1,0\n";
    return (dir_ / "q").string();
  }
  /// run on ico1 for one frame into o.off, with `extra` options.
  test::RunResult run(const std::vector<std::string>& extra) const {
    std::vector<std::string> args = {"run", mesh("ico1.off"), "-o", path("o.off"), "-n", "1", "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_cli(args);
  }
};

// boost took any unique prefix for the whole name: `run --frame 3` ran as --frames. A name is
// now taken only in full, in every command, and the refusal names the option meant.
TEST_F(CliParsing, AnAbbreviatedOptionIsRefusedWithTheNameItAbbreviates) {
  const std::string q = query_dir();
  struct Case {
    std::vector<std::string> args;
    std::string meant;
  };
  const std::vector<Case> cases = {
      {{"run", mesh("ico1.off"), "-o", path("o.off"), "-q", "--frame", "1"}, "--frames"},
      {{"run", mesh("ico1.off"), "-o", path("o.off"), "-q", "-n", "1", "--thread", "1"},
       "--threads"},
      {{"check", mesh("ico1.off"), "--fail"}, "--fail-on-self-intersections"},
      {{"bench", "error", mesh("ico1.off"), "-n", "1", "--iter", "1"}, "--iterations"},
      {{"bench", "ccd", "--quer", q}, "--queries"},
      {{"regions", mesh("ico2.off"), "--fit-tol", "0.3"}, "--fit-tolerance"},
  };
  for (const Case& c : cases) {
    const auto r = run_cli(c.args);
    EXPECT_EQ(r.exit_code, 1) << c.args[0] << ": " << r.output;
    EXPECT_TRUE(has(r.output, "unrecognised option")) << r.output;
    EXPECT_TRUE(has(r.output, "did you mean " + c.meant)) << r.output;
  }
  EXPECT_FALSE(fs::exists(path("o.off")));
}

// A misspelled option (a letter missing, US spelling, '_' for '-') gets the nearest names; an
// ambiguous start gets each option it begins; a name far from any gets none.
TEST_F(CliParsing, AMisspelledOptionGetsTheNearestNames) {
  const auto suggestion = [&](const std::string& option) { return run({option, "1"}).output; };
  EXPECT_TRUE(has(suggestion("--presure"), "did you mean --pressure?"));
  EXPECT_TRUE(has(suggestion("--fields-color"), "did you mean --fields-colour?"));
  EXPECT_TRUE(has(suggestion("--target_volume"), "did you mean --target-volume?"));
  const std::string both = suggestion("--pres");
  EXPECT_TRUE(has(both, "--pressure") && has(both, "--pressure-model")) << both;
  const std::string far = suggestion("--zzzzzzzz");
  EXPECT_TRUE(has(far, "unrecognised option '--zzzzzzzz'")) << far;
  EXPECT_FALSE(has(far, "did you mean")) << far;
}

// `bench ccd --tolerance 1e-6 1e-9` printed one table at 1e-6 and dropped 1e-9 (exit 0).
TEST_F(CliParsing, BenchCcdRefusesAStrayArgument) {
  const std::string q = query_dir();
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"bench", "ccd", "--queries", q, "--tolerance", "1e-6", "1e-9"},
        std::vector<std::string>{"bench", "ccd", "x", "--queries", q}}) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(
        has(r.output, "unexpected argument '" + (args[2] == "x" ? std::string("x") : "1e-9") + "'"))
        << r.output;
    EXPECT_FALSE(has(r.output, "vertex-face.csv")) << "a table was printed: " << r.output;
  }
}

// "too many positional options have been specified" named no argument; a pasted em dash
// (`—pressure 3`) is the usual cause and is said so.
TEST_F(CliParsing, AStrayArgumentIsNamed) {
  const auto two = run_cli({"run", mesh("ico1.off"), mesh("ico2.off"), "-o", path("o.off")});
  EXPECT_EQ(two.exit_code, 1) << two.output;
  EXPECT_TRUE(has(two.output, "unexpected argument '" + mesh("ico2.off") + "'")) << two.output;
  const auto dash = run({"\xE2\x80\x94pressure", "3"});
  EXPECT_EQ(dash.exit_code, 1) << dash.output;
  EXPECT_TRUE(has(dash.output, "'\xE2\x80\x94pressure'") && has(dash.output, "typographic dash"))
      << dash.output;
  EXPECT_FALSE(fs::exists(path("o.off")));
}

// `-o=o.off` wrote a file named "=o.off"; `-p=3` was refused only as "'=3' is not a number".
TEST_F(CliParsing, AnEqualsSignAfterAShortOptionIsRefused) {
  const auto r = run_cli({"run", mesh("ico1.off"), "-n", "1", "-q", "-o=" + path("o.off")});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "a short option takes no '='")) << r.output;
  EXPECT_TRUE(has(r.output, "--output=" + path("o.off"))) << r.output;
  EXPECT_TRUE(fs::is_empty(dir_)) << "a file was written";
  const auto p = run({"-p=3"});
  EXPECT_EQ(p.exit_code, 1) << p.output;
  EXPECT_TRUE(has(p.output, "-p 3")) << p.output;
}

// --collisions and --warm-start took 1/0/true/false in run (and not in bench error); the docs
// and the message say on|off.
TEST_F(CliParsing, OnOffOptionsTakeOnlyOnOrOff) {
  for (const char* option : {"--collisions", "--warm-start"})
    for (const char* value : {"1", "0", "true", "false", "yes", "ON"}) {
      const auto r = run({option, value});
      EXPECT_EQ(r.exit_code, 1) << option << " " << value << ": " << r.output;
      EXPECT_TRUE(has(r.output, "is not on or off")) << r.output;
      EXPECT_FALSE(fs::exists(path("o.off"))) << option << " " << value;
    }
  EXPECT_EQ(run({"--collisions", "on", "--warm-start", "off"}).exit_code, 0);
}

// `--validate` with no value read like a switch that failed: "the required argument for option
// '--validate' is missing", without the values it takes (review "tasks" F8).
TEST_F(CliParsing, AnOptionGivenWithoutItsValueListsTheValues) {
  const auto validate = run({"--validate"});
  EXPECT_EQ(validate.exit_code, 1) << validate.output;
  EXPECT_TRUE(has(validate.output, "'--validate' is missing: NAME is off | end | every-frame"))
      << validate.output;
  const auto material = run({"--material"});
  EXPECT_EQ(material.exit_code, 1) << material.output;
  EXPECT_TRUE(has(material.output, "is missing: NAME is stvk | corotated | linear | mooney-rivlin"))
      << material.output;
  EXPECT_FALSE(fs::exists(path("o.off")));
}

// --gltf-fps was read by strtod: "0x10" was 16 fps, " 3" was 3.
TEST_F(CliParsing, GltfFpsTakesOnlyADecimalNumber) {
  for (const char* fps : {"0x10", "0x1p3", " 3", "inf"}) {
    const auto r = run({"--gltf", path("g.glb"), "--gltf-fps", fps});
    EXPECT_EQ(r.exit_code, 1) << fps << ": " << r.output;
    EXPECT_TRUE(has(r.output, "--gltf-fps")) << r.output;
    EXPECT_FALSE(fs::exists(path("g.glb"))) << fps;
  }
  EXPECT_EQ(run({"--gltf", path("g.glb"), "--gltf-fps", "30"}).exit_code, 0);
}

// A --regions file's "S:" strength and a --region-weights line were read by strtod: "0x0.8:" was
// 0.5 and "0x1p-1" a weight of 0.5. They take an option's number now (blanks around them are
// the file's separators, as between face ids).
TEST_F(CliParsing, RegionFileNumbersAreDecimal) {
  std::ofstream(path("faces.txt")) << "0x0.8: 0 1 2 3 4 5\n";
  const auto faces = run({"--regions", path("faces.txt")});
  EXPECT_EQ(faces.exit_code, 2) << faces.output;
  EXPECT_TRUE(has(faces.output, "strength '0x0.8'")) << faces.output;
  std::ofstream(path("half.txt")) << " 0.5 : 0 1 2 3 4 5\n";
  EXPECT_EQ(run({"--regions", path("half.txt")}).exit_code, 0);

  // ico1: 42 vertices.
  std::string weights;
  for (int v = 0; v < 42; ++v) weights += v == 7 ? "0x1p-1\n" : " 1\n";
  std::ofstream(path("w.txt")) << weights;
  const auto w = run({"--region-weights", path("w.txt")});
  EXPECT_EQ(w.exit_code, 2) << w.output;
  EXPECT_TRUE(has(w.output, "'0x1p-1' is not a weight")) << w.output;
}

// bench error's lists: a trailing comma was taken, an item twice ran twice, --threads had no
// bound; bench ccd's --sweep took "0," and refused "0, 1e-9". One rule now (docs/cli.md).
TEST_F(CliParsing, ListsFollowOneRule) {
  const std::vector<std::string> base = {
      "bench",    "error", mesh("ico1.off"), "-n",         "1", "-q",
      "--solver", "pbd",   "--no-check",     "--substeps", "1"};
  const auto bench = [&](const std::string& option, const std::string& value) {
    std::vector<std::string> args = base;
    args.insert(args.end(), {option, value});
    if (option != "--iterations") args.insert(args.end(), {"--iterations", "1"});
    return run_cli(args);
  };
  for (const char* bad : {"1,", "1,,2", ",1", "1,1", "0", "1.5", "0x2"}) {
    const auto r = bench("--iterations", bad);
    EXPECT_EQ(r.exit_code, 1) << bad << ": " << r.output;
    EXPECT_TRUE(has(r.output, "--iterations")) << r.output;
  }
  const auto threads = bench("--threads", "4097");
  EXPECT_EQ(threads.exit_code, 1) << threads.output;
  EXPECT_TRUE(has(threads.output, "[1, 4096]")) << threads.output;
  EXPECT_EQ(bench("--orders", "both,coloured").exit_code, 1);
  EXPECT_EQ(bench("--iterations", "1, 2").exit_code, 0);  // blanks around items are separators

  const std::string q = query_dir();
  for (const char* bad : {"0,", "0,,1e-9", "0,0"}) {
    const auto r = run_cli({"bench", "ccd", "--queries", q, "--repeat", "1", "--sweep", bad});
    EXPECT_EQ(r.exit_code, 1) << bad << ": " << r.output;
  }
  const auto spaced =
      run_cli({"bench", "ccd", "--queries", q, "--repeat", "1", "--sweep", "0, 1e-9"});
  EXPECT_EQ(spaced.exit_code, 0) << spaced.output;
}

// bench error's --dt and -p took what run refuses (--dt 2, -p 1e308, found out as a failed
// reference, exit 3) and --dt 1e-320 was refused in other words: run's ranges and messages now.
TEST_F(CliParsing, BenchErrorRefusesWhatRunRefuses) {
  for (const std::vector<std::string>& bad : {std::vector<std::string>{"--dt", "2"},
                                              {"--dt", "1e-320"},
                                              {"-p", "1e308"},
                                              {"-p", "0x10"},
                                              {"-n", "0"},
                                              {"-p", "0:4, 10:2"}}) {
    std::vector<std::string> args = {"bench", "error",      mesh("ico1.off"), "-q", "--solver",
                                     "pbd",   "--no-check", "--iterations",   "1",  "--substeps",
                                     "1"};
    args.insert(args.end(), bad.begin(), bad.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << bad[0] << " " << bad[1] << ": " << r.output;
    const std::string name = bad[0] == "-p" ? "--pressure" : bad[0] == "-n" ? "--frames" : bad[0];
    EXPECT_TRUE(has(r.output, name + ": '" + bad[1] + "'")) << r.output;
  }
}

// regions' numbers and bench error's reference counts were Boost's conversions: --fit-tolerance
// 1e-400 ran as 0, " 12" was refused in Boost's words, --pbd-ref-iterations took any int
// (2000000000 ran for hours; twice it, the reference check's, overflowed). Run's grammar and the
// rungs' bound now (review drift F4, complexity F11).
TEST_F(CliParsing, RegionsAndBenchErrorReadNumbersAsRunDoes) {
  const std::string bumpy = mesh("bumpy_sphere.off");
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"--fit-tolerance", "1e-400", "is not a number"},
        {"--contrast", "0x1", "is not a number"},
        {"--max-area-fraction", "nan", "is not a number"},
        {"--min-faces", " 12", "is not an integer"},
        {"--min-faces", "12.0", "is not an integer"},
        {"--min-faces", "3000000000", "is not an integer in [1, 2147483647]"}}) {
    const auto r = run_cli({"regions", bumpy, bad[0], bad[1]});
    EXPECT_EQ(r.exit_code, 1) << bad[0] << " " << bad[1] << ": " << r.output;
    EXPECT_TRUE(has(r.output, bad[0] + ": '" + bad[1] + "' " + bad[2])) << r.output;
  }
  // The same digits in another spelling are the same number: the same table.
  const auto plain = run_cli({"regions", bumpy, "--fit-tolerance", "0.3", "--min-faces", "10"});
  const auto spelt = run_cli({"regions", bumpy, "--fit-tolerance", "+3e-1", "--min-faces", "+10"});
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_EQ(spelt.exit_code, 0) << spelt.output;
  EXPECT_EQ(spelt.output, plain.output);
  const auto ccd =
      run_cli({"bench", "ccd", "--queries", query_dir(), "--repeat", "1", "--tolerance", "1e-400"});
  EXPECT_EQ(ccd.exit_code, 1) << ccd.output;
  EXPECT_TRUE(has(ccd.output, "--tolerance: '1e-400' is not a finite number >= 0")) << ccd.output;

  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"--pbd-ref-iterations", "100001"},
        {"--ref-iterations", "100001"},
        {"--ref-substeps", "100001"},
        {"--ref-iterations", "1e3"},
        {"--pbd-ref-iterations", " 5"},
        {"--ref-substeps", "0"}}) {
    std::vector<std::string> args = {
        "bench", "error",      mesh("ico1.off"), "-q", "-n",         "1", "--solver",
        "pbd",   "--no-check", "--iterations",   "1",  "--substeps", "1"};
    args.insert(args.end(), bad.begin(), bad.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << bad[0] << " " << bad[1] << ": " << r.output;
    EXPECT_TRUE(has(r.output, bad[0] + ": '" + bad[1] + "' is not an integer in [1, 100000]"))
        << r.output;
  }
}

// `shellcontract help run` printed the commands' list; `--version extra` ignored `extra`.
TEST_F(CliParsing, HelpNamesACommandAndVersionTakesNoArgument) {
  const auto run_help = run_cli({"help", "run"});
  EXPECT_EQ(run_help.exit_code, 0) << run_help.output;
  EXPECT_TRUE(has(run_help.output, "usage: shellcontract run INPUT")) << run_help.output;
  const auto ccd_help = run_cli({"help", "bench", "ccd"});
  EXPECT_EQ(ccd_help.exit_code, 0) << ccd_help.output;
  EXPECT_TRUE(has(ccd_help.output, "usage: shellcontract bench ccd")) << ccd_help.output;
  EXPECT_EQ(run_cli({"help", "nonsense"}).exit_code, 1);
  const auto version = run_cli({"--version", "extra"});
  EXPECT_EQ(version.exit_code, 1) << version.output;
  EXPECT_TRUE(has(version.output, "'extra'")) << version.output;
}

}  // namespace
}  // namespace shellcontract
