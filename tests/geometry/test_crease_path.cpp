// The cap finder's crease test (src/geometry/crease_path.hpp) on a flat grid whose concave
// vertices are set by hand: a seed left of x = 0.5, a part right of x = 0.55, and a wall of
// concave vertices on x = 0.5 between them. A long wall with an end (the groove between two
// knuckles) puts the seed across a crease, a short one (a dent inside one part) does not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "geometry/crease_path.hpp"

namespace shellcontract {
namespace {

constexpr int N = 21;  // grid points per side, spacing 0.05 on [0, 1]
constexpr double H = 1.0 / (N - 1);

int id(int i, int j) { return j * N + i; }

/// The edge graph of the unit square triangulated with one diagonal per cell (i, j)-(i+1, j+1):
/// every edge joins neighbouring columns or stays in one, so a path from column 9 to column 11
/// steps on column 10.
detail::MeshArrays grid(Positions& x) {
  detail::MeshArrays m;
  m.nv = N * N;
  x.resize(N * N, 3);
  std::vector<std::vector<int>> nbr(m.nv);
  const auto link = [&](int a, int b) { nbr[a].push_back(b), nbr[b].push_back(a); };
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) {
      x.row(id(i, j)) << i * H, j * H, 0.0;
      if (i + 1 < N) link(id(i, j), id(i + 1, j));
      if (j + 1 < N) link(id(i, j), id(i, j + 1));
      if (i + 1 < N && j + 1 < N) link(id(i, j), id(i + 1, j + 1));
    }
  m.nbr_start.push_back(0);
  for (std::size_t v = 0; v < m.nv; ++v) {
    for (int w : nbr[v]) {
      m.nbr_to.push_back(w);
      m.nbr_len.push_back((Vec3(x.row(static_cast<Eigen::Index>(v))) - Vec3(x.row(w))).norm());
    }
    m.nbr_start.push_back(static_cast<int>(m.nbr_to.size()));
  }
  return m;
}

class CreasePathsOnAGrid : public ::testing::Test {
 protected:
  void SetUp() override {
    m = grid(x);
    part.assign(m.nv, -1);
    for (int j = 0; j < N; ++j)
      for (int i = 12; i < N; ++i) part[static_cast<std::size_t>(id(i, j))] = 0;
    crease.assign(m.nv, 0);
  }
  /// Concave vertices on the column x = 0.5 from row j0 to row j1.
  void wall(int j0, int j1) {
    for (int j = j0; j <= j1; ++j) crease[static_cast<std::size_t>(id(10, j))] = 1;
  }
  bool across(int seed, double ball = 2.0) {
    detail::CreasePaths paths(m, x, crease);
    return paths.across(seed, centre, ball, 0, part);
  }

  Positions x;
  detail::MeshArrays m;
  std::vector<int> part;
  std::vector<char> crease;
  const Vec3 centre{0.5, 0.5, 0.0};
  const int seed = id(8, 4);  // (0.4, 0.2): 0.2 from the part along row 4
};

TEST_F(CreasePathsOnAGrid, DistancesAreShortestEdgePathsWithAndWithoutTheConcaveVertices) {
  wall(0, 16);  // up to y = 0.8
  detail::CreasePaths paths(m, x, crease);
  std::vector<int> path;
  EXPECT_NEAR(paths.distance(seed, centre, 2.0, 0, part, false, &path), 0.2, 1e-12);
  ASSERT_EQ(path.size(), 5u);
  EXPECT_EQ(path.front(), seed);
  EXPECT_EQ(path.back(), id(12, 4));
  // Round the wall's end, (0.5, 0.85): two diagonal steps and 11 up to it, two right to the
  // part (column 12 is the part's from row 0 up).
  const double round = paths.distance(seed, centre, 2.0, 0, part, true, &path);
  EXPECT_NEAR(round, 13 * H + 2 * std::sqrt(2.0) * H, 1e-12);
  for (int v : path)
    EXPECT_FALSE(crease[static_cast<std::size_t>(v)]) << "the convex path steps on " << v;
  // The scratch arrays are reset: the same query again gives the same answer.
  EXPECT_EQ(paths.distance(seed, centre, 2.0, 0, part, true), round);
}

TEST_F(CreasePathsOnAGrid, NoCreaseOrAShortDentIsNotACrease) {
  EXPECT_FALSE(across(seed));
  wall(3, 5);  // a dent of three vertices across the straight way: a detour of a few edges
  EXPECT_FALSE(across(seed));
}

TEST_F(CreasePathsOnAGrid, AGrooveWithAnEndFarAwayIsACrease) {
  wall(0, 16);  // the way round is about four times the straight way
  EXPECT_TRUE(across(seed));
}

TEST_F(CreasePathsOnAGrid, AGrooveWithNoWayRoundInsideTheBallIsACrease) {
  wall(0, N - 1);
  EXPECT_TRUE(across(seed));
  // A shorter wall, up to y = 0.4: the way round, about twice the straight way, is no crease;
  // in a ball of radius 0.22 about (0.5, 0.2) the way round (by (0.5, 0.45)) is outside it.
  std::fill(crease.begin(), crease.end(), 0);
  wall(0, 8);
  EXPECT_FALSE(across(seed, 2.0));
  const Vec3 c{0.5, 0.2, 0.0};
  detail::CreasePaths paths(m, x, crease);
  EXPECT_TRUE(paths.across(seed, c, 0.22, 0, part));
}

TEST_F(CreasePathsOnAGrid, ASeedThatReachesNoPartVertexInsideTheBallIsNotAcross) {
  wall(0, N - 1);
  detail::CreasePaths paths(m, x, crease);
  // A ball about the seed that holds no part vertex: nothing to be across from.
  EXPECT_FALSE(paths.across(seed, Vec3(x.row(seed)), 0.1, 0, part));
}

}  // namespace
}  // namespace shellcontract
