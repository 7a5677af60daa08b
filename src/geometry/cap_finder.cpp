// The spherical-cap region finder (algorithm in shellcontract/regions.hpp, docs/design/regions.md
// and docs/math/cap-finder.md): diffusion-smoothed mean curvature -> seeds -> geodesic discs
// grown while a sphere fits -> ranked parts, one per sphere -> each a hemisphere at most.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/cancellation.hpp"
#include "core/constants.hpp"
#include "core/power_of_two.hpp"
#include "core/progress_stage.hpp"
#include "geometry/cap_grower.hpp"
#include "geometry/cap_internal.hpp"
#include "geometry/cotan_laplacian.hpp"
#include "geometry/crease_path.hpp"
#include "geometry/curvature.hpp"
#include "geometry/heat_smoothing.hpp"
#include "geometry/part_finder.hpp"
#include "geometry/region_metrics.hpp"
#include "geometry/region_stage_hook.hpp"
#include "geometry/sphere_moments.hpp"
#include "geometry/tip_finder.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/regions.hpp"

namespace shellcontract {
namespace {

/// Wall and processor time of the finder's stages, for the report's stage_times: a library
/// prints nothing, the CLI shows them (`regions --stage-times`). Each lap also names the stage
/// that follows it to a progress scope (core/progress_stage.hpp): the search takes seconds on a
/// large mesh, and a waiting user is told which part it is in.
class StageTimer {
 public:
  StageTimer() { progress_stage(announced(STAGES[0])); }
  void lap(const char* stage) {
    for (std::size_t i = 0; i + 1 < std::size(STAGES); ++i)
      if (std::strcmp(stage, STAGES[i]) == 0) progress_stage(announced(STAGES[i + 1]));
    const auto wall = std::chrono::steady_clock::now();
    const std::clock_t cpu = std::clock();
    laps_.push_back({stage, std::chrono::duration<double>(wall - wall_).count(),
                     static_cast<double>(cpu - cpu_) / CLOCKS_PER_SEC});
    wall_ = wall;
    cpu_ = cpu;
    if (const detail::RegionStageHook hook = detail::region_stage_hook()) hook(stage);
  }
  std::vector<RegionStageTime> take() { return std::move(laps_); }

