// The OBJ reader of read_polygon_soup (read_input_mesh's first step). CGAL::IO::read_OBJ is not
// used: it returns a bare `false` for a malformed `v` line, a face index out of range or an
// unknown statement (so no message could say where), reads "f 1 x 3" as a face of one corner, and
// lets an index one past the last vertex through to the checks, which then cannot name its line.
// tests/mesh/test_obj_scan_vs_cgal.cpp checks that both read the same points and faces from valid files.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "mesh/off_scan.hpp"

namespace shellcontract {

/// What the scan read.
struct ObjScan {
  SourceLines lines;                            ///< the line of every `v` and `f`
  std::vector<std::array<double, 3>> points;    ///< x y z of each `v` line, in file order
  std::vector<std::vector<std::size_t>> faces;  ///< 0-based vertex index of each corner of each `f`
};

/// Reads an OBJ file held in memory (a UTF-8 byte-order mark and the line ends already normalized
/// by the caller): the x y z of every `v` line (anything after them, such as a vertex colour, is
/// not read) and the vertex of every corner of every `f` line (`v`, `v/vt`, `v/vt/vn`, `v//vn`;
/// the vt and vn indices are not read), in file order, as CGAL::IO::read_OBJ reads them: indices
/// count from 1, a negative one counts back from the last `v` before its line, a positive one may
/// name a `v` further down. Every other statement CGAL's reader accepts (vt, vn, g, o, s, usemtl,
/// mtllib, comments, ...) is skipped; one it refuses is refused here too, with its line. A line
/// that ends with a backslash continues on the next (join_continued_lines, which CGAL's reader
/// does not know); a statement's line, in SourceLines and in messages, is the one it starts on.
/// @param path  the file's name, for messages only
/// @param missing  MissingVertices::Keep: a face index out of range is read, not refused
/// @throws InputError "<path>: <problem>: <vertex or face and its line>: <details>"
ObjScan scan_obj(const std::string& path, const std::string& text,
                 MissingVertices missing = MissingVertices::Refuse);

}  // namespace shellcontract
