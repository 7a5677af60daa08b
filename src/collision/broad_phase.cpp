// CCD broad phase (math-spec 10.1-10.2): swept boxes, CGAL box_intersection_d, candidate pairs.
#include "shellcontract/collision/broad_phase.hpp"

#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "shellcontract/core/error.hpp"

namespace shellcontract {

namespace {

using detail::BroadPhaseBox;
using detail::BroadPhaseScratch;

/// CGAL's cutoff: below this many boxes a subproblem is solved by a scan. Its default (10) was
/// the best of 10, 20, 50, 100 on bear (bench_broad_phase).
constexpr std::ptrdiff_t BOX_CUTOFF = 10;

std::uint64_t pack(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

/// Closed-interval overlap on all three axes: the same test CGAL applies with Topology CLOSED.
bool overlap(const BroadPhaseBox& a, const BroadPhaseBox& b) {
  return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1] &&
         a.lo[2] <= b.hi[2] && b.lo[2] <= a.hi[2];
}

void grow(BroadPhaseBox& box, const BroadPhaseBox& other) {
  for (std::size_t d = 0; d < 3; ++d) {
    box.lo[d] = std::min(box.lo[d], other.lo[d]);
    box.hi[d] = std::max(box.hi[d], other.hi[d]);
  }
}

bool is_corner(int v, const Faces& faces, int f) {
  return faces(f, 0) == v || faces(f, 1) == v || faces(f, 2) == v;
}

bool share_vertex(const Edges& edges, int a, int b) {
  return edges(a, 0) == edges(b, 0) || edges(a, 0) == edges(b, 1) || edges(a, 1) == edges(b, 0) ||
         edges(a, 1) == edges(b, 1);
}

void check_inputs(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                  double inflation) {
  if (x0.rows() != topo.num_vertices || x1.rows() != topo.num_vertices)
    throw UsageError("broad phase: position arrays have " + std::to_string(x0.rows()) + " and " +
                     std::to_string(x1.rows()) + " rows, the topology has " +
                     std::to_string(topo.num_vertices) + " vertices");
  if (!(inflation >= 0.0) || !std::isfinite(inflation))
    throw UsageError("broad phase: inflation must be finite and >= 0, got " +
                     std::to_string(inflation));
}

/// Swept, inflated boxes of every vertex, face and edge (math-spec 10.2). Face and edge boxes are
/// unions of their inflated vertex boxes, which equals min/max over the corner positions minus /
/// plus the inflation exactly, because rounding of x - inflation is monotone in x.
/// Box ids: vertices 0..V-1, faces V..V+F-1 (distinct from vertex ids, because CGAL skips pairs
/// with equal ids even in bipartite mode), edges 0..E-1 (only ever compared with edges).
void build_boxes(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                 double inflation, BroadPhaseScratch& s, bool need_faces, bool need_edges) {
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  s.vertex_boxes.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    BroadPhaseBox& b = s.vertex_boxes[v];
    const Eigen::Index i = static_cast<Eigen::Index>(v);
    for (std::size_t d = 0; d < 3; ++d) {
      const double a = x0(i, static_cast<Eigen::Index>(d));
      const double c = x1(i, static_cast<Eigen::Index>(d));
      b.lo[d] = std::min(a, c) - inflation;
      b.hi[d] = std::max(a, c) + inflation;
    }
    b.box_id = v;
  }
  if (need_faces) {
    const std::size_t nf = static_cast<std::size_t>(topo.faces.rows());
    s.face_boxes.resize(nf);
    for (std::size_t f = 0; f < nf; ++f) {
      const Eigen::Index j = static_cast<Eigen::Index>(f);
      BroadPhaseBox& b = s.face_boxes[f];
      b = s.vertex_boxes[static_cast<std::size_t>(topo.faces(j, 0))];
      grow(b, s.vertex_boxes[static_cast<std::size_t>(topo.faces(j, 1))]);
      grow(b, s.vertex_boxes[static_cast<std::size_t>(topo.faces(j, 2))]);
      b.box_id = nv + f;
    }
  }
  if (need_edges) {
    const std::size_t ne = static_cast<std::size_t>(topo.edges.rows());
    s.edge_boxes.resize(ne);
    for (std::size_t e = 0; e < ne; ++e) {
      const Eigen::Index k = static_cast<Eigen::Index>(e);
      BroadPhaseBox& b = s.edge_boxes[e];
      b = s.vertex_boxes[static_cast<std::size_t>(topo.edges(k, 0))];
      grow(b, s.vertex_boxes[static_cast<std::size_t>(topo.edges(k, 1))]);
      b.box_id = e;
    }
  }
}

/// Sorts and deduplicates packed keys, then unpacks them into pairs (deterministic output).
void keys_to_pairs(std::vector<std::uint64_t>& keys, std::vector<std::array<int, 2>>& pairs) {
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  pairs.resize(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i)
    pairs[i] = {static_cast<int>(keys[i] >> 32), static_cast<int>(keys[i] & 0xffffffffu)};
}

/// Runs CGAL's box_intersection_d on copies of `a` and `b` (it reorders its input ranges, and the
/// complete mode needs two separate copies of the same boxes, as box_self_intersection_d makes;
/// we keep the copies in scratch to avoid its allocation).
template <class Callback>
void box_search(const std::vector<BroadPhaseBox>& a, const std::vector<BroadPhaseBox>& b,
                CGAL::Box_intersection_d::Setting setting, BroadPhaseScratch& s,
                Callback callback) {
  s.work_a.assign(a.begin(), a.end());
  s.work_b.assign(b.begin(), b.end());
  CGAL::box_intersection_d(s.work_a.begin(), s.work_a.end(), s.work_b.begin(), s.work_b.end(),
                           callback, BOX_CUTOFF, CGAL::Box_intersection_d::CLOSED, setting);
}

/// Method PrimitiveBoxes: VF by a bipartite search, EE by a complete (self) search.
/// @return number of overlapping box pairs CGAL reported
std::int64_t primitive_boxes(const CollisionTopology& topo, CandidatePairs& out) {
  BroadPhaseScratch& s = out.scratch;
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  std::int64_t reported = 0;

  s.vf_keys.clear();
  box_search(s.vertex_boxes, s.face_boxes, CGAL::Box_intersection_d::BIPARTITE, s,
             [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
               ++reported;
               // Bipartite mode passes (box of range 1, box of range 2); check anyway, it is free.
               const BroadPhaseBox& vb = a.box_id < nv ? a : b;
               const BroadPhaseBox& fb = a.box_id < nv ? b : a;
               const int v = static_cast<int>(vb.box_id);
               const int f = static_cast<int>(fb.box_id - nv);
               if (!is_corner(v, topo.faces, f)) s.vf_keys.push_back(pack(v, f));
             });
  keys_to_pairs(s.vf_keys, out.vertex_face);

  s.ee_keys.clear();
  box_search(s.edge_boxes, s.edge_boxes, CGAL::Box_intersection_d::COMPLETE, s,
             [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
               ++reported;
               const int ea = static_cast<int>(a.box_id);
               const int eb = static_cast<int>(b.box_id);
               if (!share_vertex(topo.edges, ea, eb))
                 s.ee_keys.push_back(pack(std::min(ea, eb), std::max(ea, eb)));
             });
  keys_to_pairs(s.ee_keys, out.edge_edge);
  return reported;
}

/// Method FacePairs (math-spec 10.2): overlapping face pairs, then their 6 VF and 9 EE pairs.
/// Unlike math-spec 10.2 we keep face pairs that share a vertex: a VF or EE pair whose every
/// containing face pair shares a vertex (e.g. a valence-3 vertex against the face across its
/// link) would otherwise be lost, and the result would differ from the primitive-box definition.
/// Each primitive pair is box-tested itself, so the result equals PrimitiveBoxes exactly: a
/// primitive's box lies inside each of its faces' boxes, so every overlapping primitive pair has
/// an overlapping face pair (two different faces, since adjacent pairs are excluded).
/// @return number of overlapping face box pairs
std::int64_t face_pairs(const CollisionTopology& topo, CandidatePairs& out) {
  BroadPhaseScratch& s = out.scratch;
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  const Faces& faces = topo.faces;
  std::int64_t reported = 0;
  s.vf_keys.clear();
  s.ee_keys.clear();
  // The vertices of g against face h.
  auto vertices_vs_face = [&](int g, int h) {
    const BroadPhaseBox& hb = s.face_boxes[static_cast<std::size_t>(h)];
    for (int k = 0; k < 3; ++k) {
      const int v = faces(g, k);
      if (!is_corner(v, faces, h) && overlap(s.vertex_boxes[static_cast<std::size_t>(v)], hb))
        s.vf_keys.push_back(pack(v, h));
    }
  };
  box_search(s.face_boxes, s.face_boxes, CGAL::Box_intersection_d::COMPLETE, s,
             [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
               ++reported;
               const int g = static_cast<int>(a.box_id - nv);
               const int h = static_cast<int>(b.box_id - nv);
               vertices_vs_face(g, h);
               vertices_vs_face(h, g);
               for (int i = 0; i < 3; ++i) {
                 const int ea = topo.face_edges(g, i);
                 const BroadPhaseBox& ab = s.edge_boxes[static_cast<std::size_t>(ea)];
                 for (int j = 0; j < 3; ++j) {
                   const int eb = topo.face_edges(h, j);
                   if (!share_vertex(topo.edges, ea, eb) &&
                       overlap(ab, s.edge_boxes[static_cast<std::size_t>(eb)]))
                     s.ee_keys.push_back(pack(std::min(ea, eb), std::max(ea, eb)));
                 }
               }
             });
  keys_to_pairs(s.vf_keys, out.vertex_face);
  keys_to_pairs(s.ee_keys, out.edge_edge);
  return reported;
}

/// Thrown by has_any_candidate's callbacks to stop CGAL's search at the first pair.
struct CandidateFound {};

}  // namespace

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
      sides.emplace_back(pack(std::min(a, b), std::max(a, b)), 3 * f + k);
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

  // Table 2 "no culling": every pair a brute-force narrow phase would test.
  topo.all_vertex_face_pairs = static_cast<std::int64_t>(num_vertices) * nf - 3 * nf;
  std::int64_t sharing = 0;  // unordered edge pairs with a common vertex (exactly one, edges unique)
  for (const std::int64_t d : degree) sharing += d * (d - 1) / 2;
  topo.all_edge_edge_pairs = static_cast<std::int64_t>(ne) * (ne - 1) / 2 - sharing;
  return topo;
}

