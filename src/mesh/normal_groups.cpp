// Which corners at one position share a new normal (normal_groups.hpp).
#include "mesh/normal_groups.hpp"

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

}  // namespace shellcontract::soup
