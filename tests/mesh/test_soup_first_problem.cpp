// The soup checks sort their records to find problems (src/mesh/soup_checks.*), but the problem
// they report must be the first one in file order, the one a reader scanning the file meets
// first, whatever the sort puts first. Each soup below has two problems of one kind whose order
// in the sort is the reverse of their order in the file. The duplicate test was checked to fail
// when the duplicate check reports its first sorted run instead.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

using Polygon = std::vector<std::size_t>;

std::string message_of(const std::vector<Polygon>& faces, std::size_t nv) {
  std::vector<Point3> points;
  for (std::size_t i = 0; i < nv; ++i) points.emplace_back(static_cast<double>(i), static_cast<double>(i * i % 7), static_cast<double>(i % 3));
  try {
    check_input_soup("soup", points, faces);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SoupFirstProblem, DuplicateFacesAreReportedInFileOrder) {
  // Corners {0,1,2} come first in the sort, but their repeat is face 5; corners {3,4,5} repeat
  // at face 2. A scan in file order meets face 2 first.
  const std::string m = message_of({{0, 1, 2}, {3, 4, 5}, {5, 3, 4}, {6, 7, 8}, {9, 10, 11}, {2, 1, 0}}, 12);
  EXPECT_NE(m.find("duplicate face"), std::string::npos) << m;
  EXPECT_NE(m.find("face 2 "), std::string::npos) << m;
  EXPECT_NE(m.find("face 1"), std::string::npos) << m;
  EXPECT_EQ(m.find("face 5"), std::string::npos) << m;
}

TEST(SoupFirstProblem, OpenEdgesAreReportedInFileOrder) {
  // A lone triangle (vertices 8-10, all three edges open) as face 0, then a tetrahedron
  // (vertices 4-7) missing its last face (three more open edges). The tetrahedron's edges sort
  // first (smaller vertex ids), yet face 0 comes first in the file, so it is the face named.
  const std::vector<Polygon> broken_tet = {{8, 9, 10}, {4, 5, 6}, {4, 6, 7}, {4, 7, 5}};
  const std::string first = message_of(broken_tet, 11);
  EXPECT_NE(first.find("open boundary"), std::string::npos) << first;
  EXPECT_NE(first.find("face 0"), std::string::npos) << first;
}

}  // namespace
}  // namespace shellcontract
