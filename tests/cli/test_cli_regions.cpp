// Regions on the command line: `run --regions FILE` naming an empty file, `regions` with or
// without -o, its --region-at forms and table,
// and the help texts that describe them; `bench`'s help and `bench ccd`'s times.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: temporary files of this process's own

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

class CliRegions : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_regions_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string mesh(const std::string& name) { return std::string(test::MESH_DIR) + "/" + name; }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }
  /// The text with every run of blanks and line breaks as one space (help text wraps anywhere).
  static std::string squeezed(const std::string& text) {
    std::string s;
    for (char c : text)
      if (c != ' ' && c != '\n' && c != '\t') s += c;
      else if (!s.empty() && s.back() != ' ') s += ' ';
    return s;
  }
  fs::path dir_;
};

// meshes/cube.off: 8 vertices, 12 triangles, corners at 0 and 1.
TEST_F(CliRegions, RunWarnsNamingARegionFileThatListsNoRegion) {
  std::ofstream(path("empty.txt")) << "# only a comment\n\n";
  const auto r = run_cli({"run", mesh("cube.off"), "--regions", path("empty.txt"), "-n", "2", "-q", "-o", path("o.off")});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "warning: --regions " + path("empty.txt") + ": the file lists no region")) << r.output;
}

// Face lists on the coarse cube whose cap, closed by one fan from the rim's centroid, encloses
// the shell between opposite faces: "0 3" (a bottom and a top triangle) and the bottom with top
// faces blew up at step 1 (exit 3); "0 1 2 3 4 5" (bottom, front, top: one piece, every vertex on
// its rim) at step 2. Each runs now: a region in pieces sinks piece by piece (flat pieces are
// left alone, with the warning), and the volume projection moves no vertex farther than its
// dimple's size in a step. The result is finite and has no new self-intersection.
TEST_F(CliRegions, CubeFaceListsOnOppositeFacesRunWithoutBlowUp) {
  const std::vector<std::pair<std::string, bool>> lists = {
      {"0 3", true},          {"0 1 2", true},    {"0 1 2 3", true}, {"0 1 2 3 4", false},
      {"0 1 2 3 4 5", false}, {"0 1 4 5", false}, {"0 2", true},     {"2 3", true}};
  const std::vector<std::vector<std::string>> variants = {
      {}, {"--region-shrink", "0.1"}, {"--dimple", "volume"}, {"--solver", "pbd"}};
  for (const auto& [list, flat] : lists) {
    std::ofstream(path("f.txt")) << list << "\n";
    for (const std::vector<std::string>& variant : variants) {
      std::vector<std::string> args = {
          "run", mesh("cube.off"), "-o",  path("o.off"), "-n",         "5", "-q", "-p",
          "0",   "--validate",     "end", "--regions",   path("f.txt")};
      args.insert(args.end(), variant.begin(), variant.end());
      const std::string what = "\"" + list + "\" " + (variant.empty() ? "" : variant[0]);
      const auto r = run_cli(args);
      ASSERT_EQ(r.exit_code, 0) << what << ": " << r.output;
      // Every piece flat: the run says the region has no cap to sink.
      EXPECT_EQ(has(r.output, "1 of 1 regions are flat or dented at rest"), flat)
          << what << ": " << r.output;
      std::ifstream off(path("o.off"));
      std::string header;
      int vertices = 0, faces = 0, edges = 0;
      off >> header >> vertices >> faces >> edges;
      ASSERT_EQ(vertices, 8) << what;
      for (int i = 0; i < 3 * vertices; ++i) {
        double c = 0.0;
        ASSERT_TRUE(off >> c) << what;
        EXPECT_TRUE(std::isfinite(c) && std::abs(c) < 10.0) << what << ": " << c;
      }
    }
  }
}

