// Inside-out components (complexity F4: orient_components rescanned every face for each inverted
// component, O(components x faces), and wrote one warning line each). Each is flipped in one pass
// over the faces; up to MAX_LISTED they are named one line each, as before; more are one line with
// their count and the first MAX_LISTED.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "mesh/soup_checks.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

/// k unit-corner tetrahedra wound inward, 3 apart along x: 4 faces each.
void inverted_tetrahedra(std::size_t k, std::vector<Point3>& points,
                         std::vector<std::vector<std::size_t>>& faces) {
  const std::size_t tet[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};  // inward
  for (std::size_t c = 0; c < k; ++c) {
    const double x = 3.0 * static_cast<double>(c);
    points.insert(points.end(),
                  {Point3(x, 0, 0), Point3(x + 1, 0, 0), Point3(x, 1, 0), Point3(x, 0, 1)});
    for (const auto& t : tet) faces.push_back({4 * c + t[0], 4 * c + t[1], 4 * c + t[2]});
  }
}

TEST(InsideOutComponents, UpToTheListedBoundEachIsNamedOnItsOwnLine) {
  std::vector<Point3> points;
  std::vector<std::vector<std::size_t>> faces;
  inverted_tetrahedra(soup::MAX_LISTED, points, faces);
  InputReport report;
  check_input_soup("tets", points, faces, &report);
  EXPECT_TRUE(report.reoriented);
  EXPECT_NEAR(report.volume, static_cast<double>(soup::MAX_LISTED) / 6.0, 1e-12);
  ASSERT_EQ(report.warnings.size(), soup::MAX_LISTED);
  for (std::size_t c = 0; c < soup::MAX_LISTED; ++c)
    EXPECT_EQ(report.warnings[c],
              "component " + std::to_string(c) + " (4 faces, starting at face " +
                  std::to_string(4 * c) +
                  ") was inside-out (signed volume -0.166667); its faces were flipped");
}

TEST(InsideOutComponents, MoreAreOneLineWithTheirCount) {
  const std::size_t k = 2000;
  std::vector<Point3> points;
  std::vector<std::vector<std::size_t>> faces;
  inverted_tetrahedra(k, points, faces);
  InputReport report;
  const Mesh mesh = check_input_soup("tets", points, faces, &report);
  EXPECT_TRUE(report.reoriented);
  EXPECT_EQ(report.components, k);
  EXPECT_NEAR(report.volume, static_cast<double>(k) / 6.0, 1e-9);
  ASSERT_EQ(mesh.number_of_faces(), 4 * k);
  std::string listed;
  for (std::size_t c = 0; c < soup::MAX_LISTED; ++c)
    listed += "component " + std::to_string(c) + " (4 faces, starting at face " +
              std::to_string(4 * c) + ") of signed volume -0.166667, ";
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_EQ(report.warnings[0], "2000 components were inside-out; their faces were flipped: " +
                                    listed + "and 1990 more");
}

}  // namespace
}  // namespace shellcontract
