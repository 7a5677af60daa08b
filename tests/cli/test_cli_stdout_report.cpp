// Commands whose product is what they print (`check --json > report.json`, `regions`, `repair
// --json`, `--version`): a write to stdout that fails (a file size limit as a batch system sets
// it, a full disk, stdout closed) must not end with exit 0, or a CI step takes an empty report for
// a pass (docs/cli.md, "Exit codes": an output that cannot be written is 1). And `bench error
// --plot` without --csv, with $TMPDIR naming a folder that is gone, falls back to /tmp as
// mkstemp-based tools do, instead of failing with exit 3 after every run. Its table keeps its
// columns apart.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "support/child_process.hpp"
#include "support/scratch_dir.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

/// Where the child's stdout goes.
enum class Stdout { File, FileOverLimit, Closed };

struct Ended {
  int status = 0;
  std::string err;  ///< its stderr
};

/// Runs the CLI with `args`, stdout as `how` says (to `out` for the files), stderr to a pipe (a
/// file would be under the size limit too), `env` set; SIGXFSZ at its default action, as a shell
/// starts a job (test::Child).
Ended run_cli(const std::vector<std::string>& args, Stdout how, const std::string& out,
              const std::vector<std::pair<std::string, std::string>>& env = {}) {
  test::ChildSpec spec = test::cli_child(args);
  spec.out = how == Stdout::Closed ? test::ChildOut::Closed : test::ChildOut::File;
  spec.out_file = out;
  if (how == Stdout::FileOverLimit) spec.file_size_limit = 0;
  spec.env = env;
  test::Child child(spec);
  Ended e;
  e.status = child.finish();
  e.err = child.output();
  return e;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

class CliStdoutReport : public test::ScratchDirTest {
 protected:
  CliStdoutReport() : ScratchDirTest("shellcontract_stdout_report_") {}
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  const std::string mesh_ = std::string(test::MESH_DIR) + "/ico1.off";
};

// The control: the report written, exit 0 (so the failures below are the write's, not the
// command's).
TEST_F(CliStdoutReport, ReportWrittenWholeExitsZero) {
  const Ended e = run_cli({"check", mesh_, "--json"}, Stdout::File, path("r.json"));
  EXPECT_TRUE(WIFEXITED(e.status) && WEXITSTATUS(e.status) == 0) << test::ending(e.status) << '\n'
                                                                 << e.err;
  const std::string report = read_file(path("r.json"));
  EXPECT_EQ(report.rfind("}\n"), report.size() - 2) << report;
}

TEST_F(CliStdoutReport, CommandsWhoseReportCannotBeWrittenExitOne) {
  const std::vector<std::vector<std::string>> commands{
      {"check", mesh_, "--json"}, {"check", mesh_}, {"regions", mesh_}, {"--version"}, {"--help"}};
  for (const Stdout how : {Stdout::FileOverLimit, Stdout::Closed}) {
    for (const auto& args : commands) {
      const Ended e = run_cli(args, how, path("r.out"));
      const std::string what =
          args[0] + (how == Stdout::Closed ? " with stdout closed" : " over the file size limit");
      EXPECT_TRUE(WIFEXITED(e.status) && WEXITSTATUS(e.status) == 1)
          << what << ": " << test::ending(e.status) << '\n'
          << e.err;
      EXPECT_NE(e.err.find("cannot write to standard output"), std::string::npos)
          << what << ": " << e.err;
    }
  }
}

// A plot is drawn whatever TMPDIR names (a missing folder here). It once fell back from such a
// TMPDIR to /tmp for its data file; the data is now inside gnuplot's script (no file at all).
TEST_F(CliStdoutReport, BenchPlotFallsBackFromAMissingTmpdir) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    if (std::getenv("SHELLCONTRACT_STRICT_TESTS") != nullptr) FAIL() << "gnuplot is not installed";
    GTEST_SKIP() << "gnuplot is not installed";
  }
  const std::string plot = path("plot.png");
  const Ended e = run_cli({"bench", "error", mesh_, "--frames", "2", "--iterations", "1",
                           "--substeps", "1", "--solver", "pbd", "--plot", plot, "-q"},
                          Stdout::File, path("table.txt"), {{"TMPDIR", path("gone")}});
  EXPECT_TRUE(WIFEXITED(e.status) && WEXITSTATUS(e.status) == 0) << test::ending(e.status) << '\n'
                                                                 << e.err;
  EXPECT_TRUE(std::filesystem::is_regular_file(plot)) << e.err;
}

// bench error's table is read by eye and by `awk`: each row has as many blank-separated fields
// as its header, also for a reference of six-digit iterations (whose count ran into the threads'
// column: "1100001").
TEST_F(CliStdoutReport, BenchErrorRowsHaveTheirHeadersFields) {
  const std::string cube = std::string(test::MESH_DIR) + "/cube.off";
  const Ended e = run_cli(
      {"bench", "error", cube, "--solver", "xpbd", "--frames", "1", "--iterations", "1",
       "--substeps", "1", "--ref-iterations", "100000", "--ref-substeps", "1", "--no-check", "-q"},
      Stdout::File, path("table.txt"));
  ASSERT_TRUE(WIFEXITED(e.status) && WEXITSTATUS(e.status) == 0) << test::ending(e.status) << '\n'
                                                                 << e.err;
  std::istringstream table(read_file(path("table.txt")));
  auto fields = [](const std::string& line) {
    std::istringstream words(line);
    std::size_t n = 0;
    for (std::string w; words >> w;) ++n;
    return n;
  };
  std::size_t header = 0, rows = 0;
  for (std::string line; std::getline(table, line);) {
    if (line.rfind("solver ", 0) == 0) {
      header = fields(line);
    } else if (line.empty()) {
      header = 0;
    } else if (header > 0) {
      EXPECT_EQ(fields(line), header) << line;
      ++rows;
    }
  }
  EXPECT_EQ(rows, 2u) << "a rung and its reference";
}

}  // namespace
}  // namespace shellcontract
