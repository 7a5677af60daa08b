// A strength per region: the "S:" column of a face-list file scales the local
// contraction of that region. Checked against an independent way of asking for the same
// contraction (--region-shrink scaled by S: bit for bit the same run), and against the plain file
// (a column of 1 changes nothing, a smaller strength sinks the regions less).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"
#include "shellcontract/simulation_options.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

/// meshes/bumpy_sphere.bumps.txt with `prefix` before every region line, written to a temp file.
std::string bumps_with(const std::string& name, const std::string& prefix) {
  std::ifstream in(std::string(test::MESH_DIR) + "/bumpy_sphere.bumps.txt");
  std::ostringstream out;
  for (std::string line; std::getline(in, line);) {
    const bool region = line.find_first_not_of(" \t\r") != std::string::npos && line[0] != '#';
    out << (region ? prefix : "") << line << '\n';
  }
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << out.str();
  return path;
}

RunResult sink(const std::string& region_file, double shrink, const char* order = "auto") {
  RunOptions o;
  set_run_option(o, "order", order);
  o.sim.pressure = 0.0;
  o.sim.frames = 60;
  o.sim.region_shrink = shrink;
  o.regions = RegionSource::File;
  o.region_file = region_file;
  const RunResult r = run_contraction(read_input_mesh(std::string(test::MESH_DIR) + "/bumpy_sphere.off"), o);
  EXPECT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_EQ(r.regions, 3u);
  return r;
}

TEST(RegionStrength, AStrengthColumnScalesTheShrinkOfItsRegion) {
  const double S = DEFAULT_REGION_SHRINK;
  const RunResult plain = sink(bumps_with("plain.txt", ""), S);
  const RunResult ones = sink(bumps_with("ones.txt", "1: "), S);
  const RunResult half = sink(bumps_with("half.txt", "0.5: "), S);
  const RunResult scaled = sink(bumps_with("scaled.txt", ""), S * 0.5);
  ASSERT_GT(plain.region_inward_displacement, 0.0);
  // Full strength is the file without the column.
  EXPECT_TRUE(ones.positions == plain.positions);
  // Strength 0.5 on every region is --region-shrink times 0.5 (the dimples' only input; a
  // power of two, so that the area-weighted mean strength is exactly 0.5).
  EXPECT_TRUE(half.positions == scaled.positions);
  EXPECT_GT(half.region_inward_displacement, 0.0);
  EXPECT_LT(half.region_inward_displacement, 0.8 * plain.region_inward_displacement);
}

TEST(RegionStrength, StrengthZeroLeavesTheShellAtRest) {
  // At -p 0 with every region at strength 0 nothing pushes the shell: it stays at rest up to the
  // rounding of the coloured order's batched kernels (their angles and roots are polynomials, so
  // a constraint at rest may move a vertex by ~1e-22), and bit for bit under the paper's
  // sequential order, whose scalar kernels give exactly zero at rest.
  const RunResult none = sink(bumps_with("zero.txt", "0: "), DEFAULT_REGION_SHRINK);
  EXPECT_LE(std::abs(none.region_inward_displacement), 1e-15);
  EXPECT_LE(std::abs(none.outside_region_displacement), 1e-15);
  const RunResult sequential =
      sink(bumps_with("zero_sequential.txt", "0: "), DEFAULT_REGION_SHRINK, "sequential");
  EXPECT_EQ(sequential.region_inward_displacement, 0.0);
  EXPECT_EQ(sequential.outside_region_displacement, 0.0);
}

}  // namespace
}  // namespace shellcontract