TEST_F(CliRegions, RunSaysItsRegionsCameFromTheGivenPoints) {
  const auto r = run_cli({"run", mesh("ico2.off"), "--region-at", "0,0,2", "-n", "2", "-o", path("o.off")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "regions: 1 regions grown at the --region-at points")) << r.output;
  EXPECT_FALSE(has(r.output, "selected by curvature")) << r.output;
}

// The cap finder's shape tests do nothing for the tip finder: refused, as --region-at is, where
// they had passed without a word (the same face list as without them). With caps they are taken.
TEST_F(CliRegions, CapShapeOptionsAreRefusedWithTheTipFinder) {
  for (const char* option : {"--fit-tolerance", "--min-cap-angle", "--contrast"}) {
    const auto r = run_cli({"regions", mesh("ico2.off"), "--method", "tips", option, "5"});
    EXPECT_EQ(r.exit_code, 1) << option << ": " << r.output;
    EXPECT_TRUE(
        has(r.output, std::string(option) +
                          " shapes the cap finder's caps; it does not apply with --method tips"))
        << r.output;
    EXPECT_EQ(run_cli({"regions", mesh("ico2.off"), option, "5"}).exit_code, 0) << option;
  }
}

TEST_F(CliRegions, RegionsWithoutOutputPrintsTheTableAndWritesTheFaceList) {
  auto r = run_cli({"regions", mesh("bumpy_sphere.off")});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "  id  centre")) << r.output;
  EXPECT_FALSE(has(r.output, "wrote:")) << r.output;
  r = run_cli({"regions", mesh("bumpy_sphere.off"), "--face-list", path("f.txt")});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(path("f.txt")));
  EXPECT_TRUE(has(r.output, "wrote: " + path("f.txt"))) << r.output;
  // The output checks still hold for what is written: the face list cannot be the input.
  r = run_cli({"regions", mesh("bumpy_sphere.off"), "--face-list", mesh("bumpy_sphere.off")});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  r = run_cli({"regions", mesh("bumpy_sphere.off"), "-o", path("r.off")});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_FALSE(fs::exists(path("r.off")));
}

