// plan_run's warnings when the regions given hold no face: they name where the regions came from
// (the file, or the weights given as an array), so a user with several region files can tell
// which one was empty.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "shellcontract/options.hpp"
#include "sim/run_plan.hpp"
#include "support/cgal_mesh.hpp"

namespace shellcontract {
namespace {

Mesh sphere() { return test::to_surface_mesh(test::icosphere(1)); }

bool warned(const RunPlan& plan, const std::string& text) {
  for (const std::string& w : plan.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

TEST(RegionWarnings, AnEmptyRegionFileIsAWarningNamingTheFile) {
  const Mesh mesh = sphere();
  const std::string path = ::testing::TempDir() + "region_warnings_empty.txt";
  std::ofstream(path) << "# no region\n\n";
  RunOptions o;
  set_run_option(o, "regions", path);
  const RunPlan plan = plan_run(mesh, o);
  EXPECT_EQ(plan.regions, 0u);
  EXPECT_TRUE(warned(plan, path + ": the file lists no region"))
      << (plan.warnings.empty() ? std::string("no warning") : plan.warnings.front());
  std::remove(path.c_str());
}

TEST(RegionWarnings, WeightsThatAreAllZeroAreAWarningNamingTheirSource) {
  const Mesh mesh = sphere();
  RunOptions a;  // weights as an array (Python's region_weights=)
  a.vertex_weights.assign(mesh.number_of_vertices(), 0.0);
  const RunPlan plan = plan_run(mesh, a);
  EXPECT_EQ(plan.regions, 0u);
  EXPECT_TRUE(warned(plan, "`region_weights`: every weight is 0"))
      << (plan.warnings.empty() ? std::string("no warning") : plan.warnings.front());
}

TEST(RegionWarnings, RegionsOfStrengthZeroAreAWarningNamingTheFile) {
  const Mesh mesh = sphere();
  const std::string path = ::testing::TempDir() + "region_warnings_zero.txt";
  std::ofstream(path) << "0: 1 2 3\n0.0: 7 8\n";
  RunOptions o;
  set_run_option(o, "regions", path);
  const RunPlan plan = plan_run(mesh, o);
  EXPECT_EQ(plan.regions, 2u);
  EXPECT_TRUE(warned(plan, path + ": every region's strength is 0"))
      << (plan.warnings.empty() ? std::string("no warning") : plan.warnings.front());
  // One region that sinks is no reason to warn.
  std::ofstream(path) << "0: 1 2 3\n0.5: 7 8\n";
  EXPECT_TRUE(plan_run(mesh, o).warnings.empty());
  std::remove(path.c_str());
}

}  // namespace
}  // namespace shellcontract
