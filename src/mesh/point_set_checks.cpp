#include "mesh/point_set_checks.hpp"

#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>

#include <boost/iterator/counting_iterator.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "core/classic_locale.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {

namespace point_text {

std::string text(double x) {
  ClassicOStringStream s;
  s.precision(3);
  s << x;
  return s.str();
}

std::string text(const Point3& p) {
  ClassicOStringStream s;
  s << '(' << p.x() << ", " << p.y() << ", " << p.z() << ')';
  return s.str();
}

}  // namespace point_text

std::string OrientedPoints::where(std::size_t i) const {
  return lines.empty() ? "vertex " + std::to_string(i) : "line " + std::to_string(lines[i]);
}

namespace {

using Vector3 = Kernel::Vector_3;

// CGAL's solve and surface mesher compute in double with products of several coordinates, which
// overflow for coordinates far beyond any physical unit's (a valid sphere that large made the
// solve run forever). 1e30 is above any scan's coordinates in any everyday unit (the observable
// universe is under 1e27 metres across) and leaves a wide margin below the overflow.
constexpr double MAX_COORDINATE = 1e30;
// CGAL normalizes sums of four normals through their squared length: below about 1e-154 that
// underflows to zero (every cell's normal is then zero and the solve never ended), above about
// 1e154 it overflows. The limits keep a wide margin; any direction can be given at length 1.
constexpr double MIN_NORMAL_LENGTH = 1e-100;
constexpr double MAX_NORMAL_LENGTH = 1e100;
// CGAL's solve or surface mesher has absolute tolerances somewhere: on points spaced far below a
// unit the mesher failed its own assertions (an abort) whatever the shape. This limit is far above
// where that happened and below any scan's spacing in metres (a picometre, a hundredth of the
// distance between atoms).
constexpr double MIN_SPACING = 1e-12;
// A point sampling a surface has neighbours at about their own spacing: a scan's density changes
// gradually, not a hundredfold from one point to the next, and noise puts a point a few spacings
// off the surface, not a hundred. A point farther than this from its neighbours, in multiples of
// the spacing around it, samples nothing near them: the solve wrapped a surface around such a
// point, hit CGAL assertions or never ended. The spacing around a point is the larger of its
// neighbours' own (median) and the whole set's median: the first so that a sparse but evenly
// sampled region is not taken for strays, the second so that a point beside a clump of
// near-duplicates (whose own spacing is tiny) is not either.
constexpr double MAX_STRAY_OVER_SPACING_AROUND = 100.0;
// A backstop for groups of stray points, which have neighbours of their own and pass the check
// above: the solve works in the points' bounding sphere at their spacing, and a closed surface a
// million spacings long needs millions of points along it times its girth in spacings around it.
// A set that spans more is mostly empty space between groups of points far apart.
constexpr double MAX_EXTENT_OVER_SPACING = 1e6;

using point_text::text;

/// The length of `n`, without overflow in the squares (scaled by its largest component).
double length_of(const Vector3& n) {
  const double m = std::max({std::abs(n.x()), std::abs(n.y()), std::abs(n.z())});
  if (m == 0.0) return 0.0;
  const double x = n.x() / m, y = n.y() / m, z = n.z() / m;
  return m * std::sqrt(x * x + y * y + z * z);
}

/// Coordinates and normal lengths within what the solve's double arithmetic survives; plain
/// comparisons only, before anything squares a coordinate.
void check_magnitudes(const OrientedPoints& input) {
  for (std::size_t i = 0; i < input.points.size(); ++i) {
    const Point3& p = input.points[i].first;
    for (int d = 0; d < 3; ++d)
      if (!(std::abs(p[d]) <= MAX_COORDINATE))
        throw InputError(input.path + ": " + input.where(i) + ": coordinate " + text(p[d]) +
                         " is beyond +-1e30, past what the reconstruction's arithmetic survives");
    const double length = length_of(input.points[i].second);
    if (!(length >= MIN_NORMAL_LENGTH && length <= MAX_NORMAL_LENGTH))
      throw InputError(input.path + ": " + input.where(i) + ": the normal's length " +
                       text(length) +
                       " is outside 1e-100 to 1e100, where the reconstruction's arithmetic fails; "
                       "give unit normals");
  }
}

/// The indices of the points in the file's order, each position once (its first line). A
/// position given again with a normal 90 degrees or more away is refused: the solve keeps one of
/// them, and they disagree on which side is outside.
std::vector<std::size_t> distinct_positions(const OrientedPoints& input) {
  const std::vector<PointWithNormal>& p = input.points;
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return p[a].first < p[b].first; });
  std::vector<char> kept(p.size(), 1);
  for (std::size_t r = 1, first = order[0]; r < order.size(); ++r) {
    const std::size_t i = order[r];
    if (p[i].first != p[first].first) {
      first = i;
      continue;
    }
    kept[i] = 0;
    if (!(p[i].second * p[first].second > 0.0))
      throw InputError(input.path + ": " + input.where(first) + " and " + input.where(i) +
                       ": the same point " + text(p[i].first) +
                       " with normals 90 degrees or more apart: which side is outside?");
  }
  std::vector<std::size_t> distinct;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (kept[i]) distinct.push_back(i);
  return distinct;
}

