// Reading a result of `run` with its input's polygon splits (`check --against`:
// docs/design/attributes.md, "`check --against` and `--fail-on-self-intersections`").
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {

/// Another file's polygons and the triangles read_input_mesh split each into: `run` simulated
/// those triangles, and a result written as that file's polygons is read back along them.
struct SplitsToFollow {
  std::string file;                                ///< the file they are of, for the warning
  std::vector<std::vector<std::size_t>> polygons;  ///< its polygons, in file order
  /// Per polygon, its triangles (corner triples) in read_input_mesh's face order; empty for a
  /// triangle.
  std::vector<std::vector<std::vector<std::size_t>>> triangles;
};

/// read_input_mesh(path, report), but each polygon of more than three corners that is polygon p
/// of `follow` (soup::split_like: the same corners in the same cycle) is split into
/// follow.triangles[p], wound like itself, instead of by its own shape; the other polygons are
/// split by their shape as read_input_mesh splits them. The split warning counts both.
/// @throws as read_input_mesh
Mesh read_input_mesh_following(const std::string& path, const SplitsToFollow& follow,
                               InputReport* report);

}  // namespace shellcontract
