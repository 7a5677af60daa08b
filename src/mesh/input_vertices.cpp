// The input's vertices of a mesh whose seams read_input_mesh or mesh_from_arrays welded
// (mesh_io.hpp, "Seams"): everything is derived from the f:input_corners map (seam_weld.hpp),
// so that a copy of the mesh carries it and nothing else has to travel beside the mesh.
#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh/properties.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

using Corners = std::array<std::size_t, 3>;

std::pair<Mesh::Property_map<FaceIndex, Corners>, bool> corners_map(const Mesh& mesh) {
  return mesh.property_map<FaceIndex, Corners>(property::INPUT_CORNERS);
}

}  // namespace

bool has_welded_seams(const Mesh& mesh) { return corners_map(mesh).second; }

std::size_t input_vertex_count(const Mesh& mesh) {
  const auto [corners, welded] = corners_map(mesh);
  if (!welded) return mesh.number_of_vertices();
  // Every input vertex is a corner (weld_seams refuses isolated ones).
  std::size_t n = 0;
  for (const FaceIndex f : mesh.faces()) n = std::max(n, *std::max_element(corners[f].begin(), corners[f].end()) + 1);
  return n;
}

std::vector<std::size_t> input_vertex_map(const Mesh& mesh) {
  const auto [corners, welded] = corners_map(mesh);
  std::vector<std::size_t> map(input_vertex_count(mesh));
  if (!welded) {
    for (std::size_t i = 0; i < map.size(); ++i) map[i] = i;
    return map;
  }
  for (const FaceIndex f : mesh.faces()) {
    std::size_t k = 0;
    for (const VertexIndex v : vertices_around_face(mesh.halfedge(f), mesh)) map[corners[f][k++]] = v.idx();
  }
  return map;
}

std::vector<std::array<std::size_t, 3>> input_faces(const Mesh& mesh) {
  const auto [corners, welded] = corners_map(mesh);
  std::vector<Corners> faces(mesh.number_of_faces());
  for (const FaceIndex f : mesh.faces()) {
    if (welded) {
      faces[f.idx()] = corners[f];
      continue;
    }
    std::size_t k = 0;
    for (const VertexIndex v : vertices_around_face(mesh.halfedge(f), mesh))
      if (k < 3) faces[f.idx()][k++] = v.idx();
  }
  return faces;
}

Positions input_positions(const Mesh& mesh, const Positions& x) {
  const auto rows = static_cast<std::size_t>(x.rows());
  if (!has_welded_seams(mesh)) {
    if (rows != mesh.number_of_vertices())
      throw std::invalid_argument("input_positions: " + std::to_string(rows) + " position rows for " +
                                  std::to_string(mesh.number_of_vertices()) + " vertices");
    return x;
  }
  const std::vector<std::size_t> map = input_vertex_map(mesh);
  if (rows == map.size()) return x;
  if (rows != mesh.number_of_vertices())
    throw std::invalid_argument("input_positions: " + std::to_string(rows) + " position rows for " +
                                std::to_string(mesh.number_of_vertices()) + " vertices (" +
                                std::to_string(map.size()) + " in the input)");
  Positions out(static_cast<Eigen::Index>(map.size()), 3);
  for (std::size_t i = 0; i < map.size(); ++i)
    out.row(static_cast<Eigen::Index>(i)) = x.row(static_cast<Eigen::Index>(map[i]));
  return out;
}

}  // namespace shellcontract
