// The normals an OBJ document writes for new positions (docs/design/attributes.md, "Normals").
// A `vn` line is a value, not a place on the surface, and how exporters lay the values out in
// lines varies: Blender's writes each distinct normal once, so one line may serve the corners of
// many vertices (every vertex inside a flat side of a smooth-shaded box) or of many polygons
// (every polygon of a flat-shaded side); others write one line per face corner, or one per vertex
// copy at a UV seam (`f a/a/a`), so that equal values sit in many lines. Which corners are shaded
// together is therefore said by the values, at one vertex, not by the lines: once the shell has
// moved, the corners that shared a value at a vertex share one new normal, and a line whose
// corners no longer share a normal is split into one normal per group of corners that still do.
#pragma once

#include <cstddef>
#include <vector>

#include "shellcontract/types.hpp"

namespace shellcontract {

/// An OBJ file's polygons as the document read them.
struct ObjCorners {
  const std::vector<std::size_t>* polygon_start;  ///< polygon p: corners [start[p], start[p + 1])
  const std::vector<std::size_t>* corner_vertex;  ///< per corner: its `v` line, 0-based
  const std::vector<long long>* corner_vn;        ///< per corner: its `vn` line, 0-based; -1 none
  /// Per `vn` line: its value as a unit vector; zero where it has none (not three finite numbers,
  /// or of no length).
  const std::vector<Vec3>* vn_dir;
};

/// Per corner, its normal group (soup::normal_groups, numbered from 0 in order of first use):
/// the corners at one vertex whose `vn` values are the same within soup::kSameNormal, whatever
/// lines hold them; -1 for a corner without a `vn`.
/// @param position_of per `v` line, the vertex it is one copy of (vertices with the same number
///                    are one: the copies of a seam)
std::vector<long long> obj_corner_groups(const std::vector<std::size_t>& position_of,
                                         const ObjCorners& corners);

struct ObjNormals {
  /// Per `vn` line, the normals it becomes, in the order of their first corner; empty: the
  /// line stays as read (no polygon uses it, or all of its polygons lost their area).
  std::vector<std::vector<Vec3>> lines;
  /// Per corner, which of its line's normals it takes (0 for a corner without a `vn`).
  std::vector<std::size_t> pick;
};

/// The corners of each normal group (obj_corner_groups, vertices at the same position in x, its
/// rows bitwise equal, counting as one, so a seam does not show) get the normalized sum of their
/// polygons' vector areas at positions x. That is the vertex's normal where all its corners share
/// a value (smooth shading, however many lines hold it), the polygon's normal where only one
/// polygon has that value at the vertex (a flat face, a hard edge), and one normal per vertex and
/// side where a value is shared by a whole flat side (Blender's flat-shaded export: the side's
/// polygons are coplanar in the file, so nothing says whether they were meant to be smoothed
/// together). The smoothing groups (`s`) are not read: the spec gives explicit normals the last
/// word, and exporters write `s off` over smooth normals too. Each line then holds the distinct
/// normals of its corners, so a file whose lines each served one group keeps one normal per line.
ObjNormals obj_normals(const Positions& x, const ObjCorners& corners);

}  // namespace shellcontract
