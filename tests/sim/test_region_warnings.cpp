// plan_run's warnings when the regions given hold no face: they name where the regions came from
// (the file, or the weights given as an array), so a user with several region files can tell
// which one was empty. And a `region_at` point far from the surface (a fitted sphere's centre, a
// point in another frame): before, its region was taken elsewhere with no word.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/regions.hpp"
#include "sim/run_plan.hpp"
#include "support/cgal_mesh.hpp"
#include "test_paths.hpp"

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

/// The warnings of a run at this one point (CLI text "X,Y,Z").
std::vector<std::string> point_warnings(const Mesh& mesh, const Vec3& p) {
  RunOptions o;
  set_run_option(o, "region-at",
                 shortest_text(p.x()) + "," + shortest_text(p.y()) + "," + shortest_text(p.z()));
  std::vector<std::string> out;
  for (const std::string& w : plan_run(mesh, o).warnings)
    if (w.find("`region_at` point") != std::string::npos) out.push_back(w);
  return out;
}

TEST(RegionWarnings, ARegionAtPointFarFromTheSurfaceIsAWarningNamingItAndTheSurfacePoint) {
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/bumpy_sphere.off");
  const Positions x = positions_from_mesh(mesh);
  // The mistake the regions table invites: each bump's fitted-sphere centre, which lies inside
  // the bump; and a point far off.
  RegionReport found;
  select_spherical_regions(mesh, x, RegionOptions{}, &found);
  ASSERT_FALSE(found.regions.empty());
  std::vector<Vec3> far{Vec3(5, 5, 5)};
  for (const RegionSummary& r : found.regions) far.push_back(r.centre);
  for (const Vec3& p : far) {
    const std::vector<std::string> w = point_warnings(mesh, p);
    ASSERT_EQ(w.size(), 1u) << "no warning for " << p.transpose();
    const std::string given = "(" + shortest_text(p.x()) + ", " + shortest_text(p.y()) + ", " +
                              shortest_text(p.z()) + ")";
    EXPECT_NE(w[0].find("the 1st `region_at` point " + given + " is "), std::string::npos) << w[0];
    EXPECT_NE(w[0].find("from the surface point nearest to it, ("), std::string::npos) << w[0];
    EXPECT_NE(w[0].find("Y-up"), std::string::npos) << w[0];
    EXPECT_NE(w[0].find("not a sphere's centre"), std::string::npos) << w[0];
  }
}

TEST(RegionWarnings, ARegionAtPointOnOrNearTheSurfaceIsNoWarning) {
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/bumpy_sphere.off");
  const Positions x = positions_from_mesh(mesh);
  const double diagonal = (x.colwise().maxCoeff() - x.colwise().minCoeff()).norm();
  // A vertex, and points a percent of the diagonal from one (a point read off a render): the
  // surface is no farther from them than that vertex is.
  const Vec3 off = Vec3(1, 1, 1).normalized() * 0.01 * diagonal;
  for (Eigen::Index v : {Eigen::Index(0), x.rows() / 2, x.rows() - 1})
    for (const Vec3& p : {Vec3(x.row(v)), Vec3(Vec3(x.row(v)) + off), Vec3(Vec3(x.row(v)) - off)})
      EXPECT_TRUE(point_warnings(mesh, p).empty())
          << "vertex " << v << ": " << point_warnings(mesh, p)[0];
}

}  // namespace
}  // namespace shellcontract
