// A line-based pre-scan of OFF files (read_input_mesh's helper): it says which line is wrong,
// and it makes sure that the file CGAL's OFF reader then reads is consistent (CGAL resizes its
// arrays to the declared counts before reading, and returns a bare `false` on any error).
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

/// What the scan found: the lines of an ascii file, or the contents of a binary one.
struct OffScan {
  SourceLines lines;    ///< ascii: the line of every vertex and face
  bool binary = false;  ///< "OFF BINARY": read here (points, faces), not by CGAL
  std::vector<std::array<double, 3>> points;    ///< binary only
  std::vector<std::vector<std::size_t>> faces;  ///< binary only
};

/// Checks the layout of an OFF file held in memory (a UTF-8 byte-order mark and the line ends
/// already normalized by the caller): header, counts, one vertex or face per line with '#'
/// comments, every index in range. Handles OFF and its ASCII variants with the prefixes
/// C, N, ST, 4 and n (dimension 3 only). Plain "OFF BINARY" (big-endian, as CGAL writes it) is
/// read here entirely: CGAL 5.5's polygon-soup reader does not skip a binary face's colour count
/// and misreads every face after the first. Counts are checked against the file's size, never
/// reserved as declared.
/// @param path  the file's name, for messages only
/// @throws InputError "<path>: <problem>: <where>" for a file CGAL must not be given
OffScan scan_off(const std::string& path, const std::string& text);

}  // namespace shellcontract
