// The coloured solver's layout helpers (src/pbd/regional_order.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <vector>

#include "pbd/regional_order.hpp"

namespace shellcontract {
namespace {

struct Record {
  std::array<int, 3> v;
  int id;  ///< where it started, to check ties keep their order
};

TEST(SortColoursByRow, SortsEachColourByItsSmallestRowAndKeepsTheColours) {
  std::mt19937 rng(5);
  const int n = 60;
  std::vector<int> row(n);
  for (int v = 0; v < n; ++v) row[v] = v;
  std::shuffle(row.begin(), row.end(), rng);
  std::uniform_int_distribution<int> vertex(0, n - 1);
  std::vector<Record> records;
  for (int i = 0; i < 40; ++i) records.push_back({{vertex(rng), vertex(rng), vertex(rng)}, i});
  records[7].v = records[6].v;  // a tie: 6 stays before 7
  const std::vector<std::size_t> colours = {0, 10, 25, 25, 40};  // one colour empty
  const std::vector<Record> before = records;
  regional::sort_colours_by_row(records, colours, row);
  auto first_row = [&](const Record& r) {
    return std::min({row[r.v[0]], row[r.v[1]], row[r.v[2]]});
  };
  for (std::size_t c = 0; c + 1 < colours.size(); ++c) {
    std::vector<int> ids_before, ids_after;
    for (std::size_t i = colours[c]; i < colours[c + 1]; ++i) {
      ids_before.push_back(before[i].id);
      ids_after.push_back(records[i].id);
      if (i > colours[c]) {
        const Record &a = records[i - 1], &b = records[i];
        EXPECT_LE(first_row(a), first_row(b)) << "colour " << c << " at " << i;
        if (first_row(a) == first_row(b)) {
          EXPECT_LT(a.id, b.id) << "a tie reordered";
        }
      }
    }
    std::sort(ids_before.begin(), ids_before.end());
    std::sort(ids_after.begin(), ids_after.end());
    EXPECT_EQ(ids_after, ids_before) << "colour " << c << " lost or gained a record";
  }
  auto at = [&](int id) {
    return std::find_if(records.begin(), records.end(), [&](const Record& r) { return r.id == id; });
  };
  EXPECT_LT(at(6), at(7));
}

TEST(SortColoursByRow, KeepsTheOrderOfTies) {
  // 64 records of one colour whose smallest row is the same (vertex 0 is row 0), in a random
  // order of ids: sorted stably, they stay as they were (an unstable sort of this many moves them).
  std::mt19937 rng(6);
  const int n = 200;
  std::vector<int> row(n);
  for (int v = 0; v < n; ++v) row[v] = v;
  std::uniform_int_distribution<int> vertex(1, n - 1);
  std::vector<Record> records;
  for (int i = 0; i < 64; ++i) records.push_back({{vertex(rng), 0, vertex(rng)}, i});
  std::shuffle(records.begin(), records.end(), rng);
  const std::vector<Record> before = records;
  regional::sort_colours_by_row(records, {0, records.size()}, row);
  for (std::size_t i = 0; i < records.size(); ++i) EXPECT_EQ(records[i].id, before[i].id) << i;
}

}  // namespace
}  // namespace shellcontract
