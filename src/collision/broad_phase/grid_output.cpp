// The Grid method's sorted output (grid_pairs with `sorted`, find_candidates' order): the
// chunks' keys counting-sorted by their first id.
#include <algorithm>

#include "collision/broad_phase/grid.hpp"

namespace shellcontract {
namespace detail {

void sort_chunk_keys(const std::vector<GridChunk>& chunks, bool vf, int shift, std::size_t firsts,
                     std::vector<std::uint32_t>& count, std::vector<std::uint64_t>& sorted,
                     NoZeroVector<std::array<int, 2>>& pairs, NoZeroVector<std::uint8_t>& close) {
  auto keys_of = [vf](const GridChunk& c) -> const std::vector<std::uint64_t>& {
    return vf ? c.vf_keys : c.ee_keys;
  };
  const int first_shift = shift + 1;
  count.assign(firsts + 1, 0);
  std::size_t total = 0;
  for (const GridChunk& c : chunks) {
    for (const std::uint64_t k : keys_of(c)) ++count[(k >> first_shift) + 1];
    total += keys_of(c).size();
  }
  for (std::size_t a = 0; a < firsts; ++a) count[a + 1] += count[a];
  sorted.resize(total);
  for (const GridChunk& c : chunks)
    for (const std::uint64_t k : keys_of(c)) sorted[count[k >> first_shift]++] = k;
  // Now count[a] is the end of a's keys. Most a have a handful: an insertion sort; a crowded
  // scene can give one a many.
  for (std::size_t a = 0, begin = 0; a < firsts; begin = count[a], ++a) {
    std::uint64_t* const first = sorted.data() + begin;
    std::uint64_t* const last = sorted.data() + count[a];
    if (last - first > 32) {
      std::sort(first, last);
      continue;
    }
    for (std::uint64_t* i = first + (first != last); i < last; ++i) {
      const std::uint64_t k = *i;
      std::uint64_t* j = i;
      for (; j > first && *(j - 1) > k; --j) *j = *(j - 1);
      *j = k;
    }
  }
  resize_for_rewrite(pairs, total);
  resize_for_rewrite(close, total);
  const std::uint64_t mask = (std::uint64_t{1} << shift) - 1;
  for (std::size_t i = 0; i < total; ++i) {
    const std::uint64_t k = sorted[i] >> 1;
    pairs[i] = {static_cast<int>(k >> shift), static_cast<int>(k & mask)};
    close[i] = static_cast<std::uint8_t>(sorted[i] & 1u);
  }
}

}  // namespace detail
}  // namespace shellcontract
