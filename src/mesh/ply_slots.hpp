// Where a PLY document's vertex values are in the file and how they are written
// (ply_document.cpp), with the check that float32 x, y, z can hold the positions (private to
// src/mesh).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "mesh/ply_header.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract::ply {

/// Where a vertex coordinate is in the file and how it is stored.
struct Slot {
  std::size_t begin = 0, end = 0;  ///< ascii: the token's span; binary: [offset, offset + size)
  Type type = Type::Float32;       ///< as the file stores the value
  bool set = false;
  /// The value the file holds (for an integer normal that keeps the file's value: its bytes alone
  /// no longer fit the double the header declares).
  double original = 0.0;
};

/// The type a slot's new value is written in: an integer-typed x, y, z, nx, ny or nz becomes
/// double, in the header too (see PlyDocument's constructor), since positions and unit normals are
/// not integers.
inline Type written_type(const Slot& s) { return is_integer(s.type) ? Type::Float64 : s.type; }

/// Refuses positions that the file's float32 x, y, z cannot hold, which would otherwise be written
/// wrong without a word: a coordinate beyond the float range (written as inf, a file no reader
/// takes), and a mesh whose float32 coordinates are all below the smallest normal float
/// (1.17549435e-38): stored, they would be zero or subnormal
/// (a mesh of one point, or of a few bits of precision). A coordinate alone that is that small
/// beside larger ones loses nothing that matters (at most the float rounding of the mesh's extent)
/// and is written.
/// @throws UsageError naming `name` (the document's file), the vertex, its axis and the value
void require_representable(const std::string& name, const std::vector<Slot>& slots,
                           const Positions& x);

}  // namespace shellcontract::ply