 private:
  /// The stages in the order the finder laps them (RegionStageTime::stage).
  static constexpr const char* STAGES[] = {"curvature",     "smoothing", "free growth",
                                           "ranked growth", "parts",     "shape"};
  static std::string announced(const char* stage) {
    return std::string("selecting the regions (") + stage + ")";
  }
  std::vector<RegionStageTime> laps_;
  std::chrono::steady_clock::time_point wall_ = std::chrono::steady_clock::now();
  std::clock_t cpu_ = std::clock();
};

using detail::Cap;
using detail::block;
using detail::CapGrower;
using detail::MeshArrays;
using detail::mesh_arrays;
using detail::number_regions;
using detail::reference_curvature;
using detail::SEED_SCALES;
using detail::smoothed_curvature;
using detail::summarise;

/// A candidate whose freely grown cap has more than this share of its faces on better caps is a
/// fragment of a part already taken (non-maximum suppression).
constexpr double MAX_COVERED = 0.5;
/// A seed within this many radii of a kept part's sphere centre belongs to that part. A seed on
/// the part's own surface lies about one radius away, somewhat more on a part that is not a
/// sphere (the side or the sole of a foot); a seed of another part lies several radii away, and
/// ears and tips rank before the larger parts they sit on. The bound sits between the two with a
/// margin each way (measured on bear: lab/regions/finder.md).
constexpr double SAME_PART_SEED = 2.2;
/// A region whose sphere's centre is within this many radii of a larger region's centre is a
/// piece of that region's part (two caps of one end sit about a radius apart; an ear's centre
/// lies outside its head's sphere).
constexpr double SAME_PART = 1.2;

}  // namespace

namespace detail {

void block(const MeshArrays& m, const Cap& cap, std::vector<char>& blocked) {
  for (int f : cap.faces)
    for (int v : m.tri[static_cast<std::size_t>(f)]) blocked[static_cast<std::size_t>(v)] = 1;
}

/// H smoothed by one implicit heat step: (M + t L) u = M H, L the (positive semidefinite)
/// cotangent Laplacian, M the mixed areas, t = (scale * size)^2. Mesh-independent in the limit,
/// unlike ring averages, so a subdivided mesh gives the same smoothed field. Solved directly on
/// small meshes, iteratively on large ones (heat_smoothing.hpp).
std::vector<Eigen::VectorXd> smoothed_curvature(const MeshArrays& m, const Positions& x, const CurvatureField& c,
                                                const std::vector<double>& scales) {
  const auto n = static_cast<Eigen::Index>(m.nv);
  // Built in parallel, with setFromTriplets' bits (cotan_laplacian.hpp).
  const Eigen::SparseMatrix<double> L = detail::cotan_laplacian(m.tri, x);
  Eigen::VectorXd mass(n);
  // A zero mixed area (all faces degenerate) would make the row singular: a tiny positive mass.
  const double floor = 1e-12 * m.total_area / std::max<double>(1.0, static_cast<double>(m.nv));
  for (Eigen::Index i = 0; i < n; ++i) mass(i) = std::max(c.mixed_area(i), floor);
  const Eigen::VectorXd rhs = mass.cwiseProduct(c.mean);
  std::vector<double> times;
  for (double scale : scales) times.push_back((scale * m.size) * (scale * m.size));
  return detail::heat_solves(L, mass, rhs, times, n > detail::HEAT_DIRECT_MAX_VERTICES);
}

double weighted_median_abs(const Eigen::VectorXd& values, const std::vector<double>& weights) {
  std::vector<std::size_t> order(weights.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto v = [&](std::size_t i) { return std::abs(values(static_cast<Eigen::Index>(i))); };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return v(a) < v(b); });
  const double total = std::accumulate(weights.begin(), weights.end(), 0.0);
  double acc = 0.0;
  for (std::size_t i : order)
    if ((acc += weights[i]) >= 0.5 * total) return v(i);
  return 0.0;
}

RegionSummary summarise(const Mesh& mesh, const Positions& x, const MeshArrays& m, const Cap& cap, double h_ref) {
  std::vector<char> flag(m.nf, 0);
  for (int f : cap.faces) flag[static_cast<std::size_t>(f)] = 1;
  const RegionShape shape = region_shape(mesh, x, flag);
  RegionSummary s;
  s.faces = cap.faces.size();
  s.area = shape.area;
  s.area_fraction = m.total_area > 0.0 ? shape.area / m.total_area : 0.0;
  s.centre = cap.sphere.centre;
  s.radius = cap.sphere.radius;
  s.residual = cap.sphere.residual;
  s.fitted = cap.sphere.radius > 0.0;  // a fallback one-ring (select_regions_at) has no sphere
  s.cap_angle_deg = cap.angle * 180.0 / PI;
  s.compactness = shape.compactness;
  s.seed_vertex = cap.seed;
  s.mean_curvature = cap.sphere.radius > 0.0 ? 1.0 / cap.sphere.radius : 0.0;
  s.contrast = h_ref > 0.0 ? s.mean_curvature / h_ref : 0.0;
  return s;
}

std::vector<int> number_regions(std::vector<std::pair<Cap, RegionSummary>>& kept, std::size_t nf,
                                RegionReport& r, bool keep_order) {
  if (!keep_order)
    std::sort(kept.begin(), kept.end(), [](const auto& a, const auto& b) {
      if (a.second.area != b.second.area) return a.second.area > b.second.area;
      return a.first.faces.front() < b.first.faces.front();
    });
  std::vector<int> region(nf, -1);
  for (std::size_t id = 0; id < kept.size(); ++id) {
    for (int f : kept[id].first.faces) region[static_cast<std::size_t>(f)] = static_cast<int>(id);
    r.regions.push_back(kept[id].second);
  }
  return region;
}

double reference_curvature(const MeshArrays& m, const Positions& x, const Eigen::VectorXd& u_largest) {
  const double diagonal = (x.colwise().maxCoeff() - x.colwise().minCoeff()).norm();
  return std::max(weighted_median_abs(u_largest, m.vertex_area), diagonal > 0.0 ? 1.0 / diagonal : 0.0);
}

}  // namespace detail

std::vector<int> select_spherical_regions(const Mesh& mesh, const Positions& x, const RegionOptions& options,
                                          RegionReport* report) {
  return detail::with_cancel_hook(options, "select_spherical_regions", [&] {
    return detail::select_spherical_regions(mesh, x, options, report, nullptr);
  });
}

