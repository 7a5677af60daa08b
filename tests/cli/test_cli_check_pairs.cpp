// `check` and `run --validate` on a mesh whose parts all pass through each other (review
// complexity F7): its self-intersecting pairs number the square of its faces, and `check --json`
// printed every one while run --validate held them all.
// Now check counts them all and lists the first CHECK_LISTED_PAIRS in face order, saying the
// list is truncated; an INPUT with more pairs of its own than baseline_pair_limit is refused by
// run --validate and check --against (exit 2), which would have to hold them.
#include <gtest/gtest.h>

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "shellcontract/validation.hpp"
#include "support/cgal_mesh.hpp"
#include "support/cli_runner.hpp"
#include "support/crossing_needles.hpp"
#include "support/scratch_dir.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

using test::run_cli;
using test::RunResult;

class CliCheckPairs : public test::ScratchDirTest {
 protected:
  CliCheckPairs() : ScratchDirTest("shellcontract_check_pairs_") {}
  void SetUp() override {
    if (!std::filesystem::exists(SHELLCONTRACT_CLI_PATH))
      GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
    ScratchDirTest::SetUp();
  }
  std::string needles(int count) const {
    const std::string path = (dir_ / ("needles_" + std::to_string(count) + ".off")).string();
    test::write_off(test::crossing_needles(count), path);
    return path;
  }
};

/// The text between `key` and the next `end` (npos: absent).
std::string after(const std::string& text, const std::string& key, const std::string& end) {
  const std::size_t at = text.find(key);
  if (at == std::string::npos) return "absent";
  const std::size_t from = at + key.size();
  return text.substr(from, text.find(end, from) - from);
}

/// Face pairs as index pairs, to compare with a JSON list read back.
using IndexPairs = std::vector<std::array<std::size_t, 2>>;
IndexPairs indices(const std::vector<FacePair>& pairs) {
  IndexPairs out;
  for (const FacePair& p : pairs) out.push_back({p.first.idx(), p.second.idx()});
  return out;
}

TEST_F(CliCheckPairs, JsonCountsEveryPairAndListsTheFirstThousand) {
  const test::TriMesh m = test::crossing_needles(40);
  const std::string path = needles(40);
  const Mesh mesh = test::to_surface_mesh(m);
  const std::vector<FacePair> all = self_intersecting_pairs(mesh, positions_from_mesh(mesh));
  ASSERT_GT(all.size(), 2 * CHECK_LISTED_PAIRS);

  const RunResult j = run_cli({"check", path, "--json"});
  EXPECT_EQ(j.exit_code, 0) << j.output.substr(0, 2000);
  EXPECT_EQ(after(j.output, "\"self_intersecting_pairs\": ", ","), std::to_string(all.size()));
  const std::vector<FacePair> first(all.begin(), all.begin() + CHECK_LISTED_PAIRS);
  EXPECT_EQ(
      nlohmann::json::parse(after(j.output, "\"self_intersections\": ", ",\n")).get<IndexPairs>(),
      indices(first));
  EXPECT_EQ(after(j.output, "\"self_intersections_truncated\": ", ",\n"), "true");
  // The report's size no longer grows with the pairs: the list is about 14 bytes a pair.
  EXPECT_LT(j.output.size(), 20 * CHECK_LISTED_PAIRS);

  const RunResult t = run_cli({"check", path});
  EXPECT_EQ(t.exit_code, 0) << t.output.substr(0, 2000);
  std::string listed = " (";
  for (std::size_t i = 0; i < 20; ++i)
    listed += (i ? " " : "") + std::to_string(all[i].first.idx()) + "-" +
              std::to_string(all[i].second.idx());
  EXPECT_NE(t.output.find("\nself_intersecting_pairs: " + std::to_string(all.size()) + listed +
                          " ...)\n"),
            std::string::npos)
      << t.output;
}

TEST_F(CliCheckPairs, AMeshWithFewPairsIsListedWhole) {
  const RunResult j =
      run_cli({"check", std::string(test::MESH_DIR) + "/zero_area_face.off", "--json"});
  EXPECT_EQ(j.exit_code, 0) << j.output;
  EXPECT_NE(j.output.find("\"self_intersecting_pairs\": 2,\n"
                          "  \"self_intersections\": [[0, 1], [0, 12]],\n"
                          "  \"self_intersections_truncated\": false,\n"),
            std::string::npos)
      << j.output;
}

// Past baseline_pair_limit (1,000,000 pairs for a mesh this small): the two commands that keep
// an input's own pairs refuse it, naming the bound, after counting no further than it; `check`
// on its own still counts them all.
TEST_F(CliCheckPairs, AnInputWithMorePairsThanTheBaselineHoldsIsRefused) {
  const std::string path = needles(600);
  const std::string bound = "has more than " + std::to_string(BASELINE_PAIRS) +
                            " self-intersecting face pairs of its own";

  const RunResult against = run_cli({"check", path, "--against", path});
  EXPECT_EQ(against.exit_code, 2) << against.output;
  EXPECT_NE(against.output.find(path + " " + bound), std::string::npos) << against.output;
  EXPECT_NE(against.output.find("without --against"), std::string::npos) << against.output;

  const std::string out = (dir_ / "out.off").string();
  const RunResult run = run_cli(
      {"run", path, "-o", out, "--frames", "1", "--collisions", "off", "--validate", "end"});
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("the input " + bound), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("run without --validate"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(out));

  const RunResult alone = run_cli({"check", path, "--json"});
  EXPECT_EQ(alone.exit_code, 0) << alone.output.substr(0, 2000);
  EXPECT_GT(std::stoull(after(alone.output, "\"self_intersecting_pairs\": ", ",")), BASELINE_PAIRS);
  EXPECT_EQ(after(alone.output, "\"self_intersections_truncated\": ", ",\n"), "true");
}

}  // namespace
}  // namespace shellcontract