void find_candidates(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                     double inflation, CandidatePairs& out, BroadPhaseStats* stats,
                     BroadPhaseMethod method) {
  const auto start = std::chrono::steady_clock::now();
  check_inputs(x0, x1, topo, inflation);
  build_boxes(x0, x1, topo, inflation, out.scratch, true, true);
  std::int64_t reported = 0;
  switch (method) {
    case BroadPhaseMethod::PrimitiveBoxes:
      reported = primitive_boxes(topo, out);
      break;
    case BroadPhaseMethod::FacePairs:
      reported = face_pairs(topo, out);
      break;
  }
  if (stats) {
    stats->no_culling_vertex_face = topo.all_vertex_face_pairs;
    stats->no_culling_edge_edge = topo.all_edge_edge_pairs;
    stats->box_overlaps = reported;
    stats->vertex_face = static_cast<std::int64_t>(out.vertex_face.size());
    stats->edge_edge = static_cast<std::int64_t>(out.edge_edge.size());
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
}

bool has_any_candidate(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                       double inflation, detail::BroadPhaseScratch& scratch) {
  check_inputs(x0, x1, topo, inflation);
  build_boxes(x0, x1, topo, inflation, scratch, true, true);
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  // CGAL offers no early exit; an exception out of the callback is the documented-safe way to
  // stop (the boxes are copies in scratch, so their reordering does not matter).
  try {
    box_search(scratch.vertex_boxes, scratch.face_boxes, CGAL::Box_intersection_d::BIPARTITE,
               scratch, [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
                 const BroadPhaseBox& vb = a.box_id < nv ? a : b;
                 const BroadPhaseBox& fb = a.box_id < nv ? b : a;
                 if (!is_corner(static_cast<int>(vb.box_id), topo.faces,
                                static_cast<int>(fb.box_id - nv)))
                   throw CandidateFound{};
               });
    box_search(scratch.edge_boxes, scratch.edge_boxes, CGAL::Box_intersection_d::COMPLETE,
               scratch, [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
                 if (!share_vertex(topo.edges, static_cast<int>(a.box_id),
                                   static_cast<int>(b.box_id)))
                   throw CandidateFound{};
               });
  } catch (const CandidateFound&) {
    return true;
  }
  return false;
}

}  // namespace shellcontract
