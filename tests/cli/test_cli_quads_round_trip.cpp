// A quad OBJ written by `run` is read back by the tool itself: `check OUT --against IN` verifies it
// and `run OUT` goes on from it. The result's quads are the input's, with corners moved by the
// simulation, which bends them along the diagonal of their split; a strong contraction folds some
// past the point where a fan from any corner has a triangle facing against the quad's normal, and
// the reader refused them ("non-convex polygon"). It now splits such a quad along its least folded
// diagonal (src/mesh/polygon_split.hpp).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace {

using shellcontract::test::RunResult;
using shellcontract::test::run_cli;
namespace fs = std::filesystem;

class CliQuadsRoundTrip : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
    dir_ = fs::temp_directory_path() / ("shellcontract_quads_round_trip_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

/// A UV sphere of nu x nv cells, as a glTF export gives it: one vertex per texture coordinate (the
/// seam's vertices are copies), quads between the pole rows, triangles at the poles, two materials.
std::string seam_split_quad_sphere(int nu, int nv) {
  const double pi = std::acos(-1.0);
  std::map<std::pair<int, int>, int> id;
  std::ostringstream v, vt, f;
  v.precision(17);
  vt.precision(17);
  int count = 0;
  const auto vertex = [&](int i, int j) {
    const auto [it, fresh] = id.emplace(std::make_pair(i, j), count + 1);
    if (!fresh) return it->second;
    ++count;
    const double th = pi * j / nv, ph = 2.0 * pi * (i % nu) / nu;
    const double s = (j == 0 || j == nv) ? 0.0 : std::sin(th);
    const double z = j == 0 ? 1.0 : j == nv ? -1.0 : std::cos(th);
    // + 0.0: the pole's copies at 0.0, not -0.0 (the seam weld welds bitwise-equal positions only).
    v << "v " << s * std::cos(ph) + 0.0 << ' ' << s * std::sin(ph) + 0.0 << ' ' << z << '\n';
    vt << "vt " << static_cast<double>(i) / nu << ' ' << 1.0 - static_cast<double>(j) / nv << '\n';
    return it->second;
  };
  const int cells = nu * nv;
  int k = 0;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i, ++k) {
      // A quad's corners (i, j), (i, j + 1), (i + 1, j + 1), (i + 1, j); a pole triangle drops one.
      std::vector<int> c{vertex(i, j), vertex(i, j + 1)};
      if (j != nv - 1) c.push_back(vertex(i + 1, j + 1));
      if (j != 0) c.push_back(vertex(i + 1, j));
      if (k == 0) f << "usemtl red\n";
      if (k == cells / 2) f << "usemtl blue\n";
      f << 'f';
      for (const int x : c) f << ' ' << x << '/' << x;
      f << '\n';
    }
  return "mtllib seam.mtl\n" + v.str() + vt.str() + f.str();
}

TEST_F(CliQuadsRoundTrip, AStronglyContractedQuadObjIsCheckedAgainstItsInputAndRunAgain) {
  const std::string in = file("seam.obj"), out = file("out.obj"), again = file("again.obj");
  std::ofstream(in) << seam_split_quad_sphere(12, 8);
  std::ofstream(file("seam.mtl")) << "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n";
  const RunResult r = run_cli({"run", in, "-o", out, "--target-volume", "0.15", "-n", "60", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;

  // The result keeps the input's quads (line for line, but the positions).
  std::ifstream a(in), b(out);
  std::size_t quads = 0;
  for (std::string la, lb; std::getline(a, la) && std::getline(b, lb);)
    if (la.rfind("f ", 0) == 0) {
      EXPECT_EQ(la, lb);
      quads += std::count(la.begin(), la.end(), ' ') == 4;
    }
  EXPECT_EQ(quads, 12u * 6u);

  const RunResult c = run_cli({"check", out, "--against", in});
  EXPECT_EQ(c.exit_code, 0) << c.output;
  EXPECT_EQ(c.output.find("non-convex polygon"), std::string::npos) << c.output;
  const RunResult r2 = run_cli({"run", out, "-o", again, "-n", "2", "-q"});
  EXPECT_EQ(r2.exit_code, 0) << r2.output;
  EXPECT_TRUE(fs::exists(again));
}

}  // namespace
