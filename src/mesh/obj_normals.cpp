#include "mesh/obj_normals.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <unordered_map>

#include "mesh/normal_groups.hpp"
#include "mesh/seam_weld.hpp"

namespace shellcontract {
namespace {

/// A `vn` line and the bits of one of its new normals, -0.0 taken as 0.0 (they compare equal):
/// the key of that normal's place among the line's.
struct LineNormal {
  std::size_t line = 0;
  std::array<std::uint64_t, 3> bits{};
  bool operator==(const LineNormal& o) const { return line == o.line && bits == o.bits; }
};

struct LineNormalHash {
  std::size_t operator()(const LineNormal& k) const {
    std::uint64_t h = k.line;
    for (const std::uint64_t b : k.bits) h = (h ^ b) * 0x9E3779B97F4A7C15ull + (h >> 29);
    return static_cast<std::size_t>(h ^ (h >> 32));
  }
};

LineNormal line_normal(std::size_t line, const Vec3& n) {
  LineNormal k;
  k.line = line;
  for (Eigen::Index i = 0; i < 3; ++i) {
    const double v = n[i] + 0.0;  // -0.0 becomes 0.0
    std::memcpy(&k.bits[static_cast<std::size_t>(i)], &v, sizeof v);
  }
  return k;
}

}  // namespace

std::vector<long long> obj_corner_groups(const std::vector<std::size_t>& position_of,
                                         const ObjCorners& in) {
  const std::vector<std::size_t>& vertex = *in.corner_vertex;
  const std::vector<long long>& vn = *in.corner_vn;
  const std::vector<Vec3>& dir = *in.vn_dir;
  // The corners with a `vn` are soup::normal_groups' items: each stands at its vertex's first
  // corner, so that corners at one vertex with the same value are one group.
  std::vector<std::size_t> first_corner(position_of.size(), SIZE_MAX);
  std::vector<std::size_t> item_rep, item_corner;
  std::vector<Vec3> item_dir;
  for (std::size_t c = 0; c < vertex.size(); ++c) {
    if (vn[c] < 0) continue;
    if (vertex[c] >= position_of.size() || position_of[vertex[c]] >= position_of.size() ||
        static_cast<std::size_t>(vn[c]) >= dir.size())
      throw std::invalid_argument("obj_corner_groups: a corner's vertex or normal out of range");
    std::size_t& first = first_corner[position_of[vertex[c]]];
    if (first == SIZE_MAX) first = item_corner.size();
    item_rep.push_back(first);
    item_corner.push_back(c);
    item_dir.push_back(dir[static_cast<std::size_t>(vn[c])]);
  }
  const std::vector<std::size_t> group = soup::normal_groups(item_rep, item_dir);
  std::vector<long long> out(vertex.size(), -1);
  for (std::size_t i = 0; i < item_corner.size(); ++i)
    out[item_corner[i]] = static_cast<long long>(group[i]);
  return out;
}

ObjNormals obj_normals(const Positions& x, const ObjCorners& in) {
  const std::vector<std::size_t>& start = *in.polygon_start;
  const std::vector<std::size_t>& vertex = *in.corner_vertex;
  const std::vector<long long>& vn = *in.corner_vn;
  const std::vector<long long> corner_group =
      obj_corner_groups(soup::first_at_same_position(x), in);

  // Each group's sum of its polygons' Newell vectors (twice the area along the normal). The
  // corners are taken relative to the polygon's first: in the file's units a mesh far from the
  // origin (UTM metres) has terms of size |x|^2 that cancel down to the area, and the sum of
  // absolute cross products kept nothing of the normal but rounding (as the glTF writers, which
  // take edge vectors).
  std::vector<Vec3> sum;
  for (std::size_t p = 0; p + 1 < start.size(); ++p) {
    Vec3 newell = Vec3::Zero();
    const std::size_t b = start[p], e = start[p + 1];
    const Vec3 p0 =
        b < e ? Vec3(x.row(static_cast<Eigen::Index>(vertex[b])).transpose()) : Vec3::Zero();
    for (std::size_t c = b; c < e; ++c) {
      const std::size_t next = c + 1 < e ? c + 1 : b;
      const Vec3 pc = x.row(static_cast<Eigen::Index>(vertex[c])).transpose();
      const Vec3 pn = x.row(static_cast<Eigen::Index>(vertex[next])).transpose();
      newell += (pc - p0).cross(pn - p0);
    }
    for (std::size_t c = b; c < e; ++c) {
      if (corner_group[c] < 0) continue;
      const auto g = static_cast<std::size_t>(corner_group[c]);
      if (g >= sum.size()) sum.resize(g + 1, Vec3::Zero());
      sum[g] += newell;
    }
  }

  // Each line's normals, in order of their first corner: the distinct normals of the groups its
  // corners are in (a group may span lines: each of them gets its normal).
  ObjNormals out;
  out.lines.resize(in.vn_dir->size());
  out.pick.assign(vertex.size(), 0);
  // Each normal's place in its line by its bits (the normals are finite, so equal values are
  // equal bits but for the sign of zero): a search of the line's normals for every corner made a
  // line that many vertices share (one `vn` for the whole file) cost their square.
  // A group has one normal: its place in the line its last corner named is kept for the next.
  std::unordered_map<LineNormal, std::size_t, LineNormalHash> place;
  std::vector<std::size_t> group_line(sum.size(), SIZE_MAX), group_place(sum.size(), 0);
  for (std::size_t c = 0; c < vertex.size(); ++c) {
    if (corner_group[c] < 0) continue;
    const auto g = static_cast<std::size_t>(corner_group[c]);
    const auto line = static_cast<std::size_t>(vn[c]);
    if (group_line[g] == line) {
      out.pick[c] = group_place[g];
      continue;
    }
    const Vec3& s = sum[g];
    const double len = s.norm();
    // A corner whose polygons have no area any more takes its line's first normal (the line as
    // read, when none of its corners' groups has an area).
    if (!(len > 0.0) || !std::isfinite(len)) continue;
    const Vec3 n = s / len;
    std::vector<Vec3>& normals = out.lines[line];
    const auto [at, added] = place.try_emplace(line_normal(line, n), normals.size());
    if (added) normals.push_back(n);
    out.pick[c] = at->second;
    group_line[g] = line;
    group_place[g] = at->second;
  }
  return out;
}

}  // namespace shellcontract
