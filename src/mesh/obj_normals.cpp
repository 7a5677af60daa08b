#include "mesh/obj_normals.hpp"

#include <cmath>
#include <map>
#include <utility>

#include "mesh/seam_weld.hpp"

namespace shellcontract {

ObjNormals obj_normals(const Positions& x, const ObjCorners& in) {
  const std::vector<std::size_t>& start = *in.polygon_start;
  const std::vector<std::size_t>& vertex = *in.corner_vertex;
  const std::vector<long long>& vn = *in.corner_vn;
  const std::vector<std::size_t> rep = soup::first_at_same_position(x);

  // Groups: (vn line, vertex). Each polygon's weight is its Newell vector: twice its area along
  // its normal.
  std::map<std::pair<long long, std::size_t>, std::size_t> group_of;
  std::vector<Vec3> sum;
  std::vector<std::size_t> line_of_group;
  std::vector<std::size_t> corner_group(vertex.size(), SIZE_MAX);
  for (std::size_t p = 0; p + 1 < start.size(); ++p) {
    Vec3 newell = Vec3::Zero();
    const std::size_t b = start[p], e = start[p + 1];
    for (std::size_t c = b; c < e; ++c) {
      const std::size_t next = c + 1 < e ? c + 1 : b;
      const Vec3 pc = x.row(static_cast<Eigen::Index>(vertex[c])).transpose();
      const Vec3 pn = x.row(static_cast<Eigen::Index>(vertex[next])).transpose();
      newell += pc.cross(pn);
    }
    for (std::size_t c = b; c < e; ++c) {
      if (vn[c] < 0) continue;
      const auto g = group_of.emplace(std::make_pair(vn[c], rep[vertex[c]]), sum.size());
      if (g.second) {
        sum.push_back(Vec3::Zero());
        line_of_group.push_back(static_cast<std::size_t>(vn[c]));
      }
      sum[g.first->second] += newell;
      corner_group[c] = g.first->second;
    }
  }

  // Each group's normal, in order of first use; equal normals (one per line before) are one.
  ObjNormals out;
  out.lines.resize(in.vn_count);
  out.pick.assign(vertex.size(), 0);
  std::vector<std::size_t> pick_of_group(sum.size(), SIZE_MAX);
  for (std::size_t c = 0; c < vertex.size(); ++c) {
    const std::size_t g = corner_group[c];
    if (g == SIZE_MAX || pick_of_group[g] != SIZE_MAX) continue;
    const double len = sum[g].norm();
    if (!(len > 0.0) || !std::isfinite(len)) continue;  // no area now: picks another (below)
    const Vec3 n = sum[g] / len;
    std::vector<Vec3>& normals = out.lines[line_of_group[g]];
    std::size_t k = 0;
    while (k < normals.size() && normals[k] != n) ++k;
    if (k == normals.size()) normals.push_back(n);
    pick_of_group[g] = k;
  }
  // A corner whose polygons have no area any more takes its line's first normal (the line as
  // read, when none of its groups has an area).
  for (std::size_t c = 0; c < vertex.size(); ++c)
    if (corner_group[c] != SIZE_MAX && pick_of_group[corner_group[c]] != SIZE_MAX)
      out.pick[c] = pick_of_group[corner_group[c]];
  return out;
}

}  // namespace shellcontract
