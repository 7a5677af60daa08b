// Which corners at one position share a new normal (normal_groups.hpp).
#include "mesh/normal_groups.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace shellcontract::soup {
namespace {

bool same_normal(const Vec3& a, const Vec3& b) {
  const bool none_a = a.isZero(0.0), none_b = b.isZero(0.0);
  if (none_a || none_b) return none_a && none_b;
  return (a - b).squaredNorm() <= kSameNormal * kSameNormal;
}

/// Up to this many groups at one position are searched one by one (most vertices have a few).
constexpr std::size_t kSearched = 16;

/// The groups of the positions that have more than kSearched, by position and cell of a grid of
/// normals: the normals same_normal finds equal to one differ from it by at most kSameNormal in
/// each coordinate, a quarter of a cell's width, so they lie in its cell or the next one on the
/// side of the cell's nearer half, in each coordinate (the quarter left leaves room for
/// rounding). A search of all a position's groups made a fan's centre of many flat sides cost
/// the square of their number.
class GroupCells {
 public:
  /// Adds group first vertex `v` of position `p`.
  void add(std::size_t p, const std::vector<Vec3>& dir, std::size_t v) {
    std::array<long long, 3> c{}, side{};
    cell(dir[v], c, side);
    cells_[key(p, c)].push_back(v);
  }
  /// The first vertex of the earliest group of position `p` whose normal is vertex v's; SIZE_MAX
  /// when none is.
  std::size_t find(std::size_t p, const std::vector<Vec3>& dir, std::size_t v) const {
    std::array<long long, 3> c{}, side{};
    cell(dir[v], c, side);
    std::size_t best = SIZE_MAX;
    for (int corner = 0; corner < 8; ++corner) {
      std::array<long long, 3> n = c;
      for (std::size_t i = 0; i < 3; ++i)
        if (corner >> i & 1) n[i] += side[i];
      const auto it = cells_.find(key(p, n));
      if (it == cells_.end()) continue;
      for (const std::size_t u : it->second)
        if (u < best && same_normal(dir[u], dir[v])) best = u;
    }
    return best;
  }

 private:
  using Key = std::array<long long, 4>;
  struct Hash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 0;
      for (const long long x : k)
        h = (h ^ static_cast<std::uint64_t>(x)) * 0x9E3779B97F4A7C15ull + (h >> 29);
      return static_cast<std::size_t>(h ^ (h >> 32));
    }
  };
  /// The cell of normal n, and per coordinate the side (-1, +1) of the neighbour its nearer half
  /// faces.
  static void cell(const Vec3& n, std::array<long long, 3>& c, std::array<long long, 3>& side) {
    for (Eigen::Index i = 0; i < 3; ++i) {
      // Unit vectors or zero; anything else is clamped (a cell at the edge still holds all of its
      // neighbours), and NaN, which no normal is the same as, goes anywhere.
      const double x = std::isnan(n[i]) ? 0.0 : std::clamp(n[i], -4.0, 4.0);
      const double f = x / (4.0 * kSameNormal), floor = std::floor(f);
      const auto k = static_cast<std::size_t>(i);
      c[k] = static_cast<long long>(floor);
      side[k] = f - floor < 0.5 ? -1 : 1;
    }
  }
  static Key key(std::size_t p, const std::array<long long, 3>& c) {
    return {static_cast<long long>(p), c[0], c[1], c[2]};
  }
  std::unordered_map<Key, std::vector<std::size_t>, Hash> cells_;
};

}  // namespace

std::vector<std::size_t> normal_groups(const std::vector<std::size_t>& rep,
                                       const std::vector<Vec3>& dir) {
  if (rep.size() != dir.size())
    throw std::invalid_argument("normal_groups: " + std::to_string(dir.size()) + " normals for " +
                                std::to_string(rep.size()) + " vertices");
  // Per position (its first vertex), the first vertex of each of its groups.
  std::vector<std::vector<std::size_t>> firsts(rep.size());
  std::vector<std::size_t> group(rep.size());
  std::size_t count = 0;
  GroupCells cells;
  for (std::size_t v = 0; v < rep.size(); ++v) {
    std::vector<std::size_t>& at = firsts[rep[v]];
    std::size_t first = SIZE_MAX;  // the first vertex of v's group: the earliest that matches
    if (at.size() <= kSearched) {
      for (const std::size_t u : at)
        if (same_normal(dir[u], dir[v])) {
          first = u;
          break;
        }
    } else {
      first = cells.find(rep[v], dir, v);
    }
    if (first != SIZE_MAX) {
      group[v] = group[first];
      continue;
    }
    at.push_back(v);
    group[v] = count++;
    if (at.size() == kSearched + 1)  // from now on this position's groups are found by cell
      for (const std::size_t u : at) cells.add(rep[v], dir, u);
    else if (at.size() > kSearched + 1)
      cells.add(rep[v], dir, v);
  }
  return group;
}

std::vector<long long> welded_corner_groups(const std::vector<std::size_t>& welded,
                                            const std::vector<Vec3>& dir,
                                            const std::vector<std::size_t>& corner_vertex) {
  if (welded.size() != dir.size())
    throw std::invalid_argument("welded_corner_groups: " + std::to_string(dir.size()) +
                                " normals for " + std::to_string(welded.size()) + " vertices");
  bool any = false;
  for (const Vec3& d : dir) any = any || !d.isZero(0.0);
  if (!any) return {};
  // The first file vertex of each simulation vertex stands for its copies, as the first vertex
  // at a position does in normal_groups (the weld joins copies at one position).
  std::vector<std::size_t> first(welded.size(), SIZE_MAX), rep(welded.size());
  for (std::size_t v = 0; v < welded.size(); ++v) {
    if (welded[v] >= first.size())
      throw std::invalid_argument("welded_corner_groups: a welded vertex out of range");
    if (first[welded[v]] == SIZE_MAX) first[welded[v]] = v;
    rep[v] = first[welded[v]];
  }
  const std::vector<std::size_t> group = normal_groups(rep, dir);
  std::vector<long long> out(corner_vertex.size(), -1);
  for (std::size_t c = 0; c < corner_vertex.size(); ++c) {
    const std::size_t v = corner_vertex[c];
    if (v >= dir.size())
      throw std::invalid_argument("welded_corner_groups: a corner's vertex out of range");
    if (!dir[v].isZero(0.0)) out[c] = static_cast<long long>(group[v]);
  }
  return out;
}

}  // namespace shellcontract::soup
