// Greedy colouring of constraints by shared vertices (math-spec 9.4: "parallelize with graph
// colouring, not Jacobi"). Two constraints of one colour never share a vertex, so projecting a
// colour's constraints in any order, on any number of threads, gives the same bits.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

namespace shellcontract {

/// A grouping of constraints by colour.
struct Colouring {
  /// order[k] = original index of the constraint placed at position k; constraints of colour c
  /// occupy positions [offsets[c], offsets[c + 1]), each colour in increasing original index.
  std::vector<std::size_t> order;
  std::vector<std::size_t> offsets{0};  ///< size num_colours() + 1

  /// Number of colours (0 for no constraints).
  int num_colours() const { return static_cast<int>(offsets.size()) - 1; }
};

/// First-fit greedy colouring in array order: constraint k gets the smallest colour not yet
/// used by any constraint sharing one of its vertices (a per-vertex bit mask of used colours,
/// O(arity) per constraint, no conflict graph is built). Uses at most (largest number of
/// constraints that share one constraint's vertices) + 1 colours.
/// @param vertex_ids  count * arity vertex ids (>= 0), constraint k at [k * arity, (k+1) * arity)
/// @param arity       vertices per constraint (>= 1)
Colouring greedy_vertex_colouring(const std::vector<int>& vertex_ids, int arity);

/// Colours records that have a `v` member (std::array<int, N> of vertex ids).
template <class Record>
Colouring colour_constraints(const std::vector<Record>& records) {
  constexpr int N = static_cast<int>(std::tuple_size<decltype(Record::v)>::value);
  std::vector<int> ids;
  ids.reserve(records.size() * N);
  for (const Record& r : records) ids.insert(ids.end(), r.v.begin(), r.v.end());
  return greedy_vertex_colouring(ids, N);
}

/// Reorders `items` so that items[k] becomes the old items[order[k]].
template <class T>
void apply_order(std::vector<T>& items, const std::vector<std::size_t>& order) {
  std::vector<T> out;
  out.reserve(order.size());
  for (std::size_t i : order) out.push_back(items[i]);
  items.swap(out);
}

}  // namespace shellcontract
