// The contact distance a mesh allows (sim/contact_distance.hpp): a given --delta above an eighth of
// the mean edge is refused (it had swelled eight.off to 9.6 times its volume under a compressing
// pressure, exit 0), and pairs closer than delta at rest without touching, which the collision
// step holds in place, are named in a warning (a 1e-4 thin box had stayed bit for bit at rest,
// silently); --delta auto goes below their gap, and the box moves.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/cgal_volume.hpp"
#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

class CliContactDistance : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_delta_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string out(const std::string& name) { return (dir_ / name).string(); }
  static std::string read(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  /// meshes/cube.off with z scaled by 1e-4: top and bottom 1e-4 apart, closer than the default
  /// contact distance in normalized units (the diagonal is about sqrt 2).
  std::string thin_box() {
    const std::string path = out("thinbox.off");
    std::ofstream f(path);
    f << "OFF\n8 12 0\n";
    for (int v = 0; v < 8; ++v)
      f << (v == 1 || v == 2 || v == 5 || v == 6) << ' ' << (v == 2 || v == 3 || v == 6 || v == 7)
        << ' ' << (v >= 4 ? "0.0001" : "0") << '\n';
    f << "3 0 3 2\n3 0 2 1\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n"
         "3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n";
    return path;
  }
  fs::path dir_;
};

TEST_F(CliContactDistance, ADeltaAboveTheMeshsBoundIsRefused) {
  const std::string eight = std::string(test::PAPER_MESH_DIR) + "/eight.off";
  if (!fs::exists(eight)) GTEST_SKIP() << eight << " absent (scripts/fetch_paper_meshes.sh)";
  const auto r = run_cli({"run", eight, "-o", out("o.off"), "-n", "2", "--delta", "0.1"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("--delta 0.1 is above this mesh's bound"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--delta auto would choose"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out("o.off")));
  // auto, and the default, contract it.
  for (const char* delta : {"auto", "1e-4"}) {
    const auto ok = run_cli({"run", eight, "-o", out("o.off"), "-n", "2", "--delta", delta, "-q"});
    ASSERT_EQ(ok.exit_code, 0) << ok.output;
    EXPECT_LT(test::cgal_volume(test::cgal_read(out("o.off"))),
              test::cgal_volume(test::cgal_read(eight)))
        << delta;
  }
}

TEST_F(CliContactDistance, PairsHeldAtRestAreNamedAndAutoGoesBelowTheirGap) {
  const std::string box = thin_box();
  const auto held = run_cli({"run", box, "-o", out("held.off"), "-n", "10"});
  ASSERT_EQ(held.exit_code, 0) << held.output;
  EXPECT_NE(held.output.find("closer than the contact distance 1e-04 at rest"), std::string::npos)
      << held.output;
  EXPECT_NE(held.output.find("holds their 8 vertices at their rest positions"), std::string::npos)
      << held.output;
  const auto moved = run_cli({"run", box, "-o", out("moved.off"), "-n", "10", "--delta", "auto",
                              "--summary", out("s.json")});
  ASSERT_EQ(moved.exit_code, 0) << moved.output;
  EXPECT_EQ(moved.output.find("rest positions"), std::string::npos) << moved.output;
  // The box moves: its volume changes (it grows here, as it does with --collisions off), where
  // the held run's stays bit for bit.
  const double ratio = test::cgal_volume(test::cgal_read(out("moved.off"))) /
                       test::cgal_volume(test::cgal_read(box));
  EXPECT_GT(std::abs(ratio - 1.0), 1e-3) << ratio;
  EXPECT_EQ(test::cgal_volume(test::cgal_read(out("held.off"))),
            test::cgal_volume(test::cgal_read(box)));
  const std::string s = read(out("s.json"));
  const std::size_t at = s.find("\"contact_distance\": ");
  ASSERT_NE(at, std::string::npos) << s;
  EXPECT_LT(std::stod(s.substr(at + 20)), 1e-4 / std::sqrt(2.0));  // below the gap
}

}  // namespace
}  // namespace shellcontract
