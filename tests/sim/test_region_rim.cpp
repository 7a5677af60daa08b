// Regions must leave a rim to sink from (sim/region_rim.hpp): the rule, and plan_run applying it
// to every region source (a face list, a weight file, weights given as an array), so the CLI,
// Python and a sweep refuse the same input before the run.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <numeric>
#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/regions.hpp"
#include "sim/region_rim.hpp"
#include "sim/run_plan.hpp"
#include "support/cgal_mesh.hpp"

namespace shellcontract {
namespace {

Mesh sphere(int level = 1) { return test::to_surface_mesh(test::icosphere(level)); }

/// Two separate spheres (faces of the first, then of the second): two closed parts.
Mesh two_spheres() {
  const test::TriMesh a = test::icosphere(1);
  test::TriMesh both;
  both.x.resize(2 * a.x.rows(), 3);
  both.x << a.x, a.x.rowwise() + Eigen::RowVector3d(3.0, 0.0, 0.0);
  both.faces.resize(2 * a.faces.rows(), 3);
  both.faces << a.faces, a.faces.array() + static_cast<int>(a.x.rows());
  return test::to_surface_mesh(both);
}

std::string input_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(RegionRim, RegionsCoveringEveryFaceAreRefusedNamingTheSource) {
  const Mesh mesh = sphere();
  const std::size_t nf = mesh.number_of_faces();
  std::string e = input_error_of([&] { check_regions_have_rims(mesh, std::vector<int>(nf, 0), "all.txt"); });
  EXPECT_TRUE(contains(e, "all.txt: the regions cover every face")) << e;
  // Two regions that share out the surface each have a border, but nothing holds still.
  std::vector<int> halves(nf, 0);
  for (std::size_t f = nf / 2; f < nf; ++f) halves[f] = 1;
  e = input_error_of([&] { check_regions_have_rims(mesh, halves, "halves.txt"); });
  EXPECT_TRUE(contains(e, "halves.txt: the regions cover every face")) << e;
}

TEST(RegionRim, ARegionThatIsAWholeClosedPartIsRefused) {
  const Mesh mesh = two_spheres();
  std::vector<int> ids(mesh.number_of_faces(), -1);
  for (std::size_t f = 0; f < mesh.number_of_faces() / 2; ++f) ids[f] = 0;  // the first sphere
  const std::string e = input_error_of([&] { check_regions_have_rims(mesh, ids, "part.txt"); });
  EXPECT_TRUE(contains(e, "part.txt: region 0 covers a whole closed part")) << e;
  ids[0] = -1;  // one face of it stays out: a rim
  EXPECT_EQ(input_error_of([&] { check_regions_have_rims(mesh, ids, "part.txt"); }), "(accepted)");
}

TEST(RegionRim, ARegionWithATinyRestIsAccepted) {
  // The documented rule: any rim will do, one face left out gives a rim of 3 vertices (the
  // mirror's plane).
  const Mesh mesh = sphere();
  std::vector<int> ids(mesh.number_of_faces(), 0);
  ids[7] = -1;
  EXPECT_EQ(input_error_of([&] { check_regions_have_rims(mesh, ids, "f.txt"); }), "(accepted)");
  EXPECT_EQ(input_error_of([&] { check_regions_have_rims(mesh, std::vector<int>(mesh.number_of_faces(), -1), "f.txt"); }),
            "(accepted)");
}

TEST(RegionRim, PlanRunRefusesEverySourceThatCoversEveryFace) {
  const Mesh mesh = sphere();
  const std::string list = ::testing::TempDir() + "region_rim_all.txt";
  {
    std::vector<int> all(mesh.number_of_faces());
    std::iota(all.begin(), all.end(), 0);
    std::ofstream out(list);
    for (int f : all) out << f << ' ';
    out << '\n';
  }
  RunOptions o;
  set_run_option(o, "regions", list);
  std::string e = input_error_of([&] { plan_run(mesh, o); });
  EXPECT_TRUE(contains(e, list + ": the regions cover every face")) << e;

  const std::string weights = ::testing::TempDir() + "region_rim_weights.txt";
  {
    std::ofstream out(weights);
    for (std::size_t v = 0; v < mesh.number_of_vertices(); ++v) out << "1\n";
  }
  RunOptions w;
  set_run_option(w, "region-weights", weights);
  e = input_error_of([&] { plan_run(mesh, w); });
  EXPECT_TRUE(contains(e, weights + ": the regions cover every face")) << e;

  RunOptions a;  // weights as an array (Python's region_weights=)
  a.vertex_weights.assign(mesh.number_of_vertices(), 0.5);
  e = input_error_of([&] { plan_run(mesh, a); });
  EXPECT_TRUE(contains(e, "the region weights: the regions cover every face")) << e;
  std::remove(list.c_str());
  std::remove(weights.c_str());
}

TEST(RegionRim, AnEmptyRegionFileIsAWarningNamingTheFile) {
  const Mesh mesh = sphere();
  const std::string path = ::testing::TempDir() + "region_rim_empty.txt";
  std::ofstream(path) << "# no region\n\n";
  RunOptions o;
  set_run_option(o, "regions", path);
  const RunPlan plan = plan_run(mesh, o);
  EXPECT_EQ(plan.regions, 0u);
  bool named = false;
  for (const std::string& w : plan.warnings) named = named || contains(w, path + ": the file lists no region");
  EXPECT_TRUE(named) << (plan.warnings.empty() ? std::string("no warning") : plan.warnings.front());
  std::remove(path.c_str());
}

}  // namespace
}  // namespace shellcontract
