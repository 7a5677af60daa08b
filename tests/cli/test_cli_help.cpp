// `shellcontract run --help` is grouped by task and shows the defaults that apply: every option of
// the table sits in a named group (an option added without one would land under "other" and fail
// here), and the options whose table default the default solver replaces say so.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: temporary files of this process's own

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "shellcontract/options.hpp"
#include "support/cli_runner.hpp"
#include "support/summary_text.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

/// The text of `help` from the heading `title` to the next blank line.
std::string section(const std::string& help, const std::string& title) {
  const std::size_t at = help.find("\n" + title + ":\n");
  if (at == std::string::npos) return {};
  const std::size_t end = help.find("\n\n", at + 1);
  return help.substr(at, end == std::string::npos ? std::string::npos : end - at);
}

TEST(CliHelp, RunHelpIsGroupedByTaskWithEveryOptionInAGroup) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  const auto r = run_cli({"run", "--help"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("\nother:\n"), std::string::npos) << "an option has no group";
  for (const char* title : {"outputs and general", "how much it contracts", "material", "bending",
                            "solver", "local contraction (regions that sink in)", "collisions"})
    EXPECT_FALSE(section(r.output, title).empty()) << title;
  // One option per group, checked to sit in its own group's section.
  EXPECT_NE(section(r.output, "how much it contracts").find("--target-volume"), std::string::npos);
  EXPECT_NE(section(r.output, "material").find("--young"), std::string::npos);
  EXPECT_NE(section(r.output, "bending").find("--k-b"), std::string::npos);
  EXPECT_NE(section(r.output, "solver").find("--iterations"), std::string::npos);
  EXPECT_NE(section(r.output, "local contraction (regions that sink in)").find("--regions"),
            std::string::npos);
  EXPECT_NE(section(r.output, "collisions").find("--delta"), std::string::npos);
  EXPECT_NE(section(r.output, "outputs and general").find("--summary"), std::string::npos);
  // Every option of the table is shown once.
  for (const OptionSpec& o : run_option_table())
    EXPECT_NE(r.output.find("--" + o.name + " "), std::string::npos) << o.name;
}

TEST(CliHelp, RunHelpMarksTheDerivedDefaults) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  const auto r = run_cli({"run", "--help"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Under the default solver (xpbd) mu, lambda and k_B come from --young and --thickness: the
  // table's pbd defaults (1, 1, 0.01) would be wrong to show as what applies, and as wrong to
  // leave out, since they apply elsewhere (under pbd, for example):
  // RunHelpDerivedDefaultsAreWhatARunResolves checks them against runs.
  for (const char* opt :
       {"--mu MU (=derived from --young, else 1)", "--lambda LAMBDA (=derived from --young, else 1)",
        "--k-b KB (=derived from --young, else 0.01)", "--damping D (=0.1, pbd: 0.2)"})
    EXPECT_NE(r.output.find(opt), std::string::npos) << opt;
  EXPECT_EQ(r.output.find("--mu MU (=1)"), std::string::npos);
}

using test::summary_option;

TEST(CliHelp, RunHelpDerivedDefaultsAreWhatARunResolves) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  const fs::path dir =
      fs::temp_directory_path() / ("shellcontract_cli_help_defaults_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto resolved = [&](std::vector<std::string> extra) {
    std::vector<std::string> args{"run", std::string(test::MESH_DIR) + "/ico2.off", "-o",
                                  (dir / "o.off").string(), "-n", "0", "-q", "--summary",
                                  (dir / "s.json").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    std::map<std::string, std::string> v;
    for (const char* key : {"mu", "lambda", "k-b", "damping"}) v[key] = summary_option(dir / "s.json", key);
    return v;
  };
  // The default run: derived from the shell material (none of the table's values).
  const auto xpbd = resolved({});
  EXPECT_NE(xpbd.at("mu"), "1");
  EXPECT_NE(xpbd.at("lambda"), "1");
  EXPECT_NE(xpbd.at("k-b"), "0.01");
  EXPECT_EQ(xpbd.at("damping"), "0.1");
  // "else": the table's values.
  const auto pbd = resolved({"--solver", "pbd"});
  EXPECT_EQ(pbd, (std::map<std::string, std::string>{
                     {"mu", "1"}, {"lambda", "1"}, {"k-b", "0.01"}, {"damping", "0.2"}}));
  const auto mooney = resolved({"--material", "mooney-rivlin"});
  // Recorded empty: Mooney-Rivlin's membrane takes c10 and c01, not the table's mu (review9 D5).
  EXPECT_EQ(mooney.at("mu"), "");
  EXPECT_EQ(mooney.at("k-b"), "0.01");
  EXPECT_EQ(resolved({"--bending", "isometric"}).at("k-b"), "0.01");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace shellcontract
