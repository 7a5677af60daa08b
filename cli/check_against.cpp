// `check MESH --against INPUT`: reading MESH as `run` simulated it, and its new face pairs
// (check_against.hpp).
#include "check_against.hpp"

#include <algorithm>
#include <array>
#include <exception>
#include <string>

#include "mesh/followed_split.hpp"
#include "mesh/formats.hpp"
#include "mesh/read_polygon_soup.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract::cli {

Polygons read_polygons(const std::string& path) {
  Polygons p;
  std::vector<Point3> points;
  SourceLines lines;
  read_polygon_soup(path, lower_extension(path), points, p.polygons, lines);
  for (std::size_t i = 0; i < p.polygons.size(); ++i) p.face_origin.push_back(i);
  for (std::size_t i = 0; i < p.polygons.size(); ++i)
    for (std::size_t k = 3; k < p.polygons[i].size(); ++k) p.face_origin.push_back(i);
  return p;
}

Mesh read_result_mesh(const std::string& path, const std::string& input_path,
                      const Mesh& input_mesh, const Polygons& in, InputReport* report) {
  // INPUT's triangles as read_input_mesh made them, by polygon (their corners as INPUT numbers
  // them, also where it welded seams; their winding is split_like's to set).
  SplitsToFollow follow;
  follow.file = input_path;
  follow.polygons = in.polygons;
  follow.triangles.resize(in.polygons.size());
  const std::vector<std::array<std::size_t, 3>> corners = input_faces(input_mesh);
  if (corners.size() == in.face_origin.size())
    for (std::size_t f = 0; f < corners.size(); ++f)
      if (in.polygons[in.face_origin[f]].size() > 3)
        follow.triangles[in.face_origin[f]].push_back(
            {corners[f][0], corners[f][1], corners[f][2]});
  try {
    return read_input_mesh_following(path, follow, report);
  } catch (const InputError& e) {
    // Where MESH's polygons are INPUT's, the same corners in the same cycles make the same
    // closed surface, so only the geometry can make it unusable (a component of MESH that
    // INPUT's diagonals leave without volume). MESH as its own shape splits it is then the mesh
    // checked, as without --against; if that is refused too, its refusal is the one given.
    InputReport own;
    Mesh mesh = read_input_mesh(path, &own);
    own.warnings.push_back("its polygons split along " + input_path +
                           "'s triangles (the ones 'run' simulated) do not make a usable mesh (" +
                           e.what() +
                           "): they are split by their own shape instead, so a folded polygon may "
                           "be checked along other diagonals than the simulated ones");
    if (report) *report = std::move(own);
    return mesh;
  }
}

NewPairs new_pairs(const std::string& path, const Mesh& mesh, const std::string& input_path,
                   const Mesh& input_mesh, const Polygons& in,
                   const std::vector<FacePair>& input_pairs) {
  const std::string not_same = path + " is not a result of " + input_path + ": ";
  // Vertices as the files number them (a mesh welded along its seams too: mesh_io.hpp).
  const std::size_t nv = input_vertex_count(mesh), input_nv = input_vertex_count(input_mesh);
  if (nv != input_nv || mesh.number_of_faces() != input_mesh.number_of_faces())
    throw UsageError(not_same + std::to_string(nv) + " vertices and " +
                     std::to_string(mesh.number_of_faces()) + " faces against " +
                     std::to_string(input_nv) + " and " +
                     std::to_string(input_mesh.number_of_faces()));
  std::vector<std::vector<std::size_t>> polygons_of(input_nv);
  for (std::size_t p = 0; p < in.polygons.size(); ++p)
    for (const std::size_t v : in.polygons[p]) polygons_of[v].push_back(p);
  // The input polygon of each result face: the one polygon around its first vertex that holds
  // all three of its vertices.
  NewPairs out;
  out.polygon.resize(mesh.number_of_faces());
  const std::vector<std::array<std::size_t, 3>> corners = input_faces(mesh);
  for (const FaceIndex f : mesh.faces()) {
    const std::array<std::size_t, 3>& fv = corners[f.idx()];
    bool found = false;
    for (const std::size_t p : polygons_of[fv[0]]) {
      const auto& poly = in.polygons[p];
      if (std::find(poly.begin(), poly.end(), fv[1]) != poly.end() &&
          std::find(poly.begin(), poly.end(), fv[2]) != poly.end()) {
        out.polygon[f.idx()] = p;
        found = true;
        break;
      }
    }
    if (!found)
      throw UsageError(not_same + "its face " + std::to_string(f.idx()) + " (vertices " +
                       std::to_string(fv[0]) + " " + std::to_string(fv[1]) + " " +
                       std::to_string(fv[2]) + ") is in no face of the input");
  }
  for (const FacePair& q : input_pairs) {
    const std::size_t a = in.face_origin[q.first.idx()], b = in.face_origin[q.second.idx()];
    out.before.insert({std::min(a, b), std::max(a, b)});
  }
  return out;
}

}  // namespace shellcontract::cli
