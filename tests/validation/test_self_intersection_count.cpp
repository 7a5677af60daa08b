// count_self_intersections / for_each_self_intersection / FacePairSample on a mesh whose parts
// all pass through each other (support/crossing_needles.hpp): its pairs number the square of its
// faces, and are counted whole while only the first few (face order) are kept (review
// complexity F7: every pair was held, and `check --json` printed them all).
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "shellcontract/validation.hpp"
#include "support/cgal_mesh.hpp"
#include "support/crossing_needles.hpp"

namespace shellcontract {
namespace {

TEST(SelfIntersectionCount, CountsEveryPairOnceAndKeepsTheFirstInFaceOrder) {
  const Mesh mesh = test::to_surface_mesh(test::crossing_needles(40));
  const Positions x = positions_from_mesh(mesh);
  const std::vector<FacePair> all = self_intersecting_pairs(mesh, x);
  ASSERT_GT(all.size(), 4000u) << "the needles must cross each other";
  // Each pair once (self_intersecting_pairs holds what the search visits, sorted, none removed).
  EXPECT_EQ(std::adjacent_find(all.begin(), all.end()), all.end());
  for (const FacePair& p : all) EXPECT_LT(p.first, p.second);

  const SelfIntersectionCount c = count_self_intersections(mesh, x, 100);
  EXPECT_EQ(c.count, all.size());
  EXPECT_TRUE(c.complete);
  EXPECT_EQ(c.first, std::vector<FacePair>(all.begin(), all.begin() + 100));

  const SelfIntersectionCount every = count_self_intersections(mesh, x, all.size());
  EXPECT_EQ(every.first, all);
  EXPECT_TRUE(every.complete);
}

TEST(SelfIntersectionCount, StopsPastALimit) {
  const Mesh mesh = test::to_surface_mesh(test::crossing_needles(40));
  const Positions x = positions_from_mesh(mesh);
  const SelfIntersectionCount c = count_self_intersections(mesh, x, 10, 500);
  EXPECT_FALSE(c.complete);
  EXPECT_EQ(c.count, 501u);
  EXPECT_EQ(c.first.size(), 10u);
  EXPECT_TRUE(std::is_sorted(c.first.begin(), c.first.end()));
  std::size_t visited = 0;
  for_each_self_intersection(mesh, x, [&](const FacePair&) { return ++visited < 7; });
  EXPECT_EQ(visited, 7u);
  // A limit the pairs do not pass leaves the count whole.
  const std::size_t total = self_intersecting_pairs(mesh, x).size();
  EXPECT_TRUE(count_self_intersections(mesh, x, 0, total).complete);
  EXPECT_FALSE(count_self_intersections(mesh, x, 0, total - 1).complete);
}

TEST(SelfIntersectionCount, SampleKeepsTheSmallestWhateverTheOrder) {
  FacePairSample sample(3);
  const auto pair = [](int a, int b) { return FacePair(FaceIndex(a), FaceIndex(b)); };
  for (const FacePair& p : {pair(5, 9), pair(1, 2), pair(7, 8), pair(0, 4), pair(1, 3), pair(2, 6)})
    sample.add(p);
  EXPECT_EQ(sample.count(), 6u);
  EXPECT_TRUE(sample.truncated());
  EXPECT_EQ(sample.pairs(), (std::vector<FacePair>{pair(0, 4), pair(1, 2), pair(1, 3)}));
  FacePairSample none(0);
  none.add(pair(0, 1));
  EXPECT_EQ(none.count(), 1u);
  EXPECT_TRUE(none.pairs().empty());
}

TEST(SelfIntersectionCount, NewPairsAgainstACrossingBaseline) {
  const Mesh mesh = test::to_surface_mesh(test::crossing_needles(20));
  const Positions x = positions_from_mesh(mesh);
  std::vector<FacePair> all = self_intersecting_pairs(mesh, x);
  EXPECT_EQ(new_self_intersections(mesh, x, all), 0u);
  all.resize(all.size() / 2);
  EXPECT_EQ(new_self_intersections(mesh, x, all),
            self_intersecting_pairs(mesh, x).size() - all.size());
}

TEST(SelfIntersectionCount, BaselineLimit) {
  EXPECT_EQ(baseline_pair_limit(0), BASELINE_PAIRS);
  EXPECT_EQ(baseline_pair_limit(125000), BASELINE_PAIRS);
  EXPECT_EQ(baseline_pair_limit(200000), 200000 * BASELINE_PAIRS_PER_FACE);
}

}  // namespace
}  // namespace shellcontract
