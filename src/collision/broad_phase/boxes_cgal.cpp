// The broad phase's CGAL methods: box_intersection_d on primitive boxes (PrimitiveBoxes) and
// on face boxes (FacePairs), and the early-exit check has_any_candidate.
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cstddef>

#include "collision/broad_phase/boxes.hpp"

namespace shellcontract {
namespace detail {

namespace {

/// CGAL's cutoff: below this many boxes a subproblem is solved by a scan instead of further
/// segment-tree recursion. 1000 was the fastest of the cutoffs tried on bear
/// (bench_broad_phase), well ahead of CGAL's default 10 (lab/history.md).
constexpr std::ptrdiff_t BOX_CUTOFF = 1000;

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

/// Thrown by has_any_candidate's callbacks to stop CGAL's search at the first pair.
struct CandidateFound {};

}  // namespace

std::int64_t primitive_boxes(const CollisionTopology& topo, CandidatePairs& out) {
  BroadPhaseScratch& s = *out.scratch;
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

std::int64_t face_pairs(const CollisionTopology& topo, CandidatePairs& out) {
  BroadPhaseScratch& s = *out.scratch;
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
  // Vertices no face references are in no face pair: their own bipartite search.
  if (!topo.orphan_vertices.empty()) {
    std::vector<BroadPhaseBox> orphans;
    orphans.reserve(topo.orphan_vertices.size());
    for (int v : topo.orphan_vertices)
      orphans.push_back(s.vertex_boxes[static_cast<std::size_t>(v)]);
    box_search(
        orphans, s.face_boxes, CGAL::Box_intersection_d::BIPARTITE, s,
        [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
          ++reported;
          const BroadPhaseBox& vb = a.box_id < nv ? a : b;
          const BroadPhaseBox& fb = a.box_id < nv ? b : a;
          s.vf_keys.push_back(pack(static_cast<int>(vb.box_id), static_cast<int>(fb.box_id - nv)));
        });
  }
  keys_to_pairs(s.vf_keys, out.vertex_face);
  keys_to_pairs(s.ee_keys, out.edge_edge);
  return reported;
}

}  // namespace detail

using detail::BroadPhaseBox;

bool has_any_candidate(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                       double inflation, CandidatePairs& buffers) {
  BroadPhaseScratch& scratch = *buffers.scratch;
  detail::check_inputs(x0, x1, topo, inflation);
  detail::build_boxes(x0, x1, topo, inflation, scratch, true, true);
  const std::size_t nv = static_cast<std::size_t>(topo.num_vertices);
  // CGAL offers no early exit; an exception out of the callback is the documented-safe way to
  // stop (the boxes are copies in scratch, so their reordering does not matter).
  try {
    detail::box_search(scratch.vertex_boxes, scratch.face_boxes,
                       CGAL::Box_intersection_d::BIPARTITE, scratch,
                       [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
                         const BroadPhaseBox& vb = a.box_id < nv ? a : b;
                         const BroadPhaseBox& fb = a.box_id < nv ? b : a;
                         if (!detail::is_corner(static_cast<int>(vb.box_id), topo.faces,
                                                static_cast<int>(fb.box_id - nv)))
                           throw detail::CandidateFound{};
                       });
    detail::box_search(scratch.edge_boxes, scratch.edge_boxes, CGAL::Box_intersection_d::COMPLETE,
                       scratch, [&](const BroadPhaseBox& a, const BroadPhaseBox& b) {
                         if (!detail::share_vertex(topo.edges, static_cast<int>(a.box_id),
                                                   static_cast<int>(b.box_id)))
                           throw detail::CandidateFound{};
                       });
  } catch (const detail::CandidateFound&) {
    return true;
  }
  return false;
}

}  // namespace shellcontract
