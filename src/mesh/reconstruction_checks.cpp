#include "mesh/reconstruction_checks.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <boost/iterator/counting_iterator.hpp>
#include <cmath>

#include "shellcontract/error.hpp"

namespace shellcontract {

namespace {

// A point misses the surface if it lies farther from it than this many average spacings plus
// MISS_DISTANCES times the mesher's approximation error (--distance, in spacings). The Poisson
// surface passes through the points up to their noise, and noise puts a point a few spacings off
// the surface (the stray check's reasoning, point_set_checks.cpp); a point of an object the
// surface left out is at least the gap between the objects away, which is more than a few
// spacings, or the objects would have been sampled as one.
constexpr double MISS_SPACINGS = 5.0;
// The mesher bounds a facet's distance from the implicit surface only at the facet's
// circumcentre: where a coarse --distance lets facets cut across a bend or a detail smaller than
// themselves (an ear, a tail), points lie several times that bound from the facets.
constexpr double MISS_DISTANCES = 3.0;
// The share of the points that may miss the surface: a scan's outliers, which pass the stray
// check (up to 100 spacings from their neighbours) and which the solve smooths away. An object
// the surface left out is a closed surface sampled at the spacing, so it is many points, not a
// few: a ball only three spacings across is already dozens.
constexpr double MAX_MISSED_SHARE = 1e-3;
// The normals are compared with the surface only at points it passes this close to (in average
// spacings): there it follows the points, and its outward normal is theirs up to noise. Farther
// from a point, where a coarse --distance or --radius lets facets cut across details, the
// nearest facet may face anywhere.
constexpr double ORIENTATION_SPACINGS = 2.0;
// The share of those normals that may point against the surface (the minority orientation: all
// of them inward is a consistent set, and the surface is turned outward anyway). The exceptions on
// a consistent set are points next to a feature thinner than the spacing (the nearest surface
// point may be on its other side) or a sharp edge the solve rounds off, a few percent at most;
// inconsistent normals (each point's orientation a coin toss) disagree for about half the points.
constexpr double MAX_INWARD_SHARE = 0.1;
// The same share for the failure hint, with each point's nearest neighbours in place of the
// surface: neighbours a spacing apart on a smooth surface have normals far less than 90 degrees
// apart, so a point whose normal is against most of its neighbours' is flipped or noise.
constexpr double MAX_AGAINST_NEIGHBOURS_SHARE = 0.1;

using Vector3 = Kernel::Vector_3;

using point_text::text;

}  // namespace

void check_surface_fits_points(const OrientedPoints& input, const std::vector<std::size_t>& kept,
                               const std::vector<PointWithNormal>& points, const Mesh& surface,
                               double spacing, double distance) {
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  const Tree tree(faces(surface).first, faces(surface).second, surface);
  const double limit = (MISS_SPACINGS + MISS_DISTANCES * distance) * spacing;
  std::size_t missed = 0, farthest = 0, compared = 0;
  double farthest_distance = -1.0;
  std::vector<std::size_t> inward, outward;  // by the sign of the point's normal . the surface's
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Point3& p = points[i].first;
    const auto [q, face] = tree.closest_point_and_primitive(p);
    const double d = std::sqrt(CGAL::squared_distance(p, q));
    if (!(d <= limit)) {
      ++missed;
      if (d > farthest_distance) {
        farthest_distance = d;
        farthest = i;
      }
    }
    if (!(d <= ORIENTATION_SPACINGS * spacing)) continue;
    ++compared;
    const Vector3 n = CGAL::Polygon_mesh_processing::compute_face_normal(face, surface);
    (n * points[i].second < 0.0 ? inward : outward).push_back(i);
  }
  // Inconsistent normals also make the surface miss points: they are named first, as the cause.
  const bool mostly_inward = inward.size() > outward.size();
  const std::vector<std::size_t>& against = mostly_inward ? outward : inward;
  if (static_cast<double>(against.size()) > MAX_INWARD_SHARE * static_cast<double>(compared))
    throw InputError(
        input.path + ": " + std::to_string(against.size()) + " of " + std::to_string(compared) +
        " normals point " + (mostly_inward ? "out of" : "into") + " the reconstructed surface" +
        (mostly_inward ? " (the others into it)" : "") +
        ": the normals are not consistently oriented (e.g. " + input.where(kept[against.front()]) +
        ": point " + text(points[against.front()].first) + ")");
  if (static_cast<double>(missed) > MAX_MISSED_SHARE * static_cast<double>(points.size()))
    throw InputError(
        input.path + ": the reconstructed surface misses " + std::to_string(missed) + " of " +
        std::to_string(points.size()) + " points (farther than " + text(limit) + " from it, " +
        text(limit / spacing) + " average spacings), e.g. " + input.where(kept[farthest]) +
        ": point " + text(points[farthest].first) + ", " + text(farthest_distance) +
        " away: separate objects (reconstruct them one by one) or normals that are not "
        "consistently oriented?");
}

std::string inconsistent_normals_hint(const OrientedPoints& input,
                                      const std::vector<std::size_t>& kept,
                                      const std::vector<PointWithNormal>& points, int neighbours,
                                      double share) {
  if (share < 0.0) share = MAX_AGAINST_NEIGHBOURS_SHARE;
  if (points.size() < 2) return "";
  using Map = CGAL::Pointer_property_map<Point3>::const_type;
  using Traits = CGAL::Search_traits_adapter<std::size_t, Map, CGAL::Search_traits_3<Kernel>>;
  using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;
  std::vector<Point3> p;
  p.reserve(points.size());
  for (const PointWithNormal& pn : points) p.push_back(pn.first);
  const std::vector<Point3>& positions = p;
  const Map map = CGAL::make_property_map(positions);
  const Search::Tree tree(boost::counting_iterator<std::size_t>(0),
                          boost::counting_iterator<std::size_t>(p.size()), Search::Tree::Splitter(),
                          Traits(map));
  const Search::Distance distance(map);
  const std::size_t k = std::min(static_cast<std::size_t>(std::max(neighbours, 1)), p.size() - 1);
  std::size_t against = 0, example = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Search search(tree, p[i], static_cast<unsigned int>(k + 1), 0, true, distance);
    std::size_t seen = 0, opposed = 0;
    for (const auto& found : search) {
      const std::size_t j = found.first;
      if (j == i || seen == k) continue;
      ++seen;
      if (points[i].second * points[j].second < 0.0) ++opposed;
    }
    if (2 * opposed > seen && against++ == 0) example = i;
  }
  if (!(static_cast<double>(against) > share * static_cast<double>(p.size()))) return "";
  return ": " + std::to_string(against) + " of " + std::to_string(p.size()) +
         " points have a normal against most of their nearest neighbours' (e.g. " +
         input.where(kept[example]) + "): the normals are not consistently oriented";
}

}  // namespace shellcontract
