// The part finder (RegionMethod::Parts; docs/math/part-finder.md, lab/regions/heads.md): the tip
// finder's limb ends together with the cap finder's heads and bumps, which the tip finder misses
// (a head is a ball around a centre, a bump barely changes the protrusion field).
//   1. both finders run with the same options: cap regions C (cap_finder.cpp) and tip regions T
//      (tip_finder.cpp);
//   2. a cap region is kept when at most COVERED of its area lies in tip regions: a limb end
//      that both finders found stays the tip finder's (better on every end,
//      lab/regions/tips.md), a head or a bump that no tip region covers is kept;
//   3. a tip region is dropped when more than INSIDE of its area lies in one kept cap region: it
//      is a piece of that head (bear's crown between its ears);
//   4. the kept tip regions keep their faces;
//   5. each kept cap region, in the cap finder's order, grows to its ball: the faces edge-connected
//      to it whose centroid lies within (1 + residual) radii of its fitted sphere's centre (the
//      sphere and the band of the fit's RMS distance), taking no face of a tip region, of another
//      cap region or of a ball grown before. The cap finder clips a part to a hemisphere of its
//      sphere; a head is the ball down to its neck, where the surface leaves the sphere;
//   6. the filters of both finders (faces, area share, compactness) on each region, its largest
//      edge-connected piece; a ball that fails them (ragged, from a sphere fitted loosely to a
//      flat board) falls back to its cap less the tip regions' faces; summaries from a sphere
//      fitted to each region's faces, ids by decreasing area.
// Both finders are invariant under rotation, scaling and vertex order, and every rule here reads
// only face areas, face sets (face order = input order) and distances to a fitted centre, so the
// result is too.
#include "geometry/part_finder.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "core/cancellation.hpp"
#include "geometry/cap_internal.hpp"
#include "geometry/tip_finder.hpp"

