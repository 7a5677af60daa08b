// The .glb's vertices (docs/design/export.md, "Texture coordinates" and "Hard edges"): glTF has
// one set of attributes per vertex, so a simulation vertex whose corners differ in texture
// coordinates (a UV seam), in normal group (a hard edge of the input) or in region (a local
// contraction region's rim) is split into copies.
// The simulation's welded mesh is not changed: the copies move with their vertex.
#pragma once

#include <cstddef>
#include <vector>

#include "shellcontract/export.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract::gltf {

struct VertexSplit {
  std::vector<Eigen::Index> source;  ///< glTF vertex -> simulation vertex; identity for i < #V
  Faces faces;                       ///< the faces on the glTF's vertices
  /// Per glTF vertex, its texture coordinate's index into the animation's uv (-1: a vertex no
  /// face uses); empty without texture coordinates.
  std::vector<int> uv;
  /// Per glTF vertex, its colour's row in the animation's colour (-1: a vertex no face uses);
  /// empty without colours.
  std::vector<int> colour;
  /// Per glTF vertex, the region of its faces (GltfAnimation::face_region; -1: none, or a vertex
  /// no face uses); empty without regions.
  std::vector<int> region;
  /// Per glTF vertex, its normal: -1 the simulation vertex's smooth normal (vertex_normals),
  /// else an index into `hard`: the group of its corners at a vertex with a hard edge.
  std::vector<int> normal;
  /// Per hard normal group, the polygons (GltfAnimation::face_polygon; without: the faces) whose
  /// vector areas it sums, each once.
  std::vector<std::vector<int>> hard;
  std::vector<int> polygon;  ///< per face, its polygon; empty: each face its own
};

/// The split of `a`'s vertices by the texture coordinate (face_uv), the normal group
/// (face_normal), the colour (face_colour) and the region (face_region) of their corners. Glb
/// vertex i < #V is simulation vertex i with its first corner's, the copies follow in the order of
/// their first corners. Corners of a vertex whose corners all have one normal group (or none) share
/// the smooth normal: a mesh without normal groups is split at its UV seams only, as before they
/// were read.
/// @pre a is checked (write_gltf_animation's checks)
VertexSplit split_vertices(const GltfAnimation& a);

/// The normals of the glTF's vertices at positions x (#V by 3): a vertex's smooth normal is
/// vertex_normals', a hard group's the area-weighted normal of its polygons alone (the smooth
/// one where they have no area), so a hard edge stays hard as the shell moves.
Positions split_normals(const VertexSplit& s, const Positions& x, const Faces& faces);

}  // namespace shellcontract::gltf
