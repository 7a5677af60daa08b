// The broad phase's shared pieces: the primitives' swept boxes (math-spec 10.2), the input
// checks, pair keys, and the entry points of the methods find_candidates dispatches to
// (boxes_cgal.cpp, bvh.cpp; the grid's are in grid.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/broad_phase/scratch.hpp"

namespace shellcontract {
namespace detail {

inline std::uint64_t pack(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

/// Closed-interval overlap on all three axes: the same test CGAL applies with Topology CLOSED.
inline bool overlap(const BroadPhaseBox& a, const BroadPhaseBox& b) {
  return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1] &&
         a.lo[2] <= b.hi[2] && b.lo[2] <= a.hi[2];
}

inline void grow(BroadPhaseBox& box, const BroadPhaseBox& other) {
  for (std::size_t d = 0; d < 3; ++d) {
    box.lo[d] = std::min(box.lo[d], other.lo[d]);
    box.hi[d] = std::max(box.hi[d], other.hi[d]);
  }
}

inline bool is_corner(int v, const Faces& faces, int f) {
  return faces(f, 0) == v || faces(f, 1) == v || faces(f, 2) == v;
}

inline bool share_vertex(const Edges& edges, int a, int b) {
  return edges(a, 0) == edges(b, 0) || edges(a, 0) == edges(b, 1) || edges(a, 1) == edges(b, 0) ||
         edges(a, 1) == edges(b, 1);
}

void check_inputs(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                  double inflation);

/// Swept, inflated boxes of every vertex, face and edge (math-spec 10.2). Face and edge boxes are
/// unions of their inflated vertex boxes, which equals min/max over the corner positions minus /
/// plus the inflation exactly, because rounding of x - inflation is monotone in x.
/// Box ids: vertices 0..V-1, faces V..V+F-1 (distinct from vertex ids, because CGAL skips pairs
/// with equal ids even in bipartite mode), edges 0..E-1 (only ever compared with edges).
void build_boxes(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                 double inflation, BroadPhaseScratch& s, bool need_faces, bool need_edges);

/// Sorts and deduplicates packed keys, then unpacks them into pairs (deterministic output).
void keys_to_pairs(std::vector<std::uint64_t>& keys, NoZeroVector<std::array<int, 2>>& pairs);

/// Method PrimitiveBoxes: VF by a bipartite search, EE by a complete (self) search.
/// @return number of overlapping box pairs CGAL reported
std::int64_t primitive_boxes(const CollisionTopology& topo, CandidatePairs& out);

/// Method FacePairs (math-spec 10.2): overlapping face pairs, then their 6 VF and 9 EE pairs.
/// Unlike math-spec 10.2 we keep face pairs that share a vertex: a VF or EE pair whose every
/// containing face pair shares a vertex (e.g. a valence-3 vertex against the face across its
/// link) would otherwise be lost, and the result would differ from the primitive-box definition.
/// Each primitive pair is box-tested itself, so the result equals PrimitiveBoxes exactly: a
/// primitive's box lies inside each of its faces' boxes, so every overlapping primitive pair has
/// an overlapping face pair (two different faces, since adjacent pairs are excluded). Vertices
/// no face references are in no face pair: they are searched against the faces separately.
/// @return number of overlapping face box pairs (and unreferenced-vertex / face box pairs)
std::int64_t face_pairs(const CollisionTopology& topo, CandidatePairs& out);

/// Method Bvh: one query per vertex box (face tree) and per edge box (edge tree). Results come
/// grouped by the query id in increasing order, so sorting each short run sorts everything, and
/// each tree item is met at most once per query, so there are no duplicates.
/// @return number of overlapping box pairs found (VF, plus EE with a < b)
std::int64_t bvh_pairs(const CollisionTopology& topo, CandidatePairs& out);

}  // namespace detail
}  // namespace shellcontract
