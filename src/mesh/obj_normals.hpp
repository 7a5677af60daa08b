// The normals an OBJ document writes for new positions (docs/design/attributes.md, "Normals").
// A `vn` line is a value, not a place on the surface: exporters write each distinct normal once
// (Blender's does), so one line may serve the corners of many vertices (every vertex inside a
// flat side of a smooth-shaded box) or of many polygons (every polygon of a flat-shaded side).
// Once the shell has moved those corners no longer share a normal, so a line is split into one
// normal per group of corners that still do.
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
  std::size_t vn_count = 0;                       ///< the `vn` lines
};

struct ObjNormals {
  /// Per `vn` line, the normals it becomes, in the order of their first corner; empty: the
  /// line stays as read (no polygon uses it, or all of its polygons lost their area).
  std::vector<std::vector<Vec3>> lines;
  /// Per corner, which of its line's normals it takes (0 for a corner without a `vn`).
  std::vector<std::size_t> pick;
};

/// The corners that use one `vn` line are grouped by vertex: the corners of one vertex that share
/// a line are smoothed together, so they get the area-weighted normal of their polygons. That is
/// the vertex's normal where all its corners share the line (smooth shading), the polygon's
/// normal where only one polygon uses the line (a flat face), and one normal per vertex and side
/// where a line is shared by a whole flat side (Blender's flat-shaded export: the side's polygons
/// are coplanar in the file, so nothing says whether they were meant to be smoothed together).
/// The smoothing groups (`s`) are not read: the spec gives explicit normals the last word, and
/// exporters write `s off` over smooth normals too. Vertices at the same position (x's rows
/// bitwise equal: the copies of a seam) count as one, so a seam does not show. Groups with the
/// same normal share it, so a file whose lines each served one group keeps one normal per line.
ObjNormals obj_normals(const Positions& x, const ObjCorners& corners);

}  // namespace shellcontract
