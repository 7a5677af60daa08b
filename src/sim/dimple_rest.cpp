#include "sim/dimple_rest.hpp"

#include <algorithm>

#include "bending/dihedral_bending.hpp"
#include "fem/triangle_element.hpp"
#include "sim/region_mirror.hpp"

namespace shellcontract {

HingeIndex::HingeIndex(const std::vector<DihedralHingeConstraint>& hinges, const Faces& mesh_faces,
                       const std::vector<std::vector<int>>& regions) {
  built_angle.reserve(hinges.size());
  for (std::size_t i = 0; i < hinges.size(); ++i) {
    const auto [a, b] = std::minmax(hinges[i].v[0], hinges[i].v[1]);
    record_of_edge.emplace(std::make_pair(a, b), i);
    built_angle.push_back(hinges[i].rest.rest_angle);
  }
  for (Eigen::Index f = 0; f < mesh_faces.rows(); ++f)
    for (int e = 0; e < 3; ++e) {
      const auto key = std::minmax(mesh_faces(f, e), mesh_faces(f, (e + 1) % 3));
      auto it = faces_of_edge.emplace(key, std::make_pair(-1, -1)).first;
      (it->second.first < 0 ? it->second.first : it->second.second) = static_cast<int>(f);
    }
  region_of_face.assign(static_cast<std::size_t>(mesh_faces.rows()), -1);
  for (std::size_t r = 0; r < regions.size(); ++r)
    for (int f : regions[r])
      if (f >= 0 && f < mesh_faces.rows()) region_of_face[static_cast<std::size_t>(f)] = static_cast<int>(r);
}

void set_dimple_rest(ConstraintSolver& solver, const HingeIndex& hinges, const Positions& rest,
                     const Faces& mesh_faces, const RegionDimple& d, DimpleRestChange& change) {
  const auto at_rest = [&](int v) { return Vec3(rest.row(v)); };
  const auto give = [&](int f, const Vec3& a, const Vec3& b, const Vec3& c) {
    const TriangleRest r = triangle_rest(a, b, c);
    return !r.degenerate && solver.set_membrane_rest(f, r.Dm_inv, r.area);
  };
  for (int f : change.faces)
    give(f, at_rest(mesh_faces(f, 0)), at_rest(mesh_faces(f, 1)), at_rest(mesh_faces(f, 2)));
  for (std::size_t h : change.hinges) solver.set_dihedral_rest_angle(h, hinges.built_angle[h]);
  change = DimpleRestChange{};
  if (d.size <= 0) return;
  const RegionMirror mirror = make_region_mirror(rest, d.dimple);
  if (mirror.fallback != MirrorFallback::None) return;
  // The dimple's vertices (d.dimple.vertices, sorted mesh ids) in the dimpled rest state; every
  // other vertex stays at rest.
  const std::vector<int>& ids = d.dimple.vertices;
  std::vector<Vec3> placed(ids.size());
  for (std::size_t j = 0; j < ids.size(); ++j) placed[j] = at_rest(ids[j]);
  for (std::size_t i = 0; i < mirror.moved.size(); ++i)
    placed[static_cast<std::size_t>(mirror.moved[i])] = mirror.image[i] + mirror.rest_centre;
  const auto at = [&](int v) {
    const auto it = std::lower_bound(ids.begin(), ids.end(), v);
    return it != ids.end() && *it == v ? placed[static_cast<std::size_t>(it - ids.begin())] : at_rest(v);
  };
  const std::vector<DihedralHingeConstraint>& records = solver.constraints().dihedral_hinges;
  const int region = hinges.region_of_face[static_cast<std::size_t>(d.order.front())];
  for (int k = 0; k < d.size; ++k) {
    const int f = d.order[static_cast<std::size_t>(k)];
    if (give(f, at(mesh_faces(f, 0)), at(mesh_faces(f, 1)), at(mesh_faces(f, 2))))
      change.faces.push_back(f);
    for (int e = 0; e < 3; ++e) {
      const auto [a, b] = std::minmax(mesh_faces(f, e), mesh_faces(f, (e + 1) % 3));
      const auto it = hinges.record_of_edge.find({a, b});
      if (it == hinges.record_of_edge.end()) continue;
      const auto [f0, f1] = hinges.faces_of_edge.at({a, b});
      const int other = f0 == f ? f1 : f0;
      const int across = other >= 0 ? hinges.region_of_face[static_cast<std::size_t>(other)] : -1;
      if (across >= 0 && across != region) continue;
      const DihedralHingeConstraint& c = records[it->second];
      double theta = 0.0;
      if (!(c.rest.kappa > 0.0) || !dihedral_angle(at(c.v[0]), at(c.v[1]), at(c.v[2]), at(c.v[3]), theta))
        continue;
      if (std::find(change.hinges.begin(), change.hinges.end(), it->second) != change.hinges.end()) continue;
      solver.set_dihedral_rest_angle(it->second, theta);
      change.hinges.push_back(it->second);
    }
  }
}

}  // namespace shellcontract
