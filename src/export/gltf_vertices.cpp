// The .glb's vertices: split at UV seams and at the input's hard edges (gltf_vertices.hpp).
#include "export/gltf_vertices.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

namespace shellcontract::gltf {

VertexSplit split_vertices(const GltfAnimation& a) {
  const Eigen::Index nv = a.frames[0].rows();
  const auto n = static_cast<std::size_t>(nv);
  const bool with_uv = a.face_uv.rows() > 0, with_groups = a.face_normal.rows() > 0;
  const bool with_colour = a.face_colour.rows() > 0, with_region = !a.face_region.empty();
  const bool with_polygons = !a.face_polygon.empty();
  VertexSplit s;
  s.faces = a.faces;
  s.source.resize(n);
  for (Eigen::Index i = 0; i < nv; ++i) s.source[static_cast<std::size_t>(i)] = i;
  if (!with_uv && !with_groups && !with_colour && !with_region) return s;

  // Colours by value: copies of a vertex whose colours are equal (most seam copies) are not
  // split for their colour, only those that differ. Per colour row, the first row of its value.
  std::vector<int> colour_class(static_cast<std::size_t>(a.colour.rows()));
  {
    std::map<std::array<double, 4>, int> first;
    for (Eigen::Index c = 0; c < a.colour.rows(); ++c) {
      const std::array<double, 4> v{a.colour(c, 0), a.colour(c, 1), a.colour(c, 2), a.colour(c, 3)};
      colour_class[static_cast<std::size_t>(c)] =
          first.emplace(v, static_cast<int>(c)).first->second;
    }
  }

  // A vertex has a hard edge where its corners are in more than one normal group (a corner
  // without a normal, -1, counts as one): only there does the group split it. A smooth vertex's
  // corners keep the one normal of the simulation mesh, so that nothing changes for a file whose
  // normals are smooth, or for one without normals.
  std::vector<char> hard(n, 0), seen(n, 0);
  std::vector<int> first_group(n, -1);
  if (with_groups)
    for (Eigen::Index f = 0; f < a.faces.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        const auto v = static_cast<std::size_t>(a.faces(f, k));
        const int g = a.face_normal(f, k);
        if (!seen[v]) {
          seen[v] = 1;
          first_group[v] = g;
        } else if (first_group[v] != g) {
          hard[v] = 1;
        }
      }

  // Per glTF vertex its key (texture coordinate, normal group at a hard vertex, colour, region;
  // -1: none), and per simulation vertex the copies made so far. The region is in the key so
  // that a face's corners all carry its region's id: a vertex on a region's rim, shared with
  // faces of no region, would otherwise blend two categories across those faces.
  using Key = std::array<int, 4>;
  std::vector<Key> key(n, Key{-1, -1, -1, -1});
  std::vector<char> keyed(n, 0);
  std::vector<std::vector<std::pair<Key, int>>> copies(n);
  std::vector<std::vector<std::pair<int, int>>> slots(n);  // per vertex: (group, hard slot)
  s.normal.assign(n, -1);
  for (Eigen::Index f = 0; f < a.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = a.faces(f, k);
      const auto vs = static_cast<std::size_t>(v);
      const int group = hard[vs] ? a.face_normal(f, k) : -1;
      const Key want{with_uv ? a.face_uv(f, k) : -1, group,
                     with_colour ? colour_class[static_cast<std::size_t>(a.face_colour(f, k))] : -1,
                     with_region ? a.face_region[static_cast<std::size_t>(f)] : -1};
      // The hard group's slot, and this face's polygon in its list, once (a polygon's triangles
      // that share the vertex come one after the other, but not always: look at all).
      int slot = -1;
      if (group >= 0) {
        for (const auto& [g, id] : slots[vs])
          if (g == group) slot = id;
        if (slot < 0) {
          slot = static_cast<int>(s.hard.size());
          s.hard.emplace_back();
          slots[vs].emplace_back(group, slot);
        }
        std::vector<int>& polygons = s.hard[static_cast<std::size_t>(slot)];
        const int p =
            with_polygons ? a.face_polygon[static_cast<std::size_t>(f)] : static_cast<int>(f);
        if (std::find(polygons.begin(), polygons.end(), p) == polygons.end()) polygons.push_back(p);
      }
      if (!keyed[vs]) {
        keyed[vs] = 1;
        key[vs] = want;
        s.normal[vs] = slot;
      }
      if (key[vs] == want) continue;
      int id = -1;
      for (const auto& [have, copy] : copies[vs])
        if (have == want) id = copy;
      if (id < 0) {
        id = static_cast<int>(s.source.size());
        s.source.push_back(v);
        key.push_back(want);
        s.normal.push_back(slot);
        copies[vs].emplace_back(want, id);
      }
      s.faces(f, k) = id;
    }
  if (with_uv) {
    s.uv.resize(s.source.size());
    for (std::size_t i = 0; i < s.source.size(); ++i) s.uv[i] = key[i][0];
  }
  if (with_colour) {
    s.colour.resize(s.source.size());
    for (std::size_t i = 0; i < s.source.size(); ++i) s.colour[i] = key[i][2];
  }
  if (with_region) {
    s.region.resize(s.source.size());
    for (std::size_t i = 0; i < s.source.size(); ++i) s.region[i] = key[i][3];
  }
  if (s.hard.empty())
    s.normal.clear();  // every vertex smooth
  else if (with_polygons)
    s.polygon = a.face_polygon;
  return s;
}

Positions split_normals(const VertexSplit& s, const Positions& x, const Faces& faces) {
  const Positions smooth = vertex_normals(x, faces);
  Positions out(static_cast<Eigen::Index>(s.source.size()), 3);
  for (std::size_t i = 0; i < s.source.size(); ++i)
    out.row(static_cast<Eigen::Index>(i)) = smooth.row(s.source[i]);
  if (s.normal.empty()) return out;
  // Each polygon's vector area (twice its area along its normal: the sum of its triangles',
  // as vertex_normals weighs a face), and each hard group's sum of its polygons'; a group whose
  // polygons have no area takes the smooth normal.
  std::vector<Vec3> area(static_cast<std::size_t>(faces.rows()), Vec3::Zero());
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Vec3 a = x.row(faces(f, 0)), b = x.row(faces(f, 1)), c = x.row(faces(f, 2));
    const auto p =
        static_cast<std::size_t>(s.polygon.empty() ? f : s.polygon[static_cast<std::size_t>(f)]);
    area[p] += (b - a).cross(c - a);
  }
  std::vector<Vec3> hard(s.hard.size());
  std::vector<char> has_area(s.hard.size(), 0);
  for (std::size_t g = 0; g < s.hard.size(); ++g) {
    Vec3 sum = Vec3::Zero();
    for (const int p : s.hard[g]) sum += area[static_cast<std::size_t>(p)];
    const double len = sum.norm();
    if (len > 0.0 && std::isfinite(len)) {
      hard[g] = sum / len;
      has_area[g] = 1;
    }
  }
  for (std::size_t i = 0; i < s.source.size(); ++i) {
    const int g = s.normal[i];
    if (g >= 0 && has_area[static_cast<std::size_t>(g)])
      out.row(static_cast<Eigen::Index>(i)) = hard[static_cast<std::size_t>(g)].transpose();
  }
  return out;
}

}  // namespace shellcontract::gltf
