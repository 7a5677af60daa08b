// The OFF reader (read_input_mesh's helper): a line-based scan that says which line is wrong, and
// keeps the coordinates and faces it parses on the way. CGAL's OFF reader is not used: it resizes
// its arrays to the declared counts before reading, returns a bare `false` on any error, misreads
// binary OFF, and parses every line again through a string stream (a large part of reading
// bear x16: lab/pages/scale.md). tests/mesh/test_off_scan_vs_cgal.cpp checks that both
// read the same points and faces from valid files of every variant.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace shellcontract {

/// Where each vertex and face of a text file starts (1-based lines), for messages.
struct SourceLines {
  std::vector<std::size_t> vertex_line;  ///< line of vertex i; empty if unknown
  std::vector<std::size_t> face_line;    ///< line of face i; empty if unknown
};

/// What a reader does with a face that names a vertex the file lacks (an index past the last
/// vertex, a negative one, OBJ's 0).
enum class MissingVertices {
  Refuse,  ///< an InputError naming the face and its line: every reader but repair's
  /// The face is read, with that index (SIZE_MAX for a negative one or OBJ's 0): repair reads so,
  /// and drops such faces in its soup step (docs/design/repair.md), saying which.
  Keep
};

/// What the scan read.
struct OffScan {
  SourceLines lines;    ///< ascii: the line of every vertex and face
  std::vector<std::array<double, 3>> points;    ///< x / w, y / w, z / w (w = 1 unless "4OFF")
  std::vector<std::vector<std::size_t>> faces;  ///< each face's vertex indices, colours dropped
  /// Content after the declared faces, which is not read (ascii: "<path>: line N: ..."); empty
  /// when there is none but blank and comment lines.
  std::string ignored_tail;
};

/// Reads an OFF file held in memory (a UTF-8 byte-order mark and the line ends already
/// normalized by the caller), checking its layout: header, counts, one vertex or face per line
/// with '#' comments, every index in range. Handles OFF and its ASCII variants with the prefixes
/// C, N, ST, 4 and n (dimension 3 only), as CGAL's reader does (the first three numbers of a
/// vertex, divided by the fourth for "4OFF"). Plain "OFF BINARY" (big-endian, as CGAL writes it):
/// CGAL 5.5's polygon-soup reader does not skip a binary face's colour count and misreads every
/// face after the first. Counts are checked against the file's size, never reserved as declared.
/// @param path  the file's name, for messages only
/// @param missing  MissingVertices::Keep: a face index out of range is read, not refused
/// @throws InputError "<path>: <problem>: <where>" for a file CGAL must not be given
OffScan scan_off(const std::string& path, const std::string& text,
                 MissingVertices missing = MissingVertices::Refuse);

}  // namespace shellcontract
