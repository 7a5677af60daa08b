// region_shape and face_set_iou against closed forms on the unit cube, whose face sets have an
// area, a boundary and an overlap that can be counted by hand. The finder's tests compare its
// compactness with a second count of the same quantity (support/region_fixtures.hpp); these pin
// each term to geometry: the half in the triangle area, only edges with exactly one side in the
// set, the 4 pi of a disc, and the intersection and union of two sets.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "geometry/region_metrics.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

constexpr double PI = 3.14159265358979323846;

/// The unit cube [0, 1]^3 of meshes/cube.off, two triangles a side, in the file's face order:
/// faces 0-1 z = 0, 2-3 z = 1, 4-5 y = 0, 6-7 x = 1, 8-9 y = 1, 10-11 x = 0.
struct Cube {
  std::vector<double> v{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  std::vector<std::int32_t> f{0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                              1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
  Mesh mesh = mesh_from_arrays(TriangleSoupView{v.data(), 8, f.data(), nullptr, 12}, "cube",
                               nullptr, false);
  Positions x =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(v.data(), 8, 3);
};

std::vector<char> faces_of(std::initializer_list<int> ids) {
  std::vector<char> flag(12, 0);
  for (int i : ids) flag[static_cast<std::size_t>(i)] = 1;
  return flag;
}

TEST(RegionShape, OneSquareSideHasAreaOnePerimeterFourAndTheDiagonalIsInside) {
  const Cube c;
  const RegionShape s = region_shape(c.mesh, c.x, faces_of({2, 3}));
  EXPECT_NEAR(s.area, 1.0, 1e-15);
  EXPECT_NEAR(s.perimeter, 4.0, 1e-15) << "the shared diagonal is not on the boundary";
  EXPECT_NEAR(s.compactness, 16.0 / (4.0 * PI), 1e-15);
}

TEST(RegionShape, OneTriangleHasAreaHalfAndItsThreeEdges) {
  const Cube c;
  const RegionShape s = region_shape(c.mesh, c.x, faces_of({2}));
  EXPECT_NEAR(s.area, 0.5, 1e-15);
  EXPECT_NEAR(s.perimeter, 2.0 + std::sqrt(2.0), 1e-15);
}

TEST(RegionShape, TwoAdjacentSidesShareOneEdgeAndTheWholeCubeHasNoBoundary) {
  const Cube c;
  // Top (z = 1) and front (y = 0) meet along one unit edge: a 2 x 1 rectangle unfolded.
  const RegionShape l = region_shape(c.mesh, c.x, faces_of({2, 3, 4, 5}));
  EXPECT_NEAR(l.area, 2.0, 1e-15);
  EXPECT_NEAR(l.perimeter, 6.0, 1e-15);
  EXPECT_NEAR(l.compactness, 36.0 / (8.0 * PI), 1e-15);
  const RegionShape all = region_shape(c.mesh, c.x, std::vector<char>(12, 1));
  EXPECT_NEAR(all.area, 6.0, 1e-14);
  EXPECT_EQ(all.perimeter, 0.0);
  EXPECT_EQ(all.compactness, 0.0);
  const RegionShape none = region_shape(c.mesh, c.x, std::vector<char>(12, 0));
  EXPECT_EQ(none.area, 0.0);
  EXPECT_EQ(none.compactness, std::numeric_limits<double>::infinity());
}

TEST(RegionShape, MeasuresTheGivenPositionsAndCompactnessIsScaleFree) {
  const Cube c;
  const Positions x3 = 3.0 * c.x;
  const std::vector<char> set = faces_of({2, 3, 4, 5});
  const RegionShape a = region_shape(c.mesh, c.x, set), b = region_shape(c.mesh, x3, set);
  EXPECT_NEAR(b.area, 9.0 * a.area, 1e-13);
  EXPECT_NEAR(b.perimeter, 3.0 * a.perimeter, 1e-13);
  EXPECT_NEAR(b.compactness, a.compactness, 1e-13);
  EXPECT_THROW(region_shape(c.mesh, c.x, std::vector<char>(11, 1)), UsageError);
}

TEST(FaceSetIou, IntersectionOverUnionByFaceCount) {
  EXPECT_DOUBLE_EQ(face_set_iou(faces_of({0, 1}), faces_of({1, 2})), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(face_set_iou(faces_of({0, 1, 2, 3}), faces_of({1, 2})), 0.5);
  EXPECT_EQ(face_set_iou(faces_of({0}), faces_of({5})), 0.0);
  EXPECT_EQ(face_set_iou(faces_of({4, 7}), faces_of({4, 7})), 1.0);
  EXPECT_EQ(face_set_iou(faces_of({}), faces_of({})), 1.0) << "both empty: documented as 1";
  EXPECT_THROW(face_set_iou(faces_of({0}), std::vector<char>(3, 0)), UsageError);
}

}  // namespace
}  // namespace shellcontract
