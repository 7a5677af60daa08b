// `shellcontract run` as a user runs it: exit codes, messages, outputs written atomically and in
// the input's order (README "Exit codes", "Outputs").
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: temporary files of this process's own

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "shellcontract/mesh_io.hpp"
#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

class CliRun : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_run_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string mesh(const std::string& name) { return std::string(test::MESH_DIR) + "/" + name; }
  std::string out(const std::string& name) { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(CliRun, ContractsAndWritesMeshLogAndSummaryInInputOrder) {
  const auto r = run_cli({"run", mesh("ico2.off"), "-o", out("o.off"), "--frames", "20", "--log",
                          out("log.csv"), "--summary", out("s.json"), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  InputReport in_report, out_report;
  const Mesh in = read_input_mesh(mesh("ico2.off"), &in_report);
  const Mesh result = read_input_mesh(out("o.off"), &out_report);
  ASSERT_EQ(result.number_of_vertices(), in.number_of_vertices());
  ASSERT_EQ(result.number_of_faces(), in.number_of_faces());
  for (FaceIndex f : in.faces()) {
    std::vector<int> a, b;
    for (VertexIndex v : CGAL::vertices_around_face(in.halfedge(f), in)) a.push_back(int(v.idx()));
    for (VertexIndex v : CGAL::vertices_around_face(result.halfedge(f), result)) b.push_back(int(v.idx()));
    ASSERT_EQ(a, b) << "face " << f.idx();
  }
  EXPECT_LT(out_report.volume, in_report.volume) << "the shell contracted";
  std::ifstream log(out("log.csv"));
  std::string header, line;
  std::getline(log, header);
  EXPECT_EQ(header.rfind("frame,time,volume_ratio,", 0), 0u) << header;
  int rows = 0;
  while (std::getline(log, line)) ++rows;
  EXPECT_EQ(rows, 20);
  std::stringstream json;
  json << std::ifstream(out("s.json")).rdbuf();
  EXPECT_NE(json.str().find("\"frames_run\": 20"), std::string::npos) << json.str();
  // No temporary files left behind.
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir_)) files += e.is_regular_file();
  EXPECT_EQ(files, 3);
}

TEST_F(CliRun, BadInputIsExitCode2WithTheProblemNamedAndNoOutput) {
  struct Case {
    const char* file;
    const char* message;
  };
  for (const Case& c : {Case{"bad/open_sheet.off", "boundary"}, Case{"bad/nan.off", "finite"},
                        Case{"bad/truncated.off", "truncated"}, Case{"bad/empty.off", "empty"},
                        Case{"bad/nonmanifold_edge.off", "non-manifold edge"},
                        Case{"bad/nonmanifold_vertex.off", "non-manifold vertex"},
                        Case{"bad/garbage.off", "bad/garbage.off"},
                        Case{"bad/index_out_of_range.off", "out of range"}}) {
    const auto r = run_cli({"run", mesh(c.file), "-o", out("o.off"), "-q"});
    EXPECT_EQ(r.exit_code, 2) << c.file << ": " << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.file << ": " << r.output;
    EXPECT_FALSE(fs::exists(out("o.off"))) << c.file;
  }
}

TEST_F(CliRun, BadUsageIsExitCode1) {
  EXPECT_EQ(run_cli({"run", mesh("ico1.off")}).exit_code, 1);  // no -o
  EXPECT_EQ(run_cli({"run", mesh("ico1.off"), "-o", out("o.off"), "--solver", "magic"}).exit_code, 1);
  EXPECT_EQ(run_cli({"run", mesh("ico1.off"), "-o", out("o.off"), "--dt", "-1"}).exit_code, 1);
  EXPECT_EQ(run_cli({"run", mesh("ico1.off"), "-o", out("o.off"), "--no-such-option"}).exit_code, 1);
  const auto spec = run_cli(
      {"run", mesh("ico1.off"), "-o", out("o.off"), "--speculative-broad-phase", "maybe"});
  EXPECT_EQ(spec.exit_code, 1);
  EXPECT_NE(spec.output.find("auto | on | off"), std::string::npos) << spec.output;
  const auto r = run_cli({"run", mesh("ico1.off"), "-o", out("missing_dir/o.off"), "--frames", "1"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_FALSE(fs::exists(out("missing_dir")));
}

TEST_F(CliRun, BlowUpIsExitCode3AndTheLastGoodStateIsWritten) {
  const auto r = run_cli({"run", mesh("ico1.off"), "-o", out("o.off"), "--pressure", "1e6",
                          "--collisions", "off", "-q"});
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("last good state"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(out("o.off")));
}

TEST_F(CliRun, HelpListsTheOptions) {
  const auto r = run_cli({"run", "--help"});
  EXPECT_EQ(r.exit_code, 0);
  for (const char* opt : {"--pressure", "--frames", "--dt", "--solver", "--material", "--bending",
                          "--k-b", "--collisions", "--validate", "--aniso", "--log", "--summary"})
    EXPECT_NE(r.output.find(opt), std::string::npos) << opt;
}

// `bench error` with the order and thread rungs: the CSV has a row per (order, threads,
// iterations) rung with its order and thread count in the last two columns, and the coloured
// rungs' errors do not depend on the thread count; a bad order is a usage error (exit 1).
TEST_F(CliRun, BenchErrorHasOrderAndThreadRungs) {
  const auto r = run_cli({"bench", "error", mesh("ico2.off"), "--frames", "5", "--solver", "xpbd",
                          "--iterations", "1,5", "--substeps", "1", "--ref-substeps", "2",
                          "--ref-iterations", "5", "--orders", "both", "--threads", "1,2",
                          "--no-check", "--csv", out("e.csv"), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream csv(out("e.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_NE(line.find(",order,threads"), std::string::npos) << line;
  std::map<std::string, std::string> hausdorff;  // "order,threads,iterations" -> column 9
  int rungs = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> c;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) c.push_back(f);
    ASSERT_EQ(c.size(), 15u) << line;
    if (c[0] != "rung") continue;
    ++rungs;
    hausdorff[c[13] + "," + c[14] + "," + c[2]] = c[8];
  }
  EXPECT_EQ(rungs, 2 + 4);  // sequential x {1, 5}; coloured x {1, 2} threads x {1, 5}
  for (const char* it : {"1", "5"}) {
    ASSERT_EQ(hausdorff.count(std::string("coloured,1,") + it), 1u);
    EXPECT_EQ(hausdorff[std::string("coloured,1,") + it], hausdorff[std::string("coloured,2,") + it]);
  }
  const auto bad = run_cli({"bench", "error", mesh("ico2.off"), "--orders", "random", "-q"});
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("--orders"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace shellcontract
