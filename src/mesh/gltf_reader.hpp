// Reading a glTF 2.0 file (.glb or .gltf) into a triangle soup (read_polygon_soup's glTF step;
// docs/design/input-readers.md). tinygltf (compiled once, in
// src/export/tiny_gltf_implementation.cpp) parses the container and the JSON; every accessor,
// buffer view and index is checked here before a byte of a buffer is read, because tinygltf leaves
// most of those bounds to its caller.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace shellcontract {

/// The triangles of a glTF scene, in world coordinates.
struct GltfSoup {
  /// One primitive as the scene draws it.
  struct Drawn {
    std::size_t node, mesh, primitive;
  };
  /// Where a vertex comes from: the first drawn primitive (an index into `drawn`) whose
  /// triangles use it, and the element of its POSITION accessor. Every other primitive of the
  /// node that uses the vertex names the same POSITION, attribute and morph target accessors.
  struct Source {
    std::size_t drawn, element;
  };
  /// The primitives in the order they are drawn: the default scene's nodes depth first, each
  /// node's mesh's primitives in order.
  std::vector<Drawn> drawn;
  /// Every vertex that a drawn primitive's triangles use, at its world position: the node's
  /// transform and its ancestors' applied, in double precision. A vertex is an element of a
  /// POSITION accessor as one node draws it: primitives of the node that share the accessor and
  /// name the same accessors for every other attribute and morph target share its vertices
  /// (a mesh split into one primitive per material over one vertex buffer); a primitive whose
  /// other attributes differ has copies of its own. Node by node; within a node, per set of
  /// primitives sharing vertices (in the order of each set's first primitive), in accessor order.
  std::vector<std::array<double, 3>> points;
  std::vector<Source> sources;  ///< per point
  /// Triangles on `points`; a node whose transform mirrors (negative determinant) has its
  /// triangles' winding reversed, as the spec says a renderer does.
  std::vector<std::vector<std::size_t>> faces;
  /// Per face, the drawn primitive it is a triangle of (its material's).
  std::vector<std::size_t> face_drawn;
  /// Drawn primitives with morph targets, which are not applied: the points are the base shape.
  std::size_t morphed = 0;
};

/// Reads the triangle primitives (mode 4, or no mode) of the meshes the default scene (or scene
/// 0) draws. Vertices are not merged by position: a vertex that the file split at a UV or normal
/// seam stays split, and read_input_mesh welds the copies (seam_weld.hpp); an element of a
/// POSITION accessor that several primitives of a node draw alike is one vertex (`points`).
/// @param path  the file, for messages and as the folder of external buffers (.gltf)
/// @param bytes the whole file
/// @throws InputError "<path>: <problem>: <where>" for a file that is not a glTF 2.0 it can read:
///         a bad container or JSON, a primitive that is not triangles, a sparse or compressed
///         accessor, a required extension that changes the geometry, an index or offset out of
///         range, a buffer file that another buffer read already, a scene that draws more than 64
///         triangles for each byte of the file and its buffers (counted before any is read)
GltfSoup read_gltf(const std::string& path, const std::string& bytes);

}  // namespace shellcontract
