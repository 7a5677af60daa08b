#include "pbd/colouring.hpp"

#include <algorithm>
#include <cstdint>
#include <stdexcept>

namespace shellcontract {

Colouring greedy_vertex_colouring(const std::vector<int>& vertex_ids, int arity) {
  if (arity < 1 || vertex_ids.size() % static_cast<std::size_t>(arity) != 0)
    throw std::invalid_argument("greedy_vertex_colouring: ids not a multiple of arity");
  const std::size_t count = vertex_ids.size() / static_cast<std::size_t>(arity);
  int num_vertices = 0;
  for (int v : vertex_ids) {
    if (v < 0) throw std::invalid_argument("greedy_vertex_colouring: negative vertex id");
    num_vertices = std::max(num_vertices, v + 1);
  }
  // used[v * words + b] bit j: colour 64 b + j is taken by a constraint at vertex v. One word
  // covers every mesh we run (colours ~ 2 x vertex valence); more words are added on demand.
  std::size_t words = 1;
  std::vector<std::uint64_t> used(static_cast<std::size_t>(num_vertices) * words, 0);
  std::vector<int> colour(count);
  int num_colours = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const int* v = vertex_ids.data() + k * static_cast<std::size_t>(arity);
    int c = -1;
    for (std::size_t b = 0; c < 0; ++b) {
      if (b == words) {  // every colour so far conflicts: widen the masks by one word
        std::vector<std::uint64_t> wider(static_cast<std::size_t>(num_vertices) * (words + 1), 0);
        for (int u = 0; u < num_vertices; ++u)
          std::copy_n(used.begin() + static_cast<std::ptrdiff_t>(u * words), words,
                      wider.begin() + static_cast<std::ptrdiff_t>(u * (words + 1)));
        used.swap(wider);
        ++words;
      }
      std::uint64_t taken = 0;
      for (int i = 0; i < arity; ++i) taken |= used[static_cast<std::size_t>(v[i]) * words + b];
      if (taken != ~std::uint64_t{0}) {
        int j = 0;
        while (taken & (std::uint64_t{1} << j)) ++j;
        c = static_cast<int>(64 * b) + j;
      }
    }
    for (int i = 0; i < arity; ++i)
      used[static_cast<std::size_t>(v[i]) * words + static_cast<std::size_t>(c / 64)] |=
          std::uint64_t{1} << (c % 64);
    colour[k] = c;
    num_colours = std::max(num_colours, c + 1);
  }
  // Counting sort by colour; stable, so each colour keeps the original (array) order.
  Colouring out;
  out.offsets.assign(static_cast<std::size_t>(num_colours) + 1, 0);
  for (int c : colour) ++out.offsets[static_cast<std::size_t>(c) + 1];
  for (int c = 0; c < num_colours; ++c) out.offsets[c + 1] += out.offsets[c];
  std::vector<std::size_t> next(out.offsets.begin(), out.offsets.end() - 1);
  out.order.resize(count);
  for (std::size_t k = 0; k < count; ++k) out.order[next[static_cast<std::size_t>(colour[k])]++] = k;
  return out;
}

}  // namespace shellcontract
