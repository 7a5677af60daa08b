// Normals shared by many corners: the OBJ document's new normals (obj_normals.hpp) and the normal
// groups of one position (normal_groups.hpp) cost in proportion to the corners. Before, a line's
// normals were searched for every corner that names the line, and a position's groups for every
// vertex at it: either cost the square of their number, far beyond the TIMEOUT of test_costs
// (tests/CMakeLists.txt) on these inputs, which take a small part of it now.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "mesh/normal_groups.hpp"
#include "mesh/obj_normals.hpp"

namespace shellcontract {
namespace {

const double kPi = 3.14159265358979323846;

// A cone of a million flat sides around one apex whose corners all name one `vn` line (as a file
// written "f a//1 b//1 c//1" for a default normal): the line gets one normal per rim vertex.
TEST(NormalCosts, OneVnLineOfManyVerticesCostsInProportionToTheCorners) {
  const std::size_t n = 1000000;
  Positions x(static_cast<Eigen::Index>(n + 1), 3);
  x.row(0) << 0.0, 0.0, 1.0;  // the apex
  for (std::size_t i = 0; i < n; ++i) {
    const double t = 2.0 * kPi * static_cast<double>(i) / static_cast<double>(n);
    x.row(static_cast<Eigen::Index>(i + 1)) << std::cos(t), std::sin(t), 0.0;
  }
  std::vector<std::size_t> start{0}, vertex;
  for (std::size_t i = 1; i <= n; ++i) {
    for (const std::size_t v : {std::size_t{0}, i, i % n + 1}) vertex.push_back(v);
    start.push_back(vertex.size());
  }
  const std::vector<long long> vn(vertex.size(), 0);
  const std::vector<Vec3> dir{Vec3(0.0, 0.0, 1.0)};
  const ObjNormals out = obj_normals(x, ObjCorners{&start, &vertex, &vn, &dir});
  ASSERT_EQ(out.lines.size(), 1u);
  ASSERT_EQ(out.lines[0].size(), n + 1);  // the apex's and one per rim vertex, all different
  EXPECT_GT(out.lines[0][0].z(), 0.999);  // the apex's: the sum of all sides
  // In order of first corner: the apex, then rim vertex 1, 2, ...
  for (std::size_t c = 0; c < vertex.size(); ++c) ASSERT_EQ(out.pick[c], vertex[c]) << c;
}

/// Per vertex, its group as normal_groups was written before: every group of the position
/// searched in order.
std::vector<std::size_t> groups_by_search(const std::vector<std::size_t>& rep,
                                          const std::vector<Vec3>& dir) {
  std::vector<std::vector<std::size_t>> firsts(rep.size());
  std::vector<std::size_t> group(rep.size());
  std::size_t count = 0;
  for (std::size_t v = 0; v < rep.size(); ++v) {
    std::vector<std::size_t>& at = firsts[rep[v]];
    std::size_t k = 0;
    const auto same = [](const Vec3& a, const Vec3& b) {
      if (a.isZero(0.0) || b.isZero(0.0)) return a.isZero(0.0) && b.isZero(0.0);
      return (a - b).squaredNorm() <= soup::kSameNormal * soup::kSameNormal;
    };
    while (k < at.size() && !same(dir[at[k]], dir[v])) ++k;
    if (k == at.size()) {
      at.push_back(v);
      group[v] = count++;
    } else {
      group[v] = group[at[k]];
    }
  }
  return group;
}

// A million different normals at one position (points spread over the sphere), then each again
// within kSameNormal: every vertex of the second half is in its twin's group.
TEST(NormalCosts, ManyGroupsAtOnePositionCostInProportionToTheVertices) {
  const std::size_t n = 1000000;
  std::vector<Vec3> dir;
  dir.reserve(2 * n);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (std::size_t i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * static_cast<double>(i) + 1.0) / static_cast<double>(n);
    const double r = std::sqrt(1.0 - z * z), t = golden * static_cast<double>(i);
    dir.emplace_back(r * std::cos(t), r * std::sin(t), z);
  }
  for (std::size_t i = 0; i < n; ++i)
    dir.push_back((dir[i] + Vec3(0.3, -0.4, 0.5) * soup::kSameNormal).normalized());
  const std::vector<std::size_t> group =
      soup::normal_groups(std::vector<std::size_t>(2 * n, 0), dir);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(group[i], i);
    ASSERT_EQ(group[n + i], i);
  }
}

// The groups are the search's, whichever way they are found: many positions with clusters of
// nearly equal normals, some close to the bound, zero normals among them.
TEST(NormalCosts, GroupsFoundByCellAreTheGroupsASearchFinds) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> pick(0, 39);
  for (const std::size_t positions : {1, 3, 20}) {
    std::vector<Vec3> centres(40);
    for (Vec3& c : centres) c = Vec3(u(rng), u(rng), u(rng)).normalized();
    std::vector<std::size_t> rep;
    std::vector<Vec3> dir;
    for (std::size_t v = 0; v < 4000; ++v) {
      const std::size_t p = v % positions;
      rep.push_back(p);  // vertex p is the first at position p
      const int k = pick(rng);
      if (k == 0) {
        dir.push_back(Vec3::Zero());
        continue;
      }
      const double spread = (k % 3 + 1) * 0.6 * soup::kSameNormal;
      dir.push_back((centres[static_cast<std::size_t>(k)] + spread * Vec3(u(rng), u(rng), u(rng)))
                        .normalized());
    }
    EXPECT_EQ(soup::normal_groups(rep, dir), groups_by_search(rep, dir)) << positions;
  }
}

}  // namespace
}  // namespace shellcontract
