// select_regions_at (`regions --region-at`, `run --region-at`) and max_area_fraction: each cap
// stops growing at the bound (docs/cli.md), and its report describes the faces it returns.
// Before, the growth stopped only once its popped vertices' area had passed the bound and kept
// that last disc: on bumpy_sphere's top bump a bound of 0.05 gave 7.00 % of the area, 0.1 gave
// 11.12 %, on bear's ear 0.01 gave 1.09 %; and the row's sphere, residual and angle were those
// of the grown disc (0.000 and 83 degrees where the faces written give 0.010 and 80).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/region_metrics.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/regions.hpp"
#include "support/region_fixtures.hpp"
#include "support/region_measures.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

struct PointCase {
  std::string path;
  Vec3 point;
  std::vector<double> fractions;
};

std::vector<PointCase> cases() {
  std::vector<PointCase> out = {{std::string(test::MESH_DIR) + "/bumpy_sphere.off",
                                 Vec3(0.0, 0.0, 1.0),
                                 {0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.08, 0.1, 0.15, 0.25}}};
  if (fs::exists(test::paper_mesh("bear")))  // bear's ear tip (docs/design/regions.md)
    out.push_back({test::paper_mesh("bear"),
                   Vec3(0.393, 0.822, -0.056),
                   {0.002, 0.005, 0.01, 0.02, 0.03, 0.05}});
  return out;
}

/// The faces with id 0.
std::vector<int> first_region(const std::vector<int>& ids) {
  std::vector<int> faces;
  for (std::size_t f = 0; f < ids.size(); ++f)
    if (ids[f] == 0) faces.push_back(static_cast<int>(f));
  return faces;
}

/// Whether the faces are exactly the faces around one vertex (the documented fallback).
bool is_one_ring(const test::TriMesh& m, const std::vector<int>& faces) {
  for (int k = 0; k < 3; ++k) {
    const int v = m.faces(faces.front(), k);
    int around = 0;
    for (Eigen::Index f = 0; f < m.faces.rows(); ++f)
      around += (m.faces(f, 0) == v || m.faces(f, 1) == v || m.faces(f, 2) == v) ? 1 : 0;
    const bool all = std::all_of(faces.begin(), faces.end(), [&](int f) {
      return m.faces(f, 0) == v || m.faces(f, 1) == v || m.faces(f, 2) == v;
    });
    if (all && around == static_cast<int>(faces.size())) return true;
  }
  return false;
}

TEST(RegionAtBound, EachCapStaysWithinTheAreaFraction) {
  for (const PointCase& c : cases()) {
    const Mesh mesh = read_input_mesh(c.path);
    const test::TriMesh m = test::to_tri_mesh(mesh);
    std::size_t capped = 0;
    for (double fraction : c.fractions) {
      RegionOptions o;
      o.max_area_fraction = fraction;
      RegionReport report;
      const std::vector<int> faces =
          first_region(select_regions_at(mesh, m.x, {c.point}, o, &report));
      ASSERT_FALSE(faces.empty()) << c.path << " at " << fraction;
      ASSERT_EQ(report.regions.size(), 1u);
      const test::MeasuredRegion got = test::measure_region(m.x, m.faces, faces);
      if (report.regions[0].fitted) {
        ++capped;
        EXPECT_LE(got.area / got.total_area, fraction)
            << c.path << ": a cap of " << faces.size() << " faces";
      } else {
        // Below the smallest cap that can be judged: the seed vertex's one-ring (its row: '-').
        EXPECT_TRUE(is_one_ring(m, faces))
            << c.path << " at " << fraction << ": " << faces.size() << " faces";
      }
    }
    // The bound must not turn every point into a fallback.
    EXPECT_GE(capped, c.fractions.size() / 2) << c.path;
  }
}

TEST(RegionAtBound, ALargerBoundGivesAtLeastAsLargeACap) {
  // The largest cap within the bound: a looser bound can only keep it or grow it.
  for (const PointCase& c : cases()) {
    const Mesh mesh = read_input_mesh(c.path);
    const test::TriMesh m = test::to_tri_mesh(mesh);
    double previous = 0.0;
    for (double fraction : c.fractions) {
      RegionOptions o;
      o.max_area_fraction = fraction;
      RegionReport report;
      select_regions_at(mesh, m.x, {c.point}, o, &report);
      if (!report.regions[0].fitted) continue;
      EXPECT_GE(report.regions[0].area_fraction, previous) << c.path << " at " << fraction;
      previous = report.regions[0].area_fraction;
    }
  }
}

TEST(RegionAtBound, TheReportDescribesTheFacesReturned) {
  for (const PointCase& c : cases()) {
    const Mesh mesh = read_input_mesh(c.path);
    const test::TriMesh m = test::to_tri_mesh(mesh);
    for (double fraction : c.fractions) {
      RegionOptions o;
      o.max_area_fraction = fraction;
      RegionReport report;
      const std::vector<int> faces =
          first_region(select_regions_at(mesh, m.x, {c.point}, o, &report));
      const RegionSummary& s = report.regions.at(0);
      EXPECT_EQ(s.faces, faces.size());
      const test::MeasuredRegion want = test::measure_region(m.x, m.faces, faces);
      EXPECT_NEAR(s.area_fraction, want.area / want.total_area, 1e-12);
      std::vector<char> flag(faces.size() ? m.faces.rows() : 0, 0);
      for (int f : faces) flag[static_cast<std::size_t>(f)] = 1;
      EXPECT_NEAR(s.compactness, region_shape(mesh, m.x, flag).compactness, 1e-12);
      if (!s.fitted) continue;  // a one-ring: no sphere reported
      const std::string where = c.path + " at " + std::to_string(fraction);
      EXPECT_LE((s.centre - want.centre).norm(), 1e-9 * want.radius) << where;
      EXPECT_NEAR(s.radius, want.radius, 1e-9 * want.radius) << where;
      EXPECT_NEAR(s.residual, want.residual, 1e-9) << where;
      EXPECT_NEAR(s.cap_angle_deg, want.angle_deg, 1e-6) << where;
    }
  }
}

}  // namespace
}  // namespace shellcontract