/// Refuses points that all lie in one plane (exactly: CGAL's orientation predicate): they
/// enclose no volume, and the Delaunay triangulation under the Poisson solve is then flat, on
/// which CGAL's solve crashed (a segmentation fault on a flat disc of points).
void check_volume(const std::string& path, const std::vector<Point3>& p) {
  std::size_t j = 2;
  while (j < p.size() && CGAL::collinear(p[0], p[1], p[j])) ++j;
  std::size_t k = j + 1;
  while (k < p.size() && CGAL::coplanar(p[0], p[1], p[j], p[k])) ++k;
  if (k >= p.size())
    throw InputError(path + ": the points lie in one plane (or on a line): they enclose no volume");
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

/// Nearest-neighbour queries among distinct points (CGAL's kd-tree, as compute_average_spacing).
class Neighbours {
 public:
  Neighbours(const std::vector<Point3>& points, std::size_t k)
      : points_(points),
        map_(CGAL::make_property_map(points)),
        k_(std::min(k, points.size() - 1)),
        tree_(boost::counting_iterator<std::size_t>(0),
              boost::counting_iterator<std::size_t>(points.size()), Tree::Splitter(), Traits(map_)),
        distance_(map_) {}

  /// The k nearest other points of point i, nearest first: (index, distance).
  std::vector<std::pair<std::size_t, double>> of(std::size_t i) const {
    std::vector<std::pair<std::size_t, double>> found;
    const Search search(tree_, points_[i], static_cast<unsigned int>(k_ + 1), 0, true, distance_);
    for (const auto& [j, squared] : search)
      if (j != i && found.size() < k_) found.emplace_back(j, std::sqrt(squared));
    return found;
  }

  /// The mean distance of point i to its k nearest others (CGAL's spacing of one point).
  double spacing(std::size_t i) const {
    double sum = 0.0;
    const auto found = of(i);
    for (const auto& n : found) sum += n.second;
    return sum / static_cast<double>(found.size());
  }

 private:
  using Map = CGAL::Pointer_property_map<Point3>::const_type;
  using Traits = CGAL::Search_traits_adapter<std::size_t, Map, CGAL::Search_traits_3<Kernel>>;
  using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;
  using Tree = Search::Tree;
  const std::vector<Point3>& points_;
  Map map_;
  std::size_t k_;
  Tree tree_;
  Search::Distance distance_;
};

/// Refuses a point far from its neighbours in multiples of the spacing around it, naming the worst.
void check_strays(const OrientedPoints& input, const std::vector<std::size_t>& distinct,
                  const std::vector<Point3>& points, const Neighbours& neighbours,
                  const std::vector<double>& spacing, double median_spacing) {
  double worst = 0.0;
  std::size_t stray = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    // The spacing around a point is at least the median: the others need no second search.
    if (!(spacing[i] > MAX_STRAY_OVER_SPACING_AROUND * median_spacing)) continue;
    std::vector<double> around;
    for (const auto& n : neighbours.of(i)) around.push_back(spacing[n.first]);
    const double ratio = spacing[i] / std::max(median(around), median_spacing);
    if (ratio > worst) {
      worst = ratio;
      stray = i;
    }
  }
  if (!(worst > MAX_STRAY_OVER_SPACING_AROUND)) return;
  throw InputError(input.path + ": " + input.where(distinct[stray]) + ": point " +
                   text(points[stray]) + " lies on average " + text(spacing[stray]) +
                   " from its nearest neighbours, " + text(worst) +
                   " times the points' spacing around it: a stray point far from the others?");
}

