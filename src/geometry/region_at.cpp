// select_regions_at (shellcontract/regions.hpp): the cap around the surface point nearest to each
// given point, grown with the cap finder's growth (cap_grower.hpp) but without its ranking, the
// way an artist points at an ear; a point far from the surface, whose nearest surface point may
// lie on another part than meant, is a warning (REGION_POINT_NEAR).
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "collision/distance.hpp"
#include "core/cancellation.hpp"
#include "core/decimal_text.hpp"
#include "core/power_of_two.hpp"
#include "geometry/cap_grower.hpp"
#include "geometry/cap_internal.hpp"
#include "geometry/curvature.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/regions.hpp"

namespace shellcontract {
namespace {

using detail::block;
using detail::Cap;
using detail::CapGrower;
using detail::MeshArrays;
using detail::mesh_arrays;
using detail::number_regions;
using detail::reference_curvature;
using detail::SEED_SCALES;
using detail::smoothed_curvature;
using detail::summarise;

/// "1st", "2nd", "3rd", "11th": messages name the points by ordinal, which reads the same whether
/// the caller counts from 0 (Python's region_at[i]) or from 1 (the CLI's list).
std::string ordinal(std::size_t n) {
  const std::size_t tens = n % 100, ones = n % 10;
  const char* suffix = (tens >= 11 && tens <= 13) ? "th" : ones == 1 ? "st" : ones == 2 ? "nd" : ones == 3 ? "rd" : "th";
  return std::to_string(n) + suffix;
}

/// The earlier point whose region holds vertex v (its ordinal), or "an earlier point" when v was
/// blocked by a region's band rather than by one of its faces.
std::string owner_of(const MeshArrays& m, const std::vector<std::pair<Cap, RegionSummary>>& kept, int v) {
  for (std::size_t j = 0; j < kept.size(); ++j)
    for (int f : kept[j].first.faces)
      for (int c : m.tri[static_cast<std::size_t>(f)])
        if (c == v) return "the " + ordinal(j + 1) + " point";
  return "an earlier point";
}

/// A --region-at region as the table reports it (docs/design/regions.md, "Output"): the
/// area-weighted least-squares sphere of its vertices, their area-weighted RMS distance to it
/// over its radius, and the widest face centroid from its axis (cap_axis), all measured on
/// `faces`, the faces written. No sphere (radius 0: the table's '-') when the vertices fit none.
Cap measured_cap(const MeshArrays& m, const Positions& x, int seed, std::vector<int> faces) {
  Cap cap;
  cap.seed = seed;
  cap.faces = std::move(faces);
  const std::optional<detail::SphereFit> fit = detail::fit_faces(m, x, cap.faces, seed);
  if (!fit) return cap;
  const Vec3 c = fit->centre;
  const double r = fit->radius;
  std::vector<int> verts;
  for (int f : cap.faces)
    for (int v : m.tri[static_cast<std::size_t>(f)]) verts.push_back(v);
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  double w = 0.0, sq = 0.0;
  for (int v : verts) {
    const double e = (Vec3(x.row(v)) - c).norm() - r,
                 a = m.vertex_area[static_cast<std::size_t>(v)];
    w += a, sq += a * e * e;
  }
  cap.sphere = *fit;
  cap.sphere.residual = w > 0.0 ? std::sqrt(sq / w) / r : 0.0;
  const Vec3 axis = detail::cap_axis(m, x, cap.faces, c);
  for (int f : cap.faces) {
    const Vec3 d = detail::face_centroid(m, x, f) - c;
    if (d.norm() > 0.0)
      cap.angle = std::max(cap.angle, std::acos(std::clamp(d.normalized().dot(axis), -1.0, 1.0)));
  }
  return cap;
}

/// select_regions_at on positions near a unit size (the caller scales them), `near` the points
/// pulled in: the regions, and the report with each point's nearest surface point.
std::vector<int> regions_at(const Mesh& mesh, const Positions& x, const std::vector<Vec3>& near,
                            const RegionOptions& options, RegionReport& report) {
  cancellation_point();
  const CurvatureField c = compute_curvature(mesh, x);
  const MeshArrays m = mesh_arrays(mesh, x);
  if (m.nf == 0) throw UsageError("select_regions_at: the mesh has no face");
  cancellation_point();
  const std::vector<Eigen::VectorXd> u = smoothed_curvature(m, x, c, {SEED_SCALES.begin(), SEED_SCALES.end()});
  const double h_ref = reference_curvature(m, x, u.back());
  RegionReport r;
  r.total_area = m.total_area;
  r.reference_mean_curvature = h_ref;
  const std::vector<detail::GrowthVertex> gv = detail::growth_vertices(m, x, u.front());
  CapGrower grower(m, gv, c, options);
  std::vector<char> blocked(m.nv, 0);
  std::vector<std::pair<Cap, RegionSummary>> kept;
  for (std::size_t i = 0; i < near.size(); ++i) {
    cancellation_point();
    const Vec3& p = near[i];
    if (!p.allFinite()) throw UsageError("the " + ordinal(i + 1) + " region point is not finite");
    // Nearest surface point (brute force: a handful of points), then its nearest corner. The
    // first face always sets a seed, whatever its distance. The collision step's closest point
    // (collision/distance.hpp) is the one whose divisions are guarded: a face with two corners at
    // one position (which the readers accept) made Ericson's unguarded form divide 0 by 0, and a
    // NaN distance as the first face's held the seed there for every later face.
    double best = std::numeric_limits<double>::infinity();
    int seed = -1, nearest = -1;
    Vec3 surface = Vec3::Zero();
    for (std::size_t f = 0; f < m.nf; ++f) {
      const auto& t = m.tri[f];
      const Vec3 q =
          point_triangle_closest(p, Vec3(x.row(t[0])), Vec3(x.row(t[1])), Vec3(x.row(t[2])))
              .closest;
      const double d = (q - p).squaredNorm();  // finite: p is pulled in, x near a unit size
      if (!std::isfinite(d)) continue;
      if (seed < 0 || d < best) {
        best = d;
        surface = q;
        seed = t[0];
        nearest = static_cast<int>(f);
        for (int v : t)
          if ((Vec3(x.row(v)) - q).squaredNorm() < (Vec3(x.row(seed)) - q).squaredNorm()) seed = v;
      }
    }
    if (seed < 0)  // not reached: the positions are checked finite and the point is pulled in
      throw UsageError("the " + ordinal(i + 1) + " region point has no face at a finite distance");
    if (blocked[static_cast<std::size_t>(seed)])
      throw UsageError("the " + ordinal(i + 1) + " region point lies in the region of " +
                       owner_of(m, kept, seed) + "; give points on different parts");
    r.points.push_back({p, surface, std::sqrt(best)});
    ++r.seed_vertices;
    // The region a disc gives: its faces, and the seed's fan when the disc (grown by vertices)
    // missed the pointed-at face, as on a coarse mesh it can; the fan is edge-connected to the
    // disc and in no earlier region, or the seed would be blocked.
    const auto with_pointed_face = [&](std::vector<int> faces) {
      if (!std::binary_search(faces.begin(), faces.end(), nearest)) {
        for (int f : m.vertex_faces[static_cast<std::size_t>(seed)]) faces.push_back(f);
        std::sort(faces.begin(), faces.end());
        faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
      }
      return faces;
    };
    const std::function<double(const std::vector<int>&)> region_area =
        [&](const std::vector<int>& faces) {
          double a = 0.0;
          for (int f : with_pointed_face(faces)) a += m.face_area[static_cast<std::size_t>(f)];
          return a;
        };
    // The largest cap whose region is within max_area_fraction (docs/cli.md: each cap stops
    // growing at this fraction).
    std::optional<Cap> cap = grower.grow_within(seed, &blocked, region_area);
    if (!cap) {
      // No convex sphere fits here, or none within the bound (a disc is judged from
      // MIN_FIT_POINTS vertices on, and on a coarse mesh the smallest such disc can exceed a
      // small bound): the seed's one-ring, so the user still gets a region.
      cap = Cap{};
      cap->seed = seed;
      for (int f : m.vertex_faces[static_cast<std::size_t>(seed)]) cap->faces.push_back(f);
      std::sort(cap->faces.begin(), cap->faces.end());
    } else {
      ++r.candidates;
      // The row describes the faces written, not the grown disc: the sphere fitted to the
      // region's vertices, their RMS distance to it and the widest face centroid from its axis.
      *cap = measured_cap(m, x, seed, with_pointed_face(std::move(cap->faces)));
    }
    cap->faces = with_pointed_face(std::move(cap->faces));
    const RegionSummary s = summarise(mesh, x, m, *cap, h_ref);
    block(m, *cap, blocked);
    kept.emplace_back(std::move(*cap), s);
  }
  std::vector<int> region = number_regions(kept, m.nf, r, true);
  report = std::move(r);
  return region;
}

/// "(x, y, z)" with each coordinate as shortest_text writes it: the point as the user typed it.
std::string point_text(const Vec3& p) {
  return "(" + shortest_text(p.x()) + ", " + shortest_text(p.y()) + ", " + shortest_text(p.z()) +
         ")";
}

/// The warning for the i-th point when it lies farther than `bound` from the surface: a point
/// that far picks the part nearest to it, which is often not the one meant (REGION_POINT_NEAR).
std::string far_point_warning(std::size_t i, const RegionPoint& p, double bound) {
  const Vec3& s = p.surface_point;
  // A point near the largest doubles is farther than a double holds: said so, not "inf".
  const std::string distance =
      std::isfinite(p.distance)
          ? general_text(p.distance, 4)
          : "more than " + general_text(std::numeric_limits<double>::max(), 2);
  return "the " + ordinal(i + 1) + " `region_at` point " + point_text(p.point) + " is " + distance +
         " from the surface, farther than " + general_text(100.0 * REGION_POINT_NEAR, 3) +
         " % of the bounding box's diagonal (" + general_text(bound, 4) +
         "): its region grows from the surface point nearest to it, " + point_text(s) +
         ", which may be on another part than meant. Give a point on the surface (an ear's tip, "
         "not a sphere's centre from the regions table) in the input's coordinates: glTF, and OBJ "
         "by default, is Y-up, so a point (X, Y, Z) read in Blender's Z-up world after the import "
         "is (X, Z, -Y) in the file";
}

/// select_regions_at without its cancel hook (asked by the caller's scope).
std::vector<int> regions_at_points(const Mesh& mesh, const Positions& x,
                                   const std::vector<Vec3>& points, const RegionOptions& options,
                                   RegionReport* report) {
  check_region_options(options);
  RegionReport r;
  // Far points are pulled in before any scaling: scaled by 2^-k, a point far from a tiny mesh
  // would overflow.
  const std::vector<Vec3> near = detail::pulled_in(points, x);
  std::vector<int> ids;
  if (const int k = detail::finder_exponent(x); k != 0) {
    ids = regions_at(mesh, times_power_of_two(x, -k), detail::scaled_by_power_of_two(near, k),
                     options, r);
    detail::unscale_finder_results(k, &r, nullptr);
  } else {
    ids = regions_at(mesh, x, near, options, r);
  }
  // Each point as given, and its distance from the point as given (a far point was pulled in),
  // to the bound in the mesh's units.
  const double bound =
      REGION_POINT_NEAR * (x.colwise().maxCoeff() - x.colwise().minCoeff()).stableNorm();
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    RegionPoint& p = r.points[i];
    p.point = points[i];
    p.distance = (p.point - p.surface_point).stableNorm();
    if (p.distance > bound) r.warnings.push_back(far_point_warning(i, p, bound));
  }
  if (report) *report = std::move(r);
  return ids;
}

}  // namespace

std::vector<int> select_regions_at(const Mesh& mesh, const Positions& x,
                                   const std::vector<Vec3>& points, const RegionOptions& options,
                                   RegionReport* report) {
  return detail::with_cancel_hook(options, "select_regions_at", [&] {
    return regions_at_points(mesh, x, points, options, report);
  });
}

}  // namespace shellcontract