TEST_F(CliRegions, StageTimesArePrintedOnlyWhenAskedFor) {
  auto r = run_cli({"regions", mesh("bumpy_sphere.off"), "--stage-times"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::vector<std::string> stages;
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("stage ", 0) == 0) stages.push_back(line.substr(6, line.find(':') - 6));
  EXPECT_EQ(stages, (std::vector<std::string>{"curvature", "smoothing", "free growth",
                                              "ranked growth", "parts", "shape"}))
      << r.output;
  r = run_cli({"regions", mesh("bumpy_sphere.off")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(has(r.output, "stage ")) << r.output;
}

TEST_F(CliRegions, RegionsTakesTheRegionAtFormsOfRun) {
  auto r = run_cli({"regions", mesh("cube.off"), "--region-at=2,2,2;-1,-1,-1"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "regions: 2\n")) << r.output;
  r = run_cli({"regions", mesh("cube.off"), "--region-at", "2,2"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "--region-at: '2,2' is not a point X,Y,Z")) << r.output;
}

TEST_F(CliRegions, AFallbackRegionShowsNoSphere) {
  // At a cube's corner no convex sphere fits: the corner's one-ring, with no centre to show.
  const auto r = run_cli({"regions", mesh("cube.off"), "--region-at", "2,2,2"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(has(r.output, "+0, +0, +0")) << r.output;
  const std::size_t row = r.output.find("\n   0  ");
  ASSERT_NE(row, std::string::npos) << r.output;
  EXPECT_EQ(r.output.substr(row + 7, 1), "-") << r.output;
}

TEST_F(CliRegions, ARegionAtPointFarFromTheSurfaceWarnsAndTheTableShowsTheSurfacePointTaken) {
  // bumpy_sphere: radius 0.5 with bumps. (0, 0, 3) is far above it; before, no word.
  auto r = run_cli({"regions", mesh("bumpy_sphere.off"), "--region-at=0,0,3"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "warning: the 1st --region-at point (0, 0, 3) is ")) << r.output;
  // Under the region's row: "at X, Y, Z (D from the point given)", the surface point nearest to
  // (0, 0, 3) and its distance from it, to the 4 digits shown.
  const std::size_t at = r.output.find("\n      at ");
  ASSERT_NE(at, std::string::npos) << r.output;
  std::istringstream line(r.output.substr(at + 10));
  double px = 0, py = 0, pz = 0, d = 0;
  char comma = 0, paren = 0;
  line >> px >> comma >> py >> comma >> pz >> paren >> d;
  ASSERT_TRUE(line) << r.output;
  const double radius = std::sqrt(px * px + py * py + pz * pz);
  EXPECT_GE(radius, 0.5 - 1e-3) << r.output;  // on the sphere or a bump, not inside
  EXPECT_NEAR(d, std::sqrt(px * px + py * py + (3 - pz) * (3 - pz)), 2e-3) << r.output;
  EXPECT_NEAR(d, 3 - radius, 0.15) << r.output;  // the nearest point lies near the top
  // A point on the surface: a row with its surface point, no warning.
  r = run_cli(
      {"regions", mesh("bumpy_sphere.off"), "--region-at=-0.2628655560595668,0.42532540417602,0"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(has(r.output, "warning")) << r.output;
  // To 1e-5 of the diagonal (about 1.9), trailing zeros dropped.
  EXPECT_TRUE(has(r.output, "\n      at -0.26287, +0.42533, +0 (0 from the point given)\n"))
      << r.output;
  // run names it too, on stderr and in the summary's warnings.
  r = run_cli({"run", mesh("bumpy_sphere.off"), "--region-at=0,0,3", "-n", "1", "-q", "-o",
               path("o.off"), "--summary", path("s.json")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "warning: the 1st --region-at point (0, 0, 3) is ")) << r.output;
  std::ifstream in(path("s.json"));
  const std::string summary((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(has(summary, "the 1st --region-at point (0, 0, 3) is ")) << summary;
}

TEST_F(CliRegions, MaxCompactnessBelowOneIsAThreshold) {
  // A cap on a sphere is below 1 (a hemisphere 0.5), so a bound below 1 must be accepted.
  auto r = run_cli({"regions", mesh("bumpy_sphere.off"), "--max-compactness", "0.5"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = run_cli({"regions", mesh("bumpy_sphere.off"), "--max-compactness", "0"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "--max-compactness 0: must be a finite number > 0")) << r.output;
  r = run_cli({"regions", mesh("bumpy_sphere.off"), "--max-compactness", "-1"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "--max-compactness -1: must be a finite number > 0")) << r.output;
  for (const char* bad : {"nan", "inf"}) {  // no number in the grammar every command reads
    r = run_cli({"regions", mesh("bumpy_sphere.off"), "--max-compactness", bad});
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(has(r.output, std::string("--max-compactness: '") + bad + "' is not a number"))
        << bad << ": " << r.output;
  }
  r = run_cli({"regions", "--help"});
  EXPECT_TRUE(has(squeezed(r.output), "1 = a flat disc, 0.5 = a hemisphere")) << r.output;
}

TEST_F(CliRegions, HelpTextsDescribeTheStrengthColumnAndTheExitCodes) {
  auto r = run_cli({"run", "--help"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(squeezed(r.output), "strength 'S:' in [0, 1]")) << r.output;
  EXPECT_TRUE(has(r.output, "2 bad input (mesh, face list")) << r.output;
  EXPECT_FALSE(has(r.output, "2 bad input mesh")) << r.output;
  EXPECT_TRUE(has(r.output, "130 interrupted")) << r.output;  // the code a Ctrl-C'd run returns
  r = run_cli({"regions", "--help"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(squeezed(r.output), "'S: ids'")) << r.output;
  r = run_cli({"--help"});
  EXPECT_FALSE(has(r.output, "2 bad input mesh")) << r.output;
  EXPECT_TRUE(has(r.output, "130 interrupted")) << r.output;
}

// The paper's k_A = kappa_A mu_A sqrt(face rest area): --k-a had no upper bound, so --k-a 1e300
// with --mu-a 1e100 made k_A infinite and the first step's positions non-finite (exit 3).
// kappa_A is held to the stiffnesses' bound, 1e100, and refused as bad usage above it; the
// region options' other bad values (NaN, inf, negative, zero where it means nothing) are refused.
TEST_F(CliRegions, RunRefusesRegionOptionsOutOfRange) {
  const std::vector<std::vector<std::string>> bad = {
      {"--k-a", "1e300", "--mu-a", "1e100"}, {"--k-a", "nan"},        {"--k-a", "-1"},
      {"--mu-a", "inf"},                      {"--mu-a", "1e200"},      {"--region-shrink", "nan"},
      {"--region-shrink", "1.5"},             {"--region-max-area", "0"}, {"--region-max-area", "inf"},
      {"--fiber-target", "0"},                {"--fiber", "0,0,0"},     {"--fiber", "nan,0,1"},
      {"--region-at", "inf,0,0"}};
  for (const std::vector<std::string>& options : bad) {
    std::vector<std::string> args = {"run", mesh("bumpy_sphere.off"), "-o", path("o.off"), "-n", "2", "-q",
                                     "--aniso", "arap", "--solver", "pbd", "--inward", "projection"};
    args.insert(args.end(), options.begin(), options.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << options[0] << ' ' << options[1] << ": " << r.output;
    EXPECT_TRUE(has(r.output, options[0])) << r.output;
    EXPECT_FALSE(fs::exists(path("o.off"))) << options[0] << ' ' << options[1];
    fs::remove(path("o.off"));
  }
  const auto fine = run_cli({"run", mesh("bumpy_sphere.off"), "-o", path("o.off"), "-n", "2", "-q", "--aniso", "arap",
                             "--solver", "pbd", "--inward", "projection", "--k-a", "1e100", "--mu-a", "1e100"});
  EXPECT_EQ(fine.exit_code, 0) << fine.output;
}

TEST_F(CliRegions, BenchHelpShowsItsSubcommands) {
  const auto r = run_cli({"bench", "--help"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "bench ccd") && has(r.output, "bench error")) << r.output;
}

// `bench ccd` printed a mean time per query above the maximum (--repeat 1: the mean of a cold
// pass, the maximum of warm runs). Both are now of the same times and printed alike, so neither
// the table nor --json can show a mean above the maximum, whatever the times.
TEST_F(CliRegions, BenchCcdShowsNoMeanTimeAboveTheMaximum) {
  fs::create_directories(dir_ / "q");
  std::ofstream queries(dir_ / "q" / "vertex-face.csv");
  for (int row = 0; row < 3 * 8; ++row)  // three queries of eight rows: x/2^60, 3/4, -1
    queries << row % 8 << ",1152921504606846976,3,4,-1,1,0\n";
  queries.close();
  for (const char* repeat : {"1", "3"}) {
    const auto r = run_cli(
        {"bench", "ccd", "--queries", path("q"), "--repeat", repeat, "--json", path("r.json")});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    // The file's row of the table ends with mean_us and max_us.
    std::istringstream lines(r.output);
    std::string line, row;
    while (std::getline(lines, line))
      if (has(line, "vertex-face.csv")) row = line;
    std::istringstream words(row);
    std::vector<std::string> cells;
    for (std::string w; words >> w;) cells.push_back(w);
    ASSERT_GE(cells.size(), 2u) << r.output;
    EXPECT_GE(std::stod(cells.back()), std::stod(cells[cells.size() - 2]))
        << "--repeat " << repeat << ": " << row;
    std::ifstream json(path("r.json"));
    const std::string text((std::istreambuf_iterator<char>(json)),
                           std::istreambuf_iterator<char>());
    const auto number = [&](const std::string& key) {
      const std::size_t at = text.find("\"" + key + "\": ");
      return at == std::string::npos ? -1.0 : std::stod(text.substr(at + key.size() + 4));
    };
    ASSERT_GE(number("mean_us"), 0.0) << text;
    EXPECT_GE(number("max_us"), number("mean_us")) << "--repeat " << repeat << ": " << text;
  }
}

/// The three numbers of "X, Y, Z" at `text`'s start, as written ("+512345.07123").
std::vector<std::string> printed_point(const std::string& text) {
  std::vector<std::string> out;
  std::size_t at = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t end = text.find_first_of(", (", at);
    out.push_back(text.substr(at, end - at));
    at = text.find_first_not_of(", ", end);
  }
  return out;
}

// A mesh far from the origin (bumpy_sphere, diagonal 1.9, moved to (512345, 5412345, 250)): the
// `at` point under a --region-at row, given back as --region-at, is on the surface and grows the
// same region; the regions' centres differ in print as they do. Before, both were written to 4
// significant digits ("+5.123e+05, +5.412e+06, +250.7"): given back, that point lay 347 units from
// the mesh, and the regions' centres were all one.
TEST_F(CliRegions, APrintedPointGivenBackGrowsTheSameRegionFarFromTheOrigin) {
  {
    std::ifstream in(mesh("bumpy_sphere.off"));
    std::ofstream out(path("far.off"));
    std::string line;
    std::getline(in, line);
    out << line << '\n';  // OFF
    int nv = -1;
    while (nv < 0 && std::getline(in, line))
      if (!line.empty() && line[0] != '#') {
        out << line << '\n';
        nv = std::stoi(line);
      }
    out.precision(17);
    for (int i = 0; i < nv; ++i) {
      double x = 0, y = 0, z = 0;
      in >> x >> y >> z;
      out << x + 512345.0 << ' ' << y + 5412345.0 << ' ' << z + 250.0 << '\n';
    }
    out << in.rdbuf();  // the faces
  }
  auto r = run_cli({"regions", path("far.off"), "--region-at=512345.0,5412345.0,250.6",
                    "--face-list", path("given.txt")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::size_t at = r.output.find("\n      at ");
  ASSERT_NE(at, std::string::npos) << r.output;
  const std::vector<std::string> p = printed_point(r.output.substr(at + 10));
  const std::string back = p[0] + "," + p[1] + "," + p[2];
  r = run_cli({"regions", path("far.off"), "--region-at=" + back, "--face-list", path("back.txt")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(has(r.output, "warning")) << back << '\n' << r.output;
  at = r.output.find("\n      at ");
  ASSERT_NE(at, std::string::npos) << r.output;
  // On the surface to the precision printed: 1e-5 of the diagonal.
  const std::size_t paren = r.output.find('(', at);
  EXPECT_LT(std::stod(r.output.substr(paren + 1)), 1e-4) << r.output;
  auto read = [](const std::string& f) {
    std::ifstream in(f);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  EXPECT_EQ(read(path("back.txt")), read(path("given.txt"))) << back;

  // The automatic regions (three bumps and more): no two centres print alike.
  r = run_cli({"regions", path("far.off")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::vector<std::string> centres;
  for (std::size_t row = r.output.find("\n   0  "); row != std::string::npos;
       row = r.output.find("\n   " + std::to_string(centres.size()) + "  ", row + 1))
    centres.push_back(r.output.substr(row + 7, r.output.find("  ", row + 8) - row - 7));
  ASSERT_GE(centres.size(), 3u) << r.output;
  for (std::size_t i = 0; i < centres.size(); ++i)
    for (std::size_t j = i + 1; j < centres.size(); ++j)
      EXPECT_NE(centres[i], centres[j]) << r.output;
}

}  // namespace
}  // namespace shellcontract