/// Refuses points spanning far more than their median spacing (groups of points far apart).
void check_extent(const std::string& path, const std::vector<Point3>& p, double median_spacing) {
  double extent[3];
  for (int d = 0; d < 3; ++d) {
    const auto [lo, hi] = std::minmax_element(
        p.begin(), p.end(), [d](const Point3& a, const Point3& b) { return a[d] < b[d]; });
    extent[d] = (*hi)[d] - (*lo)[d];  // finite: the coordinates are within MAX_COORDINATE
  }
  const double diagonal =
      std::sqrt(extent[0] * extent[0] + extent[1] * extent[1] + extent[2] * extent[2]);
  if (diagonal > MAX_EXTENT_OVER_SPACING * median_spacing)
    throw InputError(path + ": the points span " + text(diagonal) + ", " +
                     text(diagonal / median_spacing) +
                     " times their median spacing (more than a million): groups of points far "
                     "apart, or clumps of points "
                     "at almost the same position?");
}

/// The spacing checks: the median spacing (over points of their mean distance to their nearest
/// neighbours) is a robust scale where CGAL's average spacing is not: one far point inflates the
/// average in proportion to its distance.
void check_spacing(const OrientedPoints& input, const std::vector<std::size_t>& distinct,
                   const std::vector<Point3>& points, int k) {
  const Neighbours neighbours(points, static_cast<std::size_t>(std::max(k, 1)));
  std::vector<double> spacing(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) spacing[i] = neighbours.spacing(i);
  const double median_spacing = median(spacing);
  if (!(median_spacing >= MIN_SPACING))
    throw InputError(input.path + ": the points' median spacing is " + text(median_spacing) +
                     ", below 1e-12, where CGAL's surface mesher fails; scale the coordinates up");
  check_strays(input, distinct, points, neighbours, spacing, median_spacing);
  check_extent(input.path, points, median_spacing);
}

}  // namespace

std::vector<PointWithNormal> checked_points(const OrientedPoints& input, int neighbours,
                                            std::vector<std::size_t>* kept) {
  if (input.points.empty()) throw InputError(input.path + ": no points; at least 10 are needed");
  check_magnitudes(input);
  const std::vector<std::size_t> distinct = distinct_positions(input);
  std::vector<Point3> points;
  points.reserve(distinct.size());
  for (std::size_t i : distinct) points.push_back(input.points[i].first);
  if (points.size() == 1)
    throw InputError(input.path + ": all the points are at one position " + text(points[0]));
  // The positions count, not the lines: a position given again adds nothing to the solve
  // (distinct_positions). Fewer than 10 sample no closed surface that the solve can find.
  if (points.size() < 10)
    throw InputError(input.path + ": " + std::to_string(points.size()) + " distinct points" +
                     (points.size() < input.points.size()
                          ? " (on " + std::to_string(input.points.size()) + " lines)"
                          : std::string()) +
                     "; at least 10 are needed");
  check_volume(input.path, points);
  check_spacing(input, distinct, points, neighbours);
  std::vector<PointWithNormal> result;
  result.reserve(distinct.size());
  for (std::size_t i : distinct) result.push_back(input.points[i]);
  if (kept) *kept = distinct;
  return result;
}

}  // namespace shellcontract
