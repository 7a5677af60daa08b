// How polygons of more than three corners become triangles (src/mesh/polygon_split.hpp): a folded
// quad, as `run` may leave one, is split along its least folded diagonal rather than refused, and a
// simple polygon that no fan covers is ear-clipped. Before, read_input_mesh refused both ("non-convex
// polygon"), so a quad OBJ written by `run` could not be read back.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "mesh/polygon_split.hpp"
#include "mesh/soup_geometry.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace {

using shellcontract::InputError;
using shellcontract::InputReport;
using shellcontract::Mesh;
using shellcontract::Point3;
using shellcontract::Vec3;
using shellcontract::soup::Polygon;
using shellcontract::soup::SplitRule;
using shellcontract::soup::split_polygon;
using shellcontract::soup::to_vec;

Vec3 area_vector(const Polygon& t, const std::vector<Point3>& pts) {
  const Vec3 a = to_vec(pts[t[0]]);
  return (to_vec(pts[t[1]]) - a).cross(to_vec(pts[t[2]]) - a);
}

Vec3 newell(const Polygon& p, const std::vector<Point3>& pts) {
  Vec3 n = Vec3::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) n += to_vec(pts[p[i]]).cross(to_vec(pts[p[(i + 1) % p.size()]]));
  return n;
}

/// True when every corner's fan has a triangle that faces against the Newell normal, clearly (not
/// at zero, which rounding on the reader's normalized coordinates may turn either way): the old
/// reader, which took only a fan whose triangles all face along it, refused such a polygon.
bool no_fan_corner(const Polygon& p, const std::vector<Point3>& pts) {
  const Vec3 n = newell(p, pts);
  for (std::size_t k = 0; k < p.size(); ++k) {
    bool against = false;
    for (std::size_t j = 1; j + 1 < p.size(); ++j)
      against = against || area_vector({p[k], p[(k + j) % p.size()], p[(k + j + 1) % p.size()]}, pts).dot(n) < -1e-9;
    if (!against) return false;
  }
  return true;
}

/// The cosine between the normals of the quad's two triangles along the diagonal from corner k.
double fold_cosine(const std::vector<Point3>& q, std::size_t k) {
  const Polygon a{k, (k + 1) % 4, (k + 2) % 4}, b{k, (k + 2) % 4, (k + 3) % 4};
  return area_vector(a, q).normalized().dot(area_vector(b, q).normalized());
}

/// The diagonal (as a sorted pair of corners) that the two triangles share.
std::set<std::size_t> shared_edge(const std::vector<Polygon>& t) {
  std::set<std::size_t> s;
  for (const std::size_t v : t[0])
    if (std::find(t[1].begin(), t[1].end(), v) != t[1].end()) s.insert(v);
  return s;
}

/// Each triangle is wound like the polygon: its corners appear in the polygon's cyclic order.
void expect_wound_like(const std::vector<Polygon>& tris, const Polygon& p) {
  for (const Polygon& t : tris) {
    std::vector<std::size_t> at;
    for (const std::size_t v : t) at.push_back(static_cast<std::size_t>(std::find(p.begin(), p.end(), v) - p.begin()));
    const std::size_t turns = (at[1] + p.size() - at[0]) % p.size() + (at[2] + p.size() - at[1]) % p.size() +
                              (at[0] + p.size() - at[2]) % p.size();
    EXPECT_EQ(turns, p.size()) << "triangle " << t[0] << ' ' << t[1] << ' ' << t[2];
  }
}

// Butterflies bent along one diagonal past the point where a fan from any corner has a triangle
// facing against the polygon's normal.
const std::vector<Point3> BENT_ALONG_02{{0, 0, -1}, {0, 2, 1}, {0, -1, 0}, {-1, 1, -1}};
const std::vector<Point3> BENT_ALONG_13{{0, 0, 1}, {1, 0, 1}, {1, -2, -1}, {2, 0, 0}};

TEST(SplitPolygon, AFoldedQuadIsSplitAlongItsLeastFoldedDiagonal) {
  const Polygon quad{0, 1, 2, 3};
  for (const auto* q : {&BENT_ALONG_02, &BENT_ALONG_13}) {
    ASSERT_TRUE(no_fan_corner(quad, *q));  // what the old reader refused
    const std::vector<Polygon> t = split_polygon(quad, *q);
    ASSERT_EQ(t.size(), 2u);
    expect_wound_like(t, quad);
    const std::size_t k = fold_cosine(*q, 0) >= fold_cosine(*q, 1) ? 0 : 1;
    EXPECT_EQ(shared_edge(t), (std::set<std::size_t>{k, k + 2}));
  }
  EXPECT_EQ(shared_edge(split_polygon(quad, BENT_ALONG_02)), (std::set<std::size_t>{0, 2}));
  EXPECT_EQ(shared_edge(split_polygon(quad, BENT_ALONG_13)), (std::set<std::size_t>{1, 3}));
}

