// Private to the cap finder (cap_finder.cpp, docs/math/cap-finder.md section 4): whether a
// concave crease lies between a seed and a kept part, from shortest edge paths inside the part's
// same-part ball.
#pragma once

#include <vector>

#include "geometry/cap_internal.hpp"

namespace shellcontract::detail {

/// Shortest edge paths from a seed to a part's vertices, over the vertices inside a ball about
/// the part's sphere, with or without stepping on concave vertices. Scratch arrays are kept
/// between queries and reset through the list of what a query reached.
class CreasePaths {
 public:
  /// crease[v] != 0 marks the concave vertices (the smallest smoothing below zero).
  CreasePaths(const MeshArrays& m, const Positions& x, const std::vector<char>& crease);

  /// The edge-graph distance from seed s to the nearest vertex v with vertex_part[v] == part,
  /// over the vertices within `ball` of c, stepping on no concave vertex when `convex`; infinity
  /// when none is reached. With `path`, the path's vertices from s to that vertex.
  double distance(int s, const Vec3& c, double ball, int part, const std::vector<int>& vertex_part,
                  bool convex, std::vector<int>* path = nullptr);

  /// Whether a concave crease lies between seed s and the part (inside its ball): every path
  /// from the seed to the part that steps on no concave vertex is more than CREASE_DETOUR times
  /// the shortest path, or there is none. A seed that reaches no part vertex inside the ball is
  /// not across a crease.
  bool across(int s, const Vec3& c, double ball, int part, const std::vector<int>& vertex_part);

 private:
  const MeshArrays& m_;
  const Positions& x_;
  const std::vector<char>& crease_;
  std::vector<double> dist_;
  std::vector<int> prev_;
};

/// A seed is across a crease from a part when the way round the concave vertices is more than
/// this many times the shortest way: longer than half a circle whose radius is the shortest way.
/// A concave spot inside one part (an eye, the corner of a mouth) costs a shorter detour, the
/// groove between two knuckles of a fist the way round the groove's end or no way at all. The
/// two kinds are measured apart on the paper's meshes and on the same meshes split in four, with
/// this factor about as far from each (docs/math/cap-finder.md section 4,
/// lab/regions/same_part.md): a ratio of two edge-path lengths over the same vertices, it does
/// not change with scale or rotation.
constexpr double CREASE_DETOUR = PI;

}  // namespace shellcontract::detail
