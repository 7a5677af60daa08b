// read_input_mesh builds the mesh with PMP::polygon_soup_to_polygon_mesh after its own checks,
// without running PMP::is_polygon_soup_a_polygon_mesh again (io.cpp, check_soup, says why). This
// differential test is what stands behind that: on many mutated soups, every soup our checks
// accept is one CGAL's own test accepts. The mutations are the ways a file breaks a mesh: a face
// flipped, dropped, doubled or given a wrong corner, two vertices merged, two shells pinched
// together at a vertex. With check_vertex_fans taken out the pinched soups pass our checks and
// this test fails.
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <algorithm>
#include <cstddef>
#include <random>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

using Polygon = std::vector<std::size_t>;

struct Soup {
  std::vector<Point3> points;
  std::vector<Polygon> faces;
};

/// The regular icosahedron (12 vertices, 20 faces, ccw from outside).
Soup icosahedron(double shift) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  Soup s;
  const double p[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (const auto& q : p) s.points.emplace_back(q[0] + shift, q[1], q[2]);
  s.faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  return s;
}

/// Two icosahedra side by side; with `pinch`, the second one's vertex 10 is the first one's
/// vertex 8 (they touch there: a non-manifold vertex whose edges are all fine).
Soup two_shells(bool pinch) {
  Soup a = icosahedron(0.0);
  const Soup b = icosahedron(2.0 * (1.0 + std::sqrt(5.0)) / 2.0 + (pinch ? 0.0 : 1.0));
  const std::size_t n = a.points.size();
  for (const Point3& p : b.points) a.points.push_back(p);
  for (Polygon f : b.faces) {
    for (std::size_t& v : f) v = (pinch && v == 10) ? 8 : v + n;
    a.faces.push_back(f);
  }
  if (pinch) a.points.erase(a.points.begin() + static_cast<std::ptrdiff_t>(n + 10));
  if (pinch)  // the erased point shifts the second shell's later indices down by one
    for (std::size_t f = 20; f < a.faces.size(); ++f)
      for (std::size_t& v : a.faces[f])
        if (v > n + 10) --v;
  return a;
}

bool ours_accept(const Soup& s) {
  try {
    check_input_soup("soup", s.points, s.faces);
    return true;
  } catch (const InputError&) {
    return false;
  }
}

/// One random change of the kinds a broken file shows (and some that keep the mesh valid).
void mutate(Soup& s, std::mt19937& rng) {
  auto pick = [&rng](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng); };
  const std::size_t f = pick(s.faces.size());
  switch (pick(7)) {
    case 0: std::swap(s.faces[f][1], s.faces[f][2]); break;  // flipped
    case 1: s.faces.erase(s.faces.begin() + static_cast<std::ptrdiff_t>(f)); break;  // hole
    case 2: s.faces.push_back(s.faces[f]); break;  // doubled
    case 3: s.faces[f][pick(3)] = pick(s.points.size()); break;  // a wrong corner
    case 4: {  // two vertices merged
      const std::size_t u = pick(s.points.size()), v = pick(s.points.size());
      for (Polygon& g : s.faces)
        for (std::size_t& w : g)
          if (w == v) w = u;
      break;
    }
    case 5: std::rotate(s.faces[f].begin(), s.faces[f].begin() + 1, s.faces[f].end()); break;  // valid
    default: std::swap(s.faces[f], s.faces[pick(s.faces.size())]); break;  // reordered: valid
  }
  if (s.faces.empty()) s.faces.push_back({0, 1, 2});
}

TEST(SoupChecksAgainstCgal, EverySoupOurChecksAcceptIsAPolygonMeshForCgal) {
  std::mt19937 rng(20261127);
  int accepted = 0, refused_by_both = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    Soup s = trial % 3 == 0 ? icosahedron(0.0) : two_shells(trial % 3 == 1);
    const int changes = 1 + trial % 3;
    for (int k = 0; k < changes; ++k) mutate(s, rng);
    const bool ours = ours_accept(s);
    const bool cgal = CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(s.faces);
    if (ours) {
      ++accepted;
      EXPECT_TRUE(cgal) << "trial " << trial << ": our checks accept a soup CGAL would refuse";
    } else if (!cgal) {
      ++refused_by_both;
    }
  }
  // Both outcomes must be common, or the comparison says nothing.
  EXPECT_GT(accepted, 300);
  EXPECT_GT(refused_by_both, 300);
}

TEST(SoupChecksAgainstCgal, ThePinchedShellsAreRefusedByBoth) {
  const Soup pinched = two_shells(true), apart = two_shells(false);
  EXPECT_FALSE(CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(pinched.faces));
  EXPECT_FALSE(ours_accept(pinched));
  EXPECT_TRUE(CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(apart.faces));
  EXPECT_TRUE(ours_accept(apart));
}

}  // namespace
}  // namespace shellcontract
