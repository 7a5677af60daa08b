// `bench ccd --json` and `bench error --csv/--plot` go through the same check as the other
// commands' outputs, before the benchmark runs. Each test failed against the code before the fix:
// bench ccd checked nothing (--json over a query file replaced it, exit 0; as root --json
// /dev/null turned the device into a file; a missing folder was found after the whole
// benchmark, naming the temporary), and bench error's --csv over the input mesh replaced it.
// bench error --plot without --csv took $TMPDIR on access() alone: a TMPDIR where no file can be
// made (root passes access() on /proc and /sys) failed after the whole benchmark, no plot. The
// plot now needs no temporary data file at all (its data is inside gnuplot's script): the test
// stays as the property a user sees, a plot drawn whatever TMPDIR names.
#include "hostile/hostile_support.hpp"

namespace shellcontract {
namespace {

using test::Hostile;
using test::run_cli;

/// A query folder holding the first two queries of the handcrafted vertex-face file (eight rows
/// each: ../shared/data/ccd-queries/README.md); false when the shared data is not there.
bool two_queries(const fs::path& dir, std::string& text) {
  std::ifstream in(fs::path(test::CCD_QUERY_DIR) / "handcrafted" / "vertex-face.csv");
  if (!in) return false;
  std::string line;
  for (int i = 0; i < 16 && std::getline(in, line); ++i) text += line + "\n";
  fs::create_directories(dir);
  test::spit(dir / "vertex-face.csv", text);
  return true;
}

TEST_F(Hostile, BenchCcdJsonOverAQueryFileIsRefused) {
  std::string text;
  if (!two_queries(dir_ / "q", text))
    SKIP_OR_FAIL_UNDER_CI("no CCD queries at " << test::CCD_QUERY_DIR);
  const fs::path queries = dir_ / "q" / "vertex-face.csv";
  const auto r = run_cli({"bench", "ccd", "--queries", (dir_ / "q").string(), "--repeat", "1", "--json",
                          queries.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("is the file of --queries"), std::string::npos) << r.output;
  EXPECT_EQ(test::slurp(queries), text) << "the query file was overwritten";
  EXPECT_EQ(test::listing(dir_ / "q"), std::vector<std::string>{"vertex-face.csv"});
}

TEST_F(Hostile, BenchCcdJsonInAMissingFolderIsRefusedBeforeTheBenchmark) {
  std::string text;
  if (!two_queries(dir_ / "q", text))
    SKIP_OR_FAIL_UNDER_CI("no CCD queries at " << test::CCD_QUERY_DIR);
  const auto r = run_cli({"bench", "ccd", "--queries", (dir_ / "q").string(), "--repeat", "1", "--json",
                          (dir_ / "missing" / "r.json").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("does not exist"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("tolerance"), std::string::npos) << "the benchmark ran first: " << r.output;
}

TEST_F(Hostile, BenchCcdJsonOnADeviceNeverReplacesIt) {
  std::string text, why;
  if (!two_queries(dir_ / "q", text))
    SKIP_OR_FAIL_UNDER_CI("no CCD queries at " << test::CCD_QUERY_DIR);
  const fs::path dev = dir_ / "null";
  if (!make_device(dev, 3, why)) SKIP_OR_FAIL_UNDER_CI(why);
  const auto r = run_cli({"bench", "ccd", "--queries", (dir_ / "q").string(), "--repeat", "1", "--json",
                          dev.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  struct stat st {};
  ASSERT_EQ(::lstat(dev.c_str(), &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "the device node was replaced";
}

TEST_F(Hostile, BenchErrorCsvOverTheInputIsRefused) {
  const fs::path in = dir_ / "in.off";
  fs::copy_file(test::mesh("ico1.off"), in);
  const std::string before = test::slurp(in);
  const auto r = run_cli({"bench", "error", in.string(), "--frames", "2", "--solver", "xpbd", "-q",
                          "--no-check", "--csv", in.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("is the input file"), std::string::npos) << r.output;
  EXPECT_EQ(test::slurp(in), before) << "the input mesh was overwritten";
  EXPECT_EQ(test::listing(dir_), std::vector<std::string>{"in.off"});
}

TEST_F(Hostile, BenchErrorPlotPassesOverATmpdirThatTakesNoFile) {
  if (test::run_command("command -v gnuplot >/dev/null").exit_code != 0)
    GTEST_SKIP() << "gnuplot is not installed";
  // Folders in which nobody, root included, can create a file, though access(W_OK) passes for
  // root (/proc, /sys), and a path under a regular file.
  test::spit(dir_ / "file", "x");
  for (const std::string& tmpdir :
       {std::string("/proc"), std::string("/sys"), (dir_ / "file" / "sub").string()}) {
    const fs::path plot = dir_ / "p.svg";
    fs::remove(plot);
    const auto r = test::run_command(
        "TMPDIR=" + test::quoted(tmpdir) + " " +
        test::cli_command({"bench", "error", test::mesh("ico1.off"), "--frames", "2",
                           "--iterations", "1", "--substeps", "1", "--solver", "xpbd", "-q",
                           "--no-check", "--plot", plot.string()}));
    EXPECT_EQ(r.exit_code, 0) << tmpdir << ": " << r.output;
    EXPECT_TRUE(fs::is_regular_file(plot)) << tmpdir << ": no plot: " << r.output;
  }
}

}  // namespace
}  // namespace shellcontract