namespace shellcontract::detail {
namespace {

/// Step 2: a cap region more than half covered by tip regions is a limb end the tip finder has.
constexpr double COVERED = 0.5;
/// Step 3: a tip region more than half inside one kept cap region is a piece of that part.
constexpr double INSIDE = 0.5;

/// Per region id (0..n-1 of `ids`, n = `count`), its area.
std::vector<double> areas_of(const MeshArrays& m, const std::vector<int>& ids, std::size_t count) {
  std::vector<double> a(count, 0.0);
  for (std::size_t f = 0; f < m.nf; ++f)
    if (ids[f] >= 0) a[static_cast<std::size_t>(ids[f])] += m.face_area[f];
  return a;
}

/// The faces of `flag` edge-connected to a face of `seed` (seed is a subset of flag).
std::vector<char> reached_from(const MeshArrays& m, const std::vector<char>& flag, const std::vector<char>& seed) {
  std::vector<char> seen(m.nf, 0);
  std::vector<int> stack;
  for (std::size_t f = 0; f < m.nf; ++f)
    if (seed[f] && flag[f]) {
      seen[f] = 1;
      stack.push_back(static_cast<int>(f));
    }
  while (!stack.empty()) {
    const int f = stack.back();
    stack.pop_back();
    for (int g : m.face_nbr[static_cast<std::size_t>(f)])
      if (g >= 0 && flag[static_cast<std::size_t>(g)] && !seen[static_cast<std::size_t>(g)]) {
        seen[static_cast<std::size_t>(g)] = 1;
        stack.push_back(g);
      }
  }
  return seen;
}

}  // namespace

std::vector<int> select_part_regions(const Mesh& mesh, const Positions& x, const RegionOptions& options,
                                     RegionReport* report, CurvatureField* curvature) {
  // Step 1. The two finders read the mesh only and each gives the same result on any number of
  // threads, so they run side by side: the tip finder's Dijkstra passes are serial, and the
  // method would otherwise take the two finders' times added up.
  RegionOptions caps = options, tips = options;
  caps.method = RegionMethod::Caps;
  tips.method = RegionMethod::Tips;
  RegionReport cap_report, tip_report;
  std::vector<int> cap_ids, tip_ids;
  // The cap finder, whose smoothing and growth are parallel, on this thread; the tip finder,
  // mostly serial (its Dijkstra passes), beside it. Its worker stops once the run's thread has seen
  // a cancel, and the run's thread keeps asking while it waits for the worker (run_side_by_side).
  run_side_by_side(
      [&] { cap_ids = select_spherical_regions(mesh, x, caps, &cap_report, curvature); },
      [&] { tip_ids = select_tip_regions(mesh, x, tips, &tip_report, nullptr); });
  cancellation_point();
  const MeshArrays m = mesh_arrays(mesh, x);
  RegionReport r;
  r.total_area = m.total_area;
  r.reference_mean_curvature = cap_report.reference_mean_curvature;
  r.seed_vertices = cap_report.seed_vertices + tip_report.seed_vertices;
  r.candidates = cap_report.candidates + tip_report.candidates;
  r.dropped_small = cap_report.dropped_small + tip_report.dropped_small;
  r.dropped_large = cap_report.dropped_large + tip_report.dropped_large;
  r.dropped_flat = cap_report.dropped_flat + tip_report.dropped_flat;
  r.dropped_shape = cap_report.dropped_shape + tip_report.dropped_shape;
  r.stage_times = std::move(cap_report.stage_times);
  const std::size_t nc = cap_report.regions.size(), nt = tip_report.regions.size();
  const std::vector<double> cap_area = areas_of(m, cap_ids, nc), tip_area = areas_of(m, tip_ids, nt);
  // overlap[c * nt + t] = area of cap region c in tip region t.
  std::vector<double> overlap(nc * nt, 0.0), covered(nc, 0.0);
  for (std::size_t f = 0; f < m.nf; ++f)
    if (cap_ids[f] >= 0 && tip_ids[f] >= 0) {
      const auto c = static_cast<std::size_t>(cap_ids[f]), t = static_cast<std::size_t>(tip_ids[f]);
      overlap[c * nt + t] += m.face_area[f];
      covered[c] += m.face_area[f];
    }
  // Steps 2 and 3.
  std::vector<char> keep_cap(nc, 0), keep_tip(nt, 1);
  for (std::size_t c = 0; c < nc; ++c) keep_cap[c] = covered[c] <= COVERED * cap_area[c] ? 1 : 0;
  for (std::size_t t = 0; t < nt; ++t)
    for (std::size_t c = 0; c < nc; ++c)
      if (keep_cap[c] && overlap[c * nt + t] > INSIDE * tip_area[t]) keep_tip[t] = 0;
  // Step 4: the kept tip regions as they are.
  std::vector<int> owner(m.nf, -1);  // region of the result per face: tip t -> t, cap c -> nt + c
  std::vector<std::vector<int>> tip_faces(nt);
  for (std::size_t f = 0; f < m.nf; ++f)
    if (tip_ids[f] >= 0 && keep_tip[static_cast<std::size_t>(tip_ids[f])]) {
      owner[f] = tip_ids[f];
      tip_faces[static_cast<std::size_t>(tip_ids[f])].push_back(static_cast<int>(f));
    }
  const double h_ref = r.reference_mean_curvature;
  std::vector<std::pair<Cap, RegionSummary>> kept;
  // The filters; a failure is counted in the report when `count` (not for a ball that falls
  // back to its cap).
  const auto passes = [&](const RegionSummary& s, bool count) {
    std::size_t* dropped = failed_filter(s, options, r);
    if (dropped && count) ++*dropped;
    return dropped == nullptr;
  };
  for (std::size_t t = 0; t < nt; ++t)
    if (!tip_faces[t].empty()) {
      Cap cap = region_cap(m, x, tip_report.regions[t].seed_vertex, std::move(tip_faces[t]));
      const RegionSummary s = summarise(mesh, x, m, cap, h_ref);
      if (passes(s, true)) kept.emplace_back(std::move(cap), s);
    }
  // Steps 5 and 6, in the cap finder's id order (decreasing area): a ball takes no face of a
  // kept tip region, of another cap region or of a ball grown before it.
  for (std::size_t c = 0; c < nc; ++c) {
    cancellation_point();
    if (!keep_cap[c]) continue;
    const RegionSummary& sc = cap_report.regions[c];
    const double reach = (1.0 + sc.residual) * sc.radius;
    std::vector<char> free_cap(m.nf, 0), ball(m.nf, 0);
    for (std::size_t f = 0; f < m.nf; ++f) {
      if (owner[f] >= 0) continue;
      free_cap[f] = cap_ids[f] == static_cast<int>(c) ? 1 : 0;
      ball[f] = free_cap[f] || (cap_ids[f] < 0 && (face_centroid(m, x, static_cast<int>(f)) - sc.centre).norm() <= reach);
    }
    std::optional<std::pair<Cap, RegionSummary>> got;
    for (const std::vector<char>* flag : {&ball, &free_cap}) {
      std::vector<int> faces = largest_piece(m, reached_from(m, *flag, free_cap));
      if (faces.empty()) continue;
      Cap cap = region_cap(m, x, sc.seed_vertex, std::move(faces));
      const RegionSummary s = summarise(mesh, x, m, cap, h_ref);
      if (passes(s, flag == &free_cap)) {
        got.emplace(std::move(cap), s);
        break;
      }
    }
    if (!got) continue;
    for (int f : got->first.faces) owner[static_cast<std::size_t>(f)] = static_cast<int>(nt + c);
    kept.push_back(std::move(*got));
  }
  std::vector<int> region = number_regions(kept, m.nf, r, false);
  if (report) *report = std::move(r);
  return region;
}

}  // namespace shellcontract::detail
