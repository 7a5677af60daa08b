// How read_input_mesh (io.cpp) splits a polygon of more than three corners into triangles for the
// simulation (private to src/mesh; docs/design/attributes.md, "The document"). The rule must
// accept every polygon file that `run` writes: an output's polygons are the input's, with corners
// moved by the simulation, which bent and may have folded them along the diagonals of their split.
#pragma once

#include <cstddef>
#include <vector>

#include "mesh/soup_checks.hpp"
#include "shellcontract/mesh.hpp"

namespace shellcontract::soup {

/// The most corners of a polygon that read_input_mesh splits; a larger one is refused (exit 2,
/// naming its face and line). The rules below try a fan from each corner and clip ears testing
/// every corner left, time that grows with the square of the corners (or faster), so a single
/// face of a small file could hold the reader for minutes before any message; below this
/// bound a polygon is split within seconds. A modelling tool splits a larger one in an instant.
constexpr std::size_t MAX_SPLIT_CORNERS = 10000;

/// The bound above is per polygon; a file may hold any number of such polygons, each checked and
/// split in time of the square of its corners, before the checks that refuse them (a file of the
/// same large polygon many times is duplicate faces). So the squares of the corners of a file's
/// polygons of more than SMALL_SPLIT_CORNERS corners (a smaller one costs at most that many steps
/// per corner, time in proportion to the file) may add up to MAX_SPLIT_WORK, ten polygons of
/// MAX_SPLIT_CORNERS; a file past it is refused before any is split (exit 2, naming the largest).
constexpr std::size_t SMALL_SPLIT_CORNERS = 100;
constexpr std::size_t MAX_SPLIT_WORK = 10 * MAX_SPLIT_CORNERS * MAX_SPLIT_CORNERS;

/// The rules of split_polygon below, numbered as there; `flat` is rule 1's zero-normal case.
enum class SplitRule { fan, flat, diagonal, ear_clip, best_fan };
constexpr std::size_t SPLIT_RULES = 5;  ///< SplitRule's values, for counting by rule

/// The triangles of polygon `p` (more than three distinct corners, indices into `pts`, which are
/// at a unit bounding-box diagonal), each wound like the polygon, in this order of preference:
/// 1. a fan from the first corner whose fan triangles all face along the polygon's Newell normal
///    (any convex polygon, and star-shaped ones seen from that corner); a polygon with a zero
///    Newell normal (flat) gets corner 0's fan, whose zero-area triangles are then reported;
/// 2. a quad that no corner fans (folded or bent, as `run` may leave it): the diagonal whose two
///    triangles' normals agree most (the least folded), ties to the diagonal from corner 0; a
///    diagonal with a zero-area triangle only when the other one has one too;
/// 3. a larger polygon: ear clipping of the polygon projected on the plane of its Newell normal
///    (any simple polygon in that projection);
/// 4. a fan from the corner whose triangles' normals agree best with the Newell normal (the
///    largest smallest cosine), among those fans that have no zero-area triangle.
/// @param rule if given, set to the rule that split it (left unchanged when refused), so that the
///        reader's warning says which rules it used
/// @return the triangles, or an empty vector when none of these applies (then refused)
std::vector<Polygon> split_polygon(const Polygon& p, const std::vector<Point3>& pts,
                                   SplitRule* rule = nullptr);

/// Polygon `p` split into the triangles another file's polygon `like` was split into (a result of
/// `run` read as its input was: `check --against`), each wound like `p` and starting at the corner
/// its triangle in `triangles` starts at; empty when `p` is not `like` (the same corners in the
/// same cycle, from any corner and either way round) or `triangles` are not n - 2 triangles of
/// `like`'s corners. No rule above is applied: the split is the one `like`'s was.
std::vector<Polygon> split_like(const Polygon& p, const Polygon& like,
                                const std::vector<Polygon>& triangles);

}  // namespace shellcontract::soup
