// The collision topology: unique edges, face-edge incidence and the pair counts of the paper's
// Table 2.
#include "collision/topology.hpp"

#include <algorithm>
#include <string>

#include "collision/broad_phase/boxes.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {

CollisionTopology make_collision_topology(const Faces& faces, int num_vertices) {
  if (num_vertices < 0)
    throw UsageError("make_collision_topology: negative vertex count " +
                     std::to_string(num_vertices));
  CollisionTopology topo;
  topo.faces = faces;
  topo.num_vertices = num_vertices;
  const Eigen::Index nf = faces.rows();
  for (Eigen::Index f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k)
      if (faces(f, k) < 0 || faces(f, k) >= num_vertices)
        throw InputError("make_collision_topology: face " + std::to_string(f) + " has vertex id " +
                         std::to_string(faces(f, k)) + " outside [0, " +
                         std::to_string(num_vertices) + ")");
    if (faces(f, 0) == faces(f, 1) || faces(f, 1) == faces(f, 2) || faces(f, 2) == faces(f, 0))
      throw InputError("make_collision_topology: face " + std::to_string(f) +
                       " has a repeated vertex");
  }

  // Sides as (packed sorted vertex pair, face * 3 + k); sorting gives lexicographic edge ids.
  std::vector<std::pair<std::uint64_t, Eigen::Index>> sides;
  sides.reserve(static_cast<std::size_t>(3 * nf));
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      sides.emplace_back(detail::pack(std::min(a, b), std::max(a, b)), 3 * f + k);
    }
  std::sort(sides.begin(), sides.end());
  topo.face_edges.resize(nf, 3);
  std::vector<std::uint64_t> unique_keys;
  unique_keys.reserve(sides.size() / 2 + 1);
  for (const auto& [key, slot] : sides) {
    if (unique_keys.empty() || unique_keys.back() != key) unique_keys.push_back(key);
    topo.face_edges(slot / 3, static_cast<Eigen::Index>(slot % 3)) =
        static_cast<int>(unique_keys.size()) - 1;
  }
  const Eigen::Index ne = static_cast<Eigen::Index>(unique_keys.size());
  topo.edges.resize(ne, 2);
  std::vector<std::int64_t> degree(static_cast<std::size_t>(num_vertices), 0);
  for (Eigen::Index e = 0; e < ne; ++e) {
    const std::uint64_t key = unique_keys[static_cast<std::size_t>(e)];
    topo.edges(e, 0) = static_cast<int>(key >> 32);
    topo.edges(e, 1) = static_cast<int>(key & 0xffffffffu);
    ++degree[static_cast<std::size_t>(topo.edges(e, 0))];
    ++degree[static_cast<std::size_t>(topo.edges(e, 1))];
  }

  std::vector<std::uint8_t> referenced(static_cast<std::size_t>(num_vertices), 0);
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) referenced[static_cast<std::size_t>(faces(f, k))] = 1;
  for (int v = 0; v < num_vertices; ++v)
    if (!referenced[static_cast<std::size_t>(v)]) topo.orphan_vertices.push_back(v);

  // Table 2 "no culling": every pair a brute-force narrow phase would test.
  topo.all_vertex_face_pairs = static_cast<std::int64_t>(num_vertices) * nf - 3 * nf;
  std::int64_t sharing =
      0;  // unordered edge pairs with a common vertex (exactly one, edges unique)
  for (const std::int64_t d : degree) sharing += d * (d - 1) / 2;
  topo.all_edge_edge_pairs = static_cast<std::int64_t>(ne) * (ne - 1) / 2 - sharing;
  return topo;
}

}  // namespace shellcontract
