#include "sim/dimple_rest.hpp"

#include <algorithm>
#include <map>
#include <utility>

#include "bending/dihedral_bending.hpp"
#include "fem/triangle_element.hpp"

namespace shellcontract {

HingeIndex::HingeIndex(const std::vector<DihedralHingeConstraint>& hinges, const Faces& mesh_faces,
                       const std::vector<std::vector<int>>& regions) {
  // The edges by their vertex pair, once; the tables below are what set_dimple_rest reads.
  std::map<std::pair<int, int>, std::size_t> record_of_edge;  // (lower, higher vertex id)
  built_angle.reserve(hinges.size());
  for (std::size_t i = 0; i < hinges.size(); ++i) {
    const auto [a, b] = std::minmax(hinges[i].v[0], hinges[i].v[1]);
    record_of_edge.emplace(std::make_pair(a, b), i);
    built_angle.push_back(hinges[i].rest.rest_angle);
  }
  const auto edge = [&](Eigen::Index f, int e) {
    return std::minmax(mesh_faces(f, e), mesh_faces(f, (e + 1) % 3));
  };
  std::map<std::pair<int, int>, std::pair<int, int>> faces_of_edge;  // its two faces (-1: none)
  for (Eigen::Index f = 0; f < mesh_faces.rows(); ++f)
    for (int e = 0; e < 3; ++e) {
      auto it = faces_of_edge.emplace(edge(f, e), std::make_pair(-1, -1)).first;
      (it->second.first < 0 ? it->second.first : it->second.second) = static_cast<int>(f);
    }
  const auto slots = static_cast<std::size_t>(3 * mesh_faces.rows());
  record_of_face_edge.assign(slots, -1);
  face_across.assign(slots, -1);
  for (Eigen::Index f = 0; f < mesh_faces.rows(); ++f)
    for (int e = 0; e < 3; ++e) {
      const auto key = edge(f, e);
      const auto slot = static_cast<std::size_t>(3 * f + e);
      const auto it = record_of_edge.find(key);
      if (it != record_of_edge.end()) record_of_face_edge[slot] = static_cast<int>(it->second);
      const auto [f0, f1] = faces_of_edge.at(key);
      face_across[slot] = f0 == f ? f1 : f0;
    }
  region_of_face.assign(static_cast<std::size_t>(mesh_faces.rows()), -1);
  for (std::size_t r = 0; r < regions.size(); ++r)
    for (int f : regions[r])
      if (f >= 0 && f < mesh_faces.rows()) region_of_face[static_cast<std::size_t>(f)] = static_cast<int>(r);
}

namespace {

/// Gives the dimpled rest state (set_dimple_rest's doc) to the faces of d and the hinges on
/// their edges, into `faces` and `set_hinges`, marking them in change's scratch.
void set_dimpled(ConstraintSolver& solver, const HingeIndex& hinges, const Positions& rest,
                 const Faces& mesh_faces, const RegionDimple& d, const RegionMirror& mirror,
                 DimpleRestChange& change, std::vector<int>& faces,
                 std::vector<std::size_t>& set_hinges) {
  // The dimple's vertices (d.dimple.vertices) in the dimpled rest state; every other vertex
  // stays at rest.
  const std::vector<int>& ids = d.dimple.vertices;
  std::vector<Vec3> placed(ids.size());
  for (std::size_t j = 0; j < ids.size(); ++j) placed[j] = Vec3(rest.row(ids[j]));
  for (std::size_t i = 0; i < mirror.moved.size(); ++i)
    placed[static_cast<std::size_t>(mirror.moved[i])] = mirror.image[i] + mirror.rest_centre;
  std::vector<int>& slot = change.dimple_slot;
  if (slot.size() != static_cast<std::size_t>(rest.rows()))
    slot.assign(static_cast<std::size_t>(rest.rows()), -1);
  for (std::size_t j = 0; j < ids.size(); ++j) slot[static_cast<std::size_t>(ids[j])] = static_cast<int>(j);
  const auto at = [&](int v) {
    const int j = slot[static_cast<std::size_t>(v)];
    return j >= 0 ? placed[static_cast<std::size_t>(j)] : Vec3(rest.row(v));
  };
  const std::vector<DihedralHingeConstraint>& records = solver.constraints().dihedral_hinges;
  const int region = hinges.region_of_face[static_cast<std::size_t>(d.order.front())];
  for (int k = 0; k < d.size; ++k) {
    const int f = d.order[static_cast<std::size_t>(k)];
    const TriangleRest r = triangle_rest(at(mesh_faces(f, 0)), at(mesh_faces(f, 1)), at(mesh_faces(f, 2)));
    if (!r.degenerate && solver.set_membrane_rest(f, r.Dm_inv, r.area)) {
      faces.push_back(f);
      change.face_set[static_cast<std::size_t>(f)] = 1;
    }
    for (int e = 0; e < 3; ++e) {
      const auto edge = 3 * static_cast<std::size_t>(f) + static_cast<std::size_t>(e);
      const int record = hinges.record_of_face_edge[edge];
      if (record < 0) continue;
      const int other = hinges.face_across[edge];
      const int across = other >= 0 ? hinges.region_of_face[static_cast<std::size_t>(other)] : -1;
      if (across >= 0 && across != region) continue;
      // Met before from the face across: the angle depends on the hinge only, so it was set then
      // or fails again.
      const auto h = static_cast<std::size_t>(record);
      if (change.hinge_set[h]) continue;
      const DihedralHingeConstraint& c = records[h];
      double theta = 0.0;
      if (!(c.rest.kappa > 0.0) || !dihedral_angle(at(c.v[0]), at(c.v[1]), at(c.v[2]), at(c.v[3]), theta))
        continue;
      solver.set_dihedral_rest_angle(h, theta);
      set_hinges.push_back(h);
      change.hinge_set[h] = 1;
    }
  }
  for (int v : ids) slot[static_cast<std::size_t>(v)] = -1;
}

}  // namespace

void set_dimple_rest(ConstraintSolver& solver, const HingeIndex& hinges, const Positions& rest,
                     const Faces& mesh_faces, const RegionDimple& d, const RegionMirror& mirror,
                     DimpleRestChange& change) {
  if (change.face_set.size() != static_cast<std::size_t>(mesh_faces.rows()))
    change.face_set.assign(static_cast<std::size_t>(mesh_faces.rows()), 0);
  if (change.hinge_set.size() != hinges.built_angle.size())
    change.hinge_set.assign(hinges.built_angle.size(), 0);
  std::vector<int> faces;
  std::vector<std::size_t> set_hinges;
  if (d.size > 0 && mirror.fallback == MirrorFallback::None)
    set_dimpled(solver, hinges, rest, mesh_faces, d, mirror, change, faces, set_hinges);
  // Then the last call's faces and hinges that this one did not set go back to their rest. Each
  // face and each hinge has rest data of its own, so the order of the two passes does not matter,
  // and what is set again would only have been put back to be overwritten.
  const auto at_rest = [&](int v) { return Vec3(rest.row(v)); };
  for (int f : change.faces) {
    if (change.face_set[static_cast<std::size_t>(f)]) continue;
    const TriangleRest r = triangle_rest(at_rest(mesh_faces(f, 0)), at_rest(mesh_faces(f, 1)),
                                         at_rest(mesh_faces(f, 2)));
    if (!r.degenerate) solver.set_membrane_rest(f, r.Dm_inv, r.area);
  }
  for (std::size_t h : change.hinges)
    if (!change.hinge_set[h]) solver.set_dihedral_rest_angle(h, hinges.built_angle[h]);
  for (int f : faces) change.face_set[static_cast<std::size_t>(f)] = 0;
  for (std::size_t h : set_hinges) change.hinge_set[h] = 0;
  change.faces = std::move(faces);
  change.hinges = std::move(set_hinges);
}

void set_dimple_rest(ConstraintSolver& solver, const HingeIndex& hinges, const Positions& rest,
                     const Faces& mesh_faces, const RegionDimple& d, DimpleRestChange& change) {
  set_dimple_rest(solver, hinges, rest, mesh_faces, d, make_region_mirror(rest, d.dimple), change);
}

}  // namespace shellcontract