TEST(SplitPolygon, AConvexQuadKeepsTheFanOfItsFirstCorner) {
  // Rule 1 unchanged: what was read before is read the same (the simulation of existing inputs).
  const std::vector<Point3> q{{0, 0, 0}, {1, 0, 0}, {1, 1, 0.1}, {0, 1, 0}};
  EXPECT_EQ(split_polygon({0, 1, 2, 3}, q), (std::vector<Polygon>{{0, 1, 2}, {0, 2, 3}}));
  // A planar dart: the fan from its reflex corner (2), the only inner diagonal.
  const std::vector<Point3> dart{{0, 0, 0}, {2, 1, 0}, {0.5, 0.5, 0}, {1, 2, 0}};
  EXPECT_EQ(shared_edge(split_polygon({0, 1, 2, 3}, dart)), (std::set<std::size_t>{0, 2}));
}

TEST(SplitPolygon, ASimplePolygonThatNoFanCoversIsEarClipped) {
  // A comb with three teeth: seen from any corner, some part of it is hidden.
  const std::vector<Point3> comb{{0, 0, 0}, {5, 0, 0}, {5, 2, 0}, {4, 2, 0}, {4, 1, 0}, {3, 1, 0},
                                 {3, 2, 0}, {2, 2, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  Polygon p(comb.size());
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = i;
  ASSERT_TRUE(no_fan_corner(p, comb));
  const std::vector<Polygon> t = split_polygon(p, comb);
  ASSERT_EQ(t.size(), p.size() - 2);
  expect_wound_like(t, p);
  double area = 0.0;
  for (const Polygon& tri : t) {
    const Vec3 a = area_vector(tri, comb);
    EXPECT_GT(a.z(), 0.0) << "a triangle faces against the polygon";
    area += a.z() / 2.0;
  }
  EXPECT_NEAR(area, 5.0 * 1.0 + 3.0 * 1.0, 1e-12);  // no overlap: exactly the comb's area
}

TEST(SplitPolygon, AFlatPolygonGetsTheFanOfCorner0) {
  // No normal at all (its corners on a line): corner 0's fan, whose zero-area triangles the
  // reader then reports, as before.
  const std::vector<Point3> p{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}};
  EXPECT_EQ(split_polygon({0, 1, 2, 3, 4}, p), (std::vector<Polygon>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}));
}

TEST(SplitPolygon, APolygonEveryFanOfWhichHasAZeroAreaTriangleAndNoEarIsRefused) {
  // Corners 1 and 2 at one position: every fan has a triangle with both (or one at either's place).
  const std::vector<Point3> p{{0, 2, 0}, {0, 1, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}};
  EXPECT_TRUE(split_polygon({0, 1, 2, 3, 4}, p).empty());
  // The reader's refusal says what to do (it ended "triangulate it before").
  try {
    shellcontract::check_input_soup("pentagon", p, {{0, 1, 2, 3, 4}}, nullptr);
    ADD_FAILURE() << "read";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("pentagon: non-convex polygon: "), std::string::npos) << m;
    EXPECT_NE(m.find("triangulate it in your modelling tool (Blender: Face > Triangulate Faces) before using the file"),
              std::string::npos) << m;
  }
}

