// The machine-readable outputs as an analysis script reads them: the summary's numbers in the
// shortest form that reads back (docs/cli.md), target_reached null when nothing was to be
// reached, and bench error's CSV recomputable, with PBD's dE_rel marked as not meaningful.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "shellcontract/options.hpp"
#include "support/cli_runner.hpp"
#include "support/scratch_dir.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

class CliOutputs : public test::ScratchDirTest {
 protected:
  CliOutputs() : ScratchDirTest("shellcontract_cli_outputs_") {}
  void SetUp() override {
    ScratchDirTest::SetUp();
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  }
  std::string mesh(const std::string& name) { return std::string(test::MESH_DIR) + "/" + name; }
  std::string out(const std::string& name) { return (dir_ / name).string(); }
  static std::string read(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
};

TEST_F(CliOutputs, SummaryNumbersAreShortestAndTargetReachedIsNullWithoutATarget) {
  // A blow-up (exit 3) with no target: "target_reached": true let it through a filter on the key.
  const auto r = run_cli({"run", mesh("ico2.off"), "-o", out("o.off"), "-n", "20", "-p", "1e6",
                          "--dt", "1", "--air-balance", "0", "--summary", out("s.json"), "-q"});
  ASSERT_EQ(r.exit_code, 3) << r.output;
  const std::string s = read(out("s.json"));
  EXPECT_NE(s.find("\"target_reached\": null"), std::string::npos) << s;
  // Every number (a value after a key, or in a list) is the shortest text of its double.
  const std::regex number(R"((?:: |\[|, )(-?[0-9][0-9.eE+-]*))");
  int numbers = 0;
  for (auto it = std::sregex_iterator(s.begin(), s.end(), number); it != std::sregex_iterator();
       ++it) {
    const std::string text = (*it)[1];
    EXPECT_EQ(text, shortest_text(std::strtod(text.c_str(), nullptr))) << text;
    ++numbers;
  }
  EXPECT_GT(numbers, 20);
}

TEST_F(CliOutputs, TheSummaryNamesTheInputFilesBytes) {
  // The summary named the input by the path as typed only: a rerun could not tell whether the
  // file there is the one the run read (review repro F2). Its size and FNV-1a, computed here
  // from the file's bytes by the published definition (offset basis 14695981039346656037, prime
  // 1099511628211), and its absolute path.
  const std::string in = mesh("ico2.off");
  const auto r =
      run_cli({"run", in, "-o", out("o.off"), "-n", "1", "-q", "--summary", out("s.json")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string bytes = read(in);
  std::uint64_t h = 14695981039346656037ull;
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  const std::string s = read(out("s.json"));
  EXPECT_NE(s.find("\"input_file\": {"), std::string::npos) << s;
  EXPECT_NE(s.find("\"path\": \"" + std::filesystem::absolute(in).string() + "\""),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("\"bytes\": " + std::to_string(bytes.size())), std::string::npos) << s;
  EXPECT_NE(s.find("\"fnv1a64\": \"" + std::string(hex) + "\""), std::string::npos) << s;
}

TEST_F(CliOutputs, AValidationThatPassedSaysSo) {
  // `--validate end` that found nothing said nothing: the verdict was only in the exit code and
  // the summary (review tasks F6). Without the check the line does not claim one.
  const auto checked =
      run_cli({"run", mesh("ico2.off"), "-o", out("o.off"), "-n", "2", "--validate", "end"});
  ASSERT_EQ(checked.exit_code, 0) << checked.output;
  EXPECT_NE(checked.output.find("frames, V/V0 = "), std::string::npos) << checked.output;
  EXPECT_NE(checked.output.find(", no new self-intersections (--validate)"), std::string::npos)
      << checked.output;
  const auto unchecked = run_cli({"run", mesh("ico2.off"), "-o", out("o.off"), "-n", "2"});
  ASSERT_EQ(unchecked.exit_code, 0) << unchecked.output;
  EXPECT_EQ(unchecked.output.find("self-intersections"), std::string::npos) << unchecked.output;
}

TEST_F(CliOutputs, BenchErrorCsvRecomputesAndPbdEnergyErrorIsNotMeaningful) {
  const auto r = run_cli({"bench", "error", mesh("ico2.off"), "-n", "10", "--iterations", "1,5",
                          "--substeps", "1", "--csv", out("be.csv"), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("dE_rel of pbd n/a"), std::string::npos) << r.output;
  std::istringstream csv(read(out("be.csv")));
  std::string line;
  std::getline(csv, line);  // header
  std::vector<std::vector<std::string>> rows;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream cs(line);
    std::string cell;
    while (std::getline(cs, cell, ',')) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 15u) << line;
    rows.push_back(cells);
  }
  // Columns: 0 row_type, 1 solver, 10 volume_ratio, 11 volume_error, 12 energy_error.
  std::map<std::string, double> reference_volume;
  for (const auto& c : rows)
    if (c[0] == "reference") reference_volume[c[1]] = std::strtod(c[10].c_str(), nullptr);
  ASSERT_EQ(reference_volume.size(), 2u);
  int rungs = 0;
  for (const auto& c : rows) {
    if (c[0] != "rung") continue;
    ++rungs;
    // Full precision: the volume error is recomputed, to the bit, from the volumes written.
    const double v = std::strtod(c[10].c_str(), nullptr);
    EXPECT_EQ(std::strtod(c[11].c_str(), nullptr), std::abs(v - reference_volume[c[1]])) << c[11];
    // PBD's reference (500 sweeps) holds the shell nearly rigid: no energy to compare with.
    if (c[1] == "pbd")
      EXPECT_EQ(c[12], "nan");
    else
      EXPECT_LT(std::strtod(c[12].c_str(), nullptr), 10.0) << c[12];
  }
  EXPECT_EQ(rungs, 4);
  for (const auto& c : rows) {
    if (c[0] == "reference_check" && c[1] == "pbd") {
      EXPECT_EQ(c[12], "nan");
    }
  }
}

}  // namespace
}  // namespace shellcontract
