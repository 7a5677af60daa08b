// self_intersecting_pairs / does_self_intersect / new_self_intersections on positions x.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/boost/graph/iterator.h>
#include <CGAL/intersections.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/validation.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

std::string mesh_path(const std::string& name) { return std::string(test::MESH_DIR) + "/" + name; }

TEST(SelfIntersection, IcosphereHasNone) {
  for (const char* name : {"ico1.off", "ico2.off", "ico3.off", "torus.off", "bumpy_sphere.off", "two_sheet.off"}) {
    const Mesh mesh = read_input_mesh(mesh_path(name));
    const Positions x = positions_from_mesh(mesh);
    EXPECT_TRUE(self_intersecting_pairs(mesh, x).empty()) << name;
    EXPECT_FALSE(does_self_intersect(mesh, x)) << name;
  }
}

TEST(SelfIntersection, PushedThroughVertexIsFoundOnPositionsOnly) {
  const Mesh mesh = read_input_mesh(mesh_path("ico2.off"));
  const Positions rest = positions_from_mesh(mesh);
  Positions x = rest;
  // Vertex 0 pushed through the centre and out of the opposite side (to 1.5 radii): its fan of
  // faces now pierces the far side of the sphere. (Stopping inside, say at -0.9 r, would not
  // intersect anything: the fan would only cut through the empty interior.)
  const VertexIndex v0(0);
  x.row(0) = -1.5 * rest.row(0);
  const std::vector<FacePair> pairs = self_intersecting_pairs(mesh, x);
  ASSERT_FALSE(pairs.empty());
  EXPECT_TRUE(does_self_intersect(mesh, x));
  // Every pair involves one of the faces around the moved vertex (nothing else moved).
  std::vector<FaceIndex> fan;
  for (const FaceIndex f : faces_around_target(mesh.halfedge(v0), mesh)) fan.push_back(f);
  for (const FacePair& p : pairs) {
    EXPECT_LT(p.first, p.second);
    const bool touches = std::find(fan.begin(), fan.end(), p.first) != fan.end() ||
                         std::find(fan.begin(), fan.end(), p.second) != fan.end();
    EXPECT_TRUE(touches) << "pair " << p.first << "-" << p.second << " does not touch vertex 0's faces";
  }
  // The rest positions (and the mesh's own points, untouched) still have none: the map is used.
  EXPECT_TRUE(self_intersecting_pairs(mesh, rest).empty());
  EXPECT_FALSE(does_self_intersect(mesh, rest));
  // New against an empty baseline = all; against itself = none.
  EXPECT_EQ(new_self_intersections(mesh, x, {}), pairs.size());
  EXPECT_EQ(new_self_intersections(mesh, x, pairs), 0u);
  // A baseline given in the other order still matches.
  std::vector<FacePair> swapped;
  for (const FacePair& p : pairs) swapped.emplace_back(p.second, p.first);
  EXPECT_EQ(new_self_intersections(mesh, x, swapped), 0u);
}

// zero_area_face.off: a unit cube whose face 13 (0, 2, 8) has its corners on one line, vertex 8 at
// the middle of the bottom's diagonal 0-2. CGAL reports such a face as the pair (13, 13); that is
// no intersection of two faces (read_input_mesh reports the face as one of zero area), so it is in
// no pair. The two pairs left are real contacts: faces 1 (0, 8, 1) and 12 (8, 2, 1) lie along
// face 0's edge 0-2 without sharing it.
TEST(SelfIntersection, ZeroAreaFaceIsNotAPairWithItself) {
  InputReport report;
  const Mesh mesh = read_input_mesh(mesh_path("zero_area_face.off"), &report);
  ASSERT_EQ(report.zero_area_faces, std::vector<std::size_t>{13});
  const Positions x = positions_from_mesh(mesh);
  const std::vector<FacePair> expected{{FaceIndex(0), FaceIndex(1)}, {FaceIndex(0), FaceIndex(12)}};
  EXPECT_EQ(self_intersecting_pairs(mesh, x), expected);
  EXPECT_EQ(new_self_intersections(mesh, x, expected), 0u);
}

TEST(SelfIntersection, ElkHasSevenPreExistingPairs) {
  const std::string path = std::string(test::PAPER_MESH_DIR) + "/elk.off";
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << path << " is absent: run scripts/fetch_paper_meshes.sh (it extracts the paper's "
                 << "models from Debian's libcgal-demo data)";
  const Mesh mesh = read_input_mesh(path);
  const Positions x = positions_from_mesh(mesh);
  const std::vector<FacePair> pairs = self_intersecting_pairs(mesh, x);
  // 7: the count CGAL's self_intersections gave on the elk as the fetch script extracts it, kept
  // as a change detector (every elk run subtracts this baseline); no source outside the code
  // states it. What can be checked independently is checked: each pair of faces that share no
  // corner is two triangles that meet in exact arithmetic (for faces sharing a corner, meeting
  // there is no intersection, and CGAL's test beyond it is what the count already relies on).
  EXPECT_EQ(pairs.size(), 7u);
  using Exact = CGAL::Exact_predicates_exact_constructions_kernel;
  const auto triangle = [&](FaceIndex f) {
    std::vector<Exact::Point_3> p;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      p.emplace_back(x(v.idx(), 0), x(v.idx(), 1), x(v.idx(), 2));
    return Exact::Triangle_3(p.at(0), p.at(1), p.at(2));
  };
  for (const FacePair& fp : pairs) {
    std::vector<VertexIndex> a, b;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(fp.first), mesh)) a.push_back(v);
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(fp.second), mesh)) b.push_back(v);
    if (std::any_of(a.begin(), a.end(),
                    [&](VertexIndex v) { return std::count(b.begin(), b.end(), v) > 0; }))
      continue;
    EXPECT_TRUE(CGAL::do_intersect(triangle(fp.first), triangle(fp.second)))
        << fp.first << ", " << fp.second;
  }
  EXPECT_TRUE(does_self_intersect(mesh, x));
  EXPECT_EQ(new_self_intersections(mesh, x, pairs), 0u);
}

}  // namespace
}  // namespace shellcontract
