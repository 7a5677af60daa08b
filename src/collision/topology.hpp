// The connectivity the collision handling needs (unique edges, face-edge incidence, pair
// counts), built once per mesh. Eigen and std only.
#pragma once

#include <cstdint>
#include <vector>

#include "shellcontract/types.hpp"

namespace shellcontract {

/// Unique mesh edges, one row per edge, smaller vertex id first (#E by 2).
using Edges = Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>;

/// Edge ids of each face's three sides (#F by 3): column k is the side from corner k to corner
/// (k+1) mod 3.
using FaceEdges = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Connectivity the broad phase needs; built once per mesh by make_collision_topology and reused
/// every step (positions change, connectivity does not).
struct CollisionTopology {
  Faces faces;           ///< #F by 3 vertex ids (a copy of the input)
  Edges edges;           ///< #E by 2, edges(e, 0) < edges(e, 1), rows sorted lexicographically
  FaceEdges face_edges;  ///< #F by 3 edge ids, see FaceEdges
  int num_vertices = 0;  ///< #V; every vertex 0..#V-1 is a VF candidate, referenced or not
  std::vector<int> orphan_vertices;  ///< the vertices no face references, increasing
  /// VF pairs with the vertex not a corner of the face: #V #F - 3 #F (paper Table 2 "no culling").
  std::int64_t all_vertex_face_pairs = 0;
  /// EE pairs a < b sharing no vertex: #E(#E-1)/2 - sum_v deg(v)(deg(v)-1)/2.
  std::int64_t all_edge_edge_pairs = 0;
};

/// Builds the unique edges and face-edge incidence of a triangle mesh.
/// @param faces         #F by 3 vertex ids in [0, num_vertices), three distinct ids per face
/// @param num_vertices  #V, the number of rows of the position arrays that will be passed later
/// @return the topology; edge ids are deterministic (lexicographic order of (min id, max id))
/// @throws InputError if a face has an id out of range or a repeated corner
/// @throws UsageError if num_vertices < 0
/// \note The mesh need not be closed or manifold: the broad phase only needs ids.
CollisionTopology make_collision_topology(const Faces& faces, int num_vertices);

}  // namespace shellcontract
