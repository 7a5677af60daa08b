// Which corners at one position share a new normal (normal_groups.hpp).
#include "mesh/normal_groups.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>

namespace shellcontract::soup {
namespace {

bool same_normal(const Vec3& a, const Vec3& b) {
  const bool none_a = a.isZero(0.0), none_b = b.isZero(0.0);
  if (none_a || none_b) return none_a && none_b;
  return (a - b).squaredNorm() <= kSameNormal * kSameNormal;
}

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
  for (std::size_t v = 0; v < rep.size(); ++v) {
    std::vector<std::size_t>& at = firsts[rep[v]];
    std::size_t k = 0;
    while (k < at.size() && !same_normal(dir[at[k]], dir[v])) ++k;
    if (k == at.size()) {
      at.push_back(v);
      group[v] = count++;
    } else {
      group[v] = group[at[k]];
    }
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