TEST(SplitPolygon, SaysWhichRuleSplitIt) {
  const auto rule_of = [](const Polygon& p, const std::vector<Point3>& pts) {
    SplitRule r = SplitRule::best_fan;  // a value no case below expects
    EXPECT_FALSE(split_polygon(p, pts, &r).empty());
    return r;
  };
  EXPECT_EQ(rule_of({0, 1, 2, 3}, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.1}, {0, 1, 0}}), SplitRule::fan);
  EXPECT_EQ(rule_of({0, 1, 2, 3}, BENT_ALONG_02), SplitRule::diagonal);
  EXPECT_EQ(rule_of({0, 1, 2, 3, 4}, {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}}), SplitRule::flat);
  const std::vector<Point3> comb{{0, 0, 0}, {5, 0, 0}, {5, 2, 0}, {4, 2, 0}, {4, 1, 0}, {3, 1, 0},
                                 {3, 2, 0}, {2, 2, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  EXPECT_EQ(rule_of({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}, comb), SplitRule::ear_clip);
  // A refused polygon leaves it as it was.
  SplitRule r = SplitRule::diagonal;
  EXPECT_TRUE(split_polygon({0, 1, 2, 3, 4}, {{0, 2, 0}, {0, 1, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}}, &r).empty());
  EXPECT_EQ(r, SplitRule::diagonal);
}

// Through the reader: the warning counts the polygons by the rule that split them. Before, it said
// "fan-triangulated" whatever the rule: here the comb prism's two comb faces are ear-clipped, its
// twelve rectangular sides fanned.
TEST(ReadInputMeshPolygons, TheWarningSaysWhichRulesSplitThePolygons) {
  const std::vector<std::array<double, 2>> comb{{0, 0}, {5, 0}, {5, 2}, {4, 2}, {4, 1}, {3, 1},
                                                {3, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const std::size_t n = comb.size();
  std::vector<Point3> points;
  for (const double z : {0.0, 1.0})
    for (const auto& c : comb) points.emplace_back(c[0], c[1], z);
  std::vector<std::vector<std::size_t>> polygons(2);
  for (std::size_t i = 0; i < n; ++i) {
    polygons[0].push_back(n - 1 - i);  // the bottom, seen from below
    polygons[1].push_back(n + i);      // the top, counter-clockwise seen from above
  }
  for (std::size_t i = 0; i < n; ++i) polygons.push_back({i, (i + 1) % n, n + (i + 1) % n, n + i});
  InputReport report;
  const Mesh mesh = shellcontract::check_input_soup("comb prism", points, polygons, &report);
  EXPECT_EQ(mesh.number_of_faces(), 2 * (n - 2) + 2 * n);
  EXPECT_NEAR(report.volume, 8.0, 1e-12);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_EQ(report.warnings[0],
            "14 polygons with more than 3 vertices were split into 44 triangles (12 by a fan from a corner, 2 by ear "
            "clipping; the first triangle of each keeps the polygon's face index, the others are appended after face 13)");
}

// Through the reader: a square pyramid whose base is a folded quad. Before, read_input_mesh
// refused it ("non-convex polygon: face 0 ... has 4 vertices and no corner from which a fan
// triangulates it").
TEST(ReadInputMeshPolygons, APyramidOnAFoldedQuadIsRead) {
  for (const auto* q : {&BENT_ALONG_02, &BENT_ALONG_13}) {
    std::vector<Point3> points = *q;
    const Vec3 n = newell({0, 1, 2, 3}, points).normalized();
    points.push_back(Point3(-3 * n.x(), -3 * n.y(), -3 * n.z()));  // the apex, on the quad's back
    const std::vector<std::vector<std::size_t>> polygons{{0, 1, 2, 3}, {1, 0, 4}, {2, 1, 4}, {3, 2, 4}, {0, 3, 4}};
    InputReport report;
    const Mesh mesh = shellcontract::check_input_soup("pyramid", points, polygons, &report);
    EXPECT_EQ(mesh.number_of_faces(), 6u);
    EXPECT_EQ(report.triangulated_faces, 1u);
    EXPECT_NE(std::find(report.warnings.begin(), report.warnings.end(),
                        "1 polygon with more than 3 vertices was split into 2 triangles (1 along a folded quad's least folded "
                        "diagonal; the first triangle of each keeps the polygon's face index, the others are appended after face 4)"),
              report.warnings.end());
  }
}

}  // namespace

namespace {

using shellcontract::soup::split_like;

// `check --against` splits a result's polygon into its input's triangles (split_like): the same
// triangles whichever corner the result's polygon starts at, wound like it.
TEST(SplitLike, TheSameCycleFromAnyCornerEitherWayRoundGetsTheSameTriangles) {
  const Polygon like = {10, 11, 12, 13, 14};
  const std::vector<Polygon> tris = {{10, 11, 12}, {12, 13, 14}, {10, 12, 14}};  // an ear split
  const std::vector<Polygon> same = split_like(like, like, tris);
  EXPECT_EQ(same, tris);
  // Rotated: the same corner triples, each starting where the given one starts.
  EXPECT_EQ(split_like({12, 13, 14, 10, 11}, like, tris), tris);
  // Reversed (a result whose polygon is wound the other way): each triangle wound the other way.
  const std::vector<Polygon> reversed = split_like({14, 13, 12, 11, 10}, like, tris);
  EXPECT_EQ(reversed, (std::vector<Polygon>{{10, 12, 11}, {12, 14, 13}, {10, 14, 12}}));
  // A triangle given wound against the polygon (an inside-out input, flipped) is wound like it.
  EXPECT_EQ(split_like(like, like, {{10, 12, 11}, {12, 13, 14}, {10, 12, 14}}), tris);
}

TEST(SplitLike, AnotherPolygonOrAnotherSplitGetsNone) {
  const Polygon like = {0, 1, 2, 3};
  const std::vector<Polygon> tris = {{0, 1, 2}, {0, 2, 3}};
  EXPECT_TRUE(split_like({0, 2, 1, 3}, like, tris).empty());     // the same corners, another cycle
  EXPECT_TRUE(split_like({0, 1, 2, 4}, like, tris).empty());     // another corner
  EXPECT_TRUE(split_like({0, 1, 2, 3, 4}, like, tris).empty());  // more corners
  EXPECT_TRUE(split_like(like, like, {{0, 1, 2}}).empty());      // too few triangles
  EXPECT_TRUE(
      split_like(like, like, {{0, 1, 2}, {0, 2, 4}}).empty());  // a corner not the polygon's
  EXPECT_TRUE(split_like(like, like, {{0, 1, 1}, {0, 2, 3}}).empty());  // a repeated corner
}

}  // namespace
