// `check MESH --against INPUT` (cli/check.cpp): MESH read along the triangles `run` simulated,
// INPUT's splits of its polygons, and MESH's face pairs told new or not by INPUT's polygons
// (docs/design/attributes.md, "`check --against` and `--fail-on-self-intersections`").
#pragma once

#include <algorithm>
#include <cstddef>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/validation.hpp"

namespace shellcontract::cli {

/// A file's polygons (as its reader gives them) and, per face of the mesh read_input_mesh makes
/// of it, the polygon that face comes from: face i < #polygons is polygon i's first triangle,
/// the other triangles of split polygons follow in polygon order.
struct Polygons {
  std::vector<std::vector<std::size_t>> polygons;
  std::vector<std::size_t> face_origin;
};

Polygons read_polygons(const std::string& path);

/// MESH (`path`) read as read_input_mesh reads it, but with each polygon that is INPUT's polygon of
/// the same index split into the triangles read_input_mesh made of INPUT's (`input_path`, read
/// into `input_mesh`, whose polygons are `in`): the triangles `run` simulated, whatever diagonal
/// MESH's own (folded) shape would choose. Where those do not make a usable mesh, MESH is read as
/// read_input_mesh reads it, with a warning that says so (`report`).
/// @throws what read_input_mesh throws for MESH
Mesh read_result_mesh(const std::string& path, const std::string& input_path,
                      const Mesh& input_mesh, const Polygons& in, InputReport* report);

/// Which face pairs of `mesh` are new: those whose polygons do not intersect in the input. A face
/// of the result belongs to the input polygon that holds its three vertices.
struct NewPairs {
  std::vector<std::size_t> polygon;  // per result face
  std::set<std::pair<std::size_t, std::size_t>> before;
  bool operator()(const FacePair& q) const {
    const std::size_t a = polygon[q.first.idx()], b = polygon[q.second.idx()];
    return !before.count({std::min(a, b), std::max(a, b)});
  }
};

/// NewPairs of `mesh` (read from `path`) against the input (`input_mesh`, read from input_path,
/// whose polygons are `in`, with pairs input_pairs).
/// @throws UsageError if the two files do not have the same vertices and polygons
NewPairs new_pairs(const std::string& path, const Mesh& mesh, const std::string& input_path,
                   const Mesh& input_mesh, const Polygons& in,
                   const std::vector<FacePair>& input_pairs);

}  // namespace shellcontract::cli