std::vector<int> detail::select_spherical_regions(const Mesh& mesh, const Positions& x, const RegionOptions& options,
                                                  RegionReport* report, CurvatureField* curvature) {
  check_region_options(options);
  // A NaN position would make every curvature and fit NaN, and the finder would answer "no
  // region" as if the mesh were smooth.
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    if (!x.row(i).allFinite())
      throw UsageError("select_spherical_regions: vertex " + std::to_string(i) + " has a coordinate that is not finite");
  if (const int k = finder_exponent(x); k != 0) {
    const std::vector<int> ids = select_spherical_regions(mesh, times_power_of_two(x, -k), options, report, curvature);
    unscale_finder_results(k, report, curvature);
    return ids;
  }
  if (options.method == RegionMethod::Tips) return detail::select_tip_regions(mesh, x, options, report, curvature);
  if (options.method == RegionMethod::Parts) return detail::select_part_regions(mesh, x, options, report, curvature);
  StageTimer timer;
  cancellation_point();
  detail::FinderStart start = detail::start_finder(mesh, x);
  timer.lap("curvature");
  if (start.empty()) {
    std::vector<int> none = detail::no_regions(start, report, curvature);
    if (report) report->stage_times = timer.take();
    return none;
  }
  cancellation_point();
  CurvatureField& c = start.curvature;
  const MeshArrays& m = start.arrays;
  RegionReport r;
  r.total_area = m.total_area;
  const std::vector<Eigen::VectorXd> u = smoothed_curvature(m, x, c, {SEED_SCALES.begin(), SEED_SCALES.end()});
  timer.lap("smoothing");
  cancellation_point();
  const double h_ref = reference_curvature(m, x, u.back());
  r.reference_mean_curvature = h_ref;

  // Step 1: strict one-ring maxima (ties make no seed, so the vertex order cannot matter).
  std::vector<int> seeds;
  for (std::size_t k = 1; k < u.size(); ++k)
    for (std::size_t v = 0; v < m.nv; ++v) {
      const Eigen::VectorXd& s = u[k];
      const double val = s(static_cast<Eigen::Index>(v));
      if (!(val > 0.0)) continue;
      bool peak = true;
      for (int k = m.nbr_start[v]; k < m.nbr_start[v + 1] && peak; ++k) peak = val > s(m.nbr_to[static_cast<std::size_t>(k)]);
      if (peak) seeds.push_back(static_cast<int>(v));
    }
  std::sort(seeds.begin(), seeds.end());
  seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
  r.seed_vertices = seeds.size();

  // Step 2: free growth, to rank.
  const detail::GrowthGraph graph(m, detail::growth_vertices(m, x, u.front()));
  CapGrower grower(m, graph, c, options);
  const double min_angle = options.min_cap_angle_deg * PI / 180.0;
  const auto curved = [&](const Cap& cap) {
    return cap.angle >= min_angle && cap.sphere.radius * options.min_curvature_contrast * h_ref <= 1.0;
  };
  // Each seed's free growth depends on the seed alone: grown side by side, one grower (scratch
  // arrays) per thread, and read back in seed order, so the result does not depend on threads.
  // Only the caps that may be kept need their faces (for the ranking and the coverage test).
  const std::function<bool(const Cap&)> candidate = [&](const Cap& cap) { return !cap.unbounded && curved(cap); };
  // Seeds are taken in the graph's (spatial) order, so that a thread's successive discs overlap
  // and find their vertices in the cache.
  std::vector<std::size_t> by_slot(seeds.size());
  std::iota(by_slot.begin(), by_slot.end(), std::size_t{0});
  std::sort(by_slot.begin(), by_slot.end(),
            [&](std::size_t a, std::size_t b) { return graph.slot(seeds[a]) < graph.slot(seeds[b]); });
  std::vector<std::optional<Cap>> grown(seeds.size());
  tbb::enumerable_thread_specific<std::unique_ptr<CapGrower>> growers;
  // In blocks, with a cancel check between them (a large mesh has tens of thousands of seeds).
  constexpr std::size_t SEED_BLOCK = 1024;
  for (std::size_t lo = 0; lo < seeds.size(); lo += SEED_BLOCK) {
    cancellation_point();
    tbb::parallel_for(lo, std::min(seeds.size(), lo + SEED_BLOCK), [&](std::size_t k) {
      std::unique_ptr<CapGrower>& g = growers.local();
      if (!g) g = std::make_unique<CapGrower>(m, graph, c, options);
      const std::size_t i = by_slot[k];
      grown[i] = g->grow(seeds[i], nullptr, &candidate);
    });
  }
  timer.lap("free growth");
  std::vector<Cap> candidates;
  for (std::optional<Cap>& cap : grown)
    if (cap) {
      ++r.candidates;
      if (cap->unbounded) {
        ++r.dropped_large;
      } else if (curved(*cap)) {
        candidates.push_back(std::move(*cap));
      } else {
        ++r.dropped_flat;
      }
    }
  std::sort(candidates.begin(), candidates.end(), [](const Cap& a, const Cap& b) {
    if (a.angle != b.angle) return a.angle > b.angle;
    return a.faces.size() > b.faces.size();
  });

  // The concave creases (the smallest smoothing below zero, as the growth counts them): a seed
  // across one from a part is not that part's (step 3), and the outline smoothing does not fill
  // a notch on one (step 5).
  std::vector<char> crease(m.nv, 0);
  for (std::size_t v = 0; v < m.nv; ++v)
    crease[v] = u.front()(static_cast<Eigen::Index>(v)) < 0.0 ? 1 : 0;
  detail::CreasePaths paths(m, x, crease);
  // Step 3: in rank order, grown again around the regions already kept.
  std::vector<char> blocked(m.nv, 0);
  // The part (index in kept) each blocked vertex belongs to, and the candidates each part took
  // over (their free caps widen the part in step 4).
  std::vector<int> vertex_part(m.nv, -1);
  std::vector<std::vector<const Cap*>> members;
  std::vector<std::pair<Cap, RegionSummary>> kept;
  for (const Cap& first : candidates) {
    cancellation_point();
    const auto join = [&](int part) {
      if (part >= 0) members[static_cast<std::size_t>(part)].push_back(&first);
    };
    if (blocked[static_cast<std::size_t>(first.seed)]) {  // inside a better cap
      join(vertex_part[static_cast<std::size_t>(first.seed)]);
      continue;
    }
    // A seed near a kept part's sphere (the back of a head whose face was taken, the side of a
    // foot) is that part's, whatever its own cap: one part, one region. Not when a concave
    // crease lies between the seed and the part (crease_path.hpp).
    const Vec3 sp(x.row(first.seed));
    int same = -1;
    for (std::size_t k = 0; k < kept.size() && same < 0; ++k) {
      const Vec3& c = kept[k].first.sphere.centre;
      const double ball = SAME_PART_SEED * kept[k].first.sphere.radius;
      if ((sp - c).norm() <= ball &&
          !paths.across(first.seed, c, ball, static_cast<int>(k), vertex_part))
        same = static_cast<int>(k);
    }
    if (same >= 0) {
      join(same);
      continue;
    }
    // Mostly covered by better caps: a fragment of a part already taken, not a part of its own.
    std::size_t covered = 0;
    std::map<int, std::size_t> by_part;
    for (int f : first.faces) {
      int part = -1;
      for (int v : m.tri[static_cast<std::size_t>(f)])
        if (blocked[static_cast<std::size_t>(v)]) part = vertex_part[static_cast<std::size_t>(v)];
      if (part >= 0) ++covered, ++by_part[part];
    }
    if (static_cast<double>(covered) > MAX_COVERED * static_cast<double>(first.faces.size())) {
      int best = -1;
      for (const auto& [p, n] : by_part)
        if (best < 0 || n > by_part[best]) best = p;
      join(best);
      continue;
    }
    std::optional<Cap> cap = grower.grow(first.seed, &blocked);
    if (!cap || cap->faces.empty()) continue;
    if (cap->unbounded) {
      ++r.dropped_large;
      continue;
    }
    if (!curved(*cap)) {
      ++r.dropped_flat;
      continue;
    }
    const RegionSummary s = summarise(mesh, x, m, *cap, h_ref);
    if (s.area_fraction < options.min_area_fraction || s.faces < static_cast<std::size_t>(options.min_faces)) {
      ++r.dropped_small;
    } else if (s.area_fraction > options.max_area_fraction) {
      ++r.dropped_large;
    } else if (!(s.compactness <= options.max_compactness)) {
      ++r.dropped_shape;
    } else {
      block(m, *cap, blocked);
      for (int f : cap->faces)
        for (int v : m.tri[static_cast<std::size_t>(f)]) vertex_part[static_cast<std::size_t>(v)] = static_cast<int>(kept.size());
      members.emplace_back();
      kept.emplace_back(std::move(*cap), s);
    }
  }
  timer.lap("ranked growth");
  // Step 4: each part is its cap and the free caps of the seeds it took over, so its sphere and
  // axis do not hang on which of its seeds ranked first (on bear and bear split in four a
  // different seed of one arm can win).
  std::vector<Cap> caps;
  for (auto& k : kept) caps.push_back(std::move(k.first));
  std::vector<int> in_part(m.nf, -1);
  for (std::size_t k = 0; k < caps.size(); ++k) {
    const int id = static_cast<int>(k);
    for (int f : caps[k].faces) in_part[static_cast<std::size_t>(f)] = id;
    for (const Cap* c : members[k])
      for (int f : c->faces) {
        if (in_part[static_cast<std::size_t>(f)] == id) continue;
        bool other = false;  // a face touching another part stays that part's
        for (int v : m.tri[static_cast<std::size_t>(f)]) {
          const int p = vertex_part[static_cast<std::size_t>(v)];
          other = other || (p >= 0 && p != id);
        }
        if (!other) in_part[static_cast<std::size_t>(f)] = id, caps[k].faces.push_back(f);
      }
    std::sort(caps[k].faces.begin(), caps[k].faces.end());
  }
  timer.lap("parts");
  // Step 5: each region clipped to a hemisphere of its sphere, in one piece, its holes filled;
  // the size, shape and fit filters again on the final faces (the flood over the sphere can
  // make a region larger than the cap that found it).
  // The outline smoothing does not fill a notch on a concave crease (cap_shape.cpp).
  std::vector<int> owner_face(m.nf, -1);
  for (std::size_t id = 0; id < caps.size(); ++id)
    for (int f : caps[id].faces) owner_face[static_cast<std::size_t>(f)] = static_cast<int>(id);
  kept.clear();
  for (std::size_t id = 0; id < caps.size(); ++id) {
    cancellation_point();
    Cap& cap = caps[id];
    const bool shaped = detail::shape_cap(m, x, cap, owner_face, static_cast<int>(id), crease);
    const RegionSummary s = shaped ? summarise(mesh, x, m, cap, h_ref) : RegionSummary{};
    // The final region must still fit its sphere as the growth asked (a cap on a sphere).
    const bool keep = shaped && s.area_fraction >= options.min_area_fraction &&
                      s.area_fraction <= options.max_area_fraction &&
                      s.faces >= static_cast<std::size_t>(options.min_faces) &&
                      s.compactness <= options.max_compactness && s.residual <= options.fit_tolerance;
    if (keep) {
      kept.emplace_back(std::move(cap), s);
    } else {
      if (shaped && s.area_fraction > options.max_area_fraction)
        ++r.dropped_large;
      else
        ++(shaped && !(s.compactness <= options.max_compactness && s.residual <= options.fit_tolerance) ? r.dropped_shape
                                                                                                           : r.dropped_small);
      for (std::size_t f = 0; f < m.nf; ++f)
        if (owner_face[f] == static_cast<int>(id)) owner_face[f] = -1;
    }
  }
  // A region whose sphere's centre lies within SAME_PART radii of a larger region's centre is a
  // piece of that part's end (the side of a foot that a second seed grew after the first took
  // the tip): dropped, its faces stay unassigned. Larger regions first, so a piece never keeps
  // out the part it belongs to.
  std::sort(kept.begin(), kept.end(), [](const auto& a, const auto& b) {
    if (a.second.area != b.second.area) return a.second.area > b.second.area;
    return a.first.faces.front() < b.first.faces.front();
  });
  // Not when its seed lies across a concave crease from the larger region's vertices (within the
  // larger part's same-part ball): two knuckles side by side have centres that close.
  std::vector<std::pair<Cap, RegionSummary>> parts;
  std::vector<int> region_vertex(m.nv, -1);  // the part (index in parts) each vertex belongs to
  for (auto& k : kept) {
    bool piece = false;
    for (std::size_t j = 0; j < parts.size() && !piece; ++j) {
      const auto& p = parts[j];
      if (!((p.second.centre - k.second.centre).norm() <= SAME_PART * p.second.radius)) continue;
      piece = !paths.across(k.first.seed, p.second.centre, SAME_PART_SEED * p.second.radius,
                            static_cast<int>(j), region_vertex);
    }
    if (!piece) {
      for (int f : k.first.faces)
        for (int v : m.tri[static_cast<std::size_t>(f)])
          if (region_vertex[static_cast<std::size_t>(v)] < 0)
            region_vertex[static_cast<std::size_t>(v)] = static_cast<int>(parts.size());
      parts.push_back(std::move(k));
    }
  }
  kept = std::move(parts);
  timer.lap("shape");
  std::vector<int> region = number_regions(kept, m.nf, r, false);
  r.stage_times = timer.take();
  if (report) *report = std::move(r);
  if (curvature) *curvature = std::move(c);
  return region;
}

}  // namespace shellcontract
