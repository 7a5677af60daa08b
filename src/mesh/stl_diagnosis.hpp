// Why CGAL's STL reader refused a file, and where (read_polygon_soup's message). CGAL reads every
// STL file that it accepts; when it refuses one it returns a bare `false`, and the message said
// neither where nor what. This scan runs only then: it walks the file as CGAL's reader does
// (CGAL/IO/STL/STL_reader.h) and says where that reading stops, in the words of the STL grammar.
#pragma once

#include <string>

namespace shellcontract {

/// The problem ("parse error", "truncated file", "non-finite coordinate", "not a triangle mesh")
/// and where it is ("line 11: expected 'vertex X Y Z' with three numbers, got 'vertex abc 0 1'"),
/// as the other readers word them after the file's name.
struct StlDiagnosis {
  std::string problem;
  std::string details;
};

/// Diagnoses a file that CGAL::IO::read_STL refused. ASCII or binary is decided as the bytes
/// allow: a file of text (no control bytes but blanks and line ends) is diagnosed as ASCII, any
/// other as binary (80-byte header, uint32 facet count, 50 bytes a facet), whatever its first
/// word: binary files may begin with "solid", and CGAL tries both readings before refusing. (CGAL
/// 5.5's read_STL has no size rule: it tries ASCII first after a first word "solid" and a blank,
/// binary first otherwise, then the other; a binary file of 84 + 50 x count bytes or more is always
/// read, so a refused binary file is one cut short.)
/// @return an empty problem if the scan finds nothing wrong (the caller keeps a general message)
StlDiagnosis diagnose_stl(const std::string& bytes);

/// A file that CGAL::IO::read_STL accepted: if CGAL read it as binary, its first non-finite vertex
/// coordinate, with the facet and corner ("non-finite coordinate"). CGAL keeps an infinite one
/// (the checks after it refuse it), but it merges a NaN point with another one of its points
/// (its std::map of points cannot order NaN), and the file was read as a valid mesh.
/// @return an empty problem if the file was read as ASCII or every coordinate is finite
StlDiagnosis non_finite_in_binary_stl(const std::string& bytes);

/// A file that CGAL::IO::read_STL accepted: whether it is text that CGAL read as a binary STL
/// (CGAL tries binary first unless the text begins with 'solid' and a space or a line end, and
/// after a failed ASCII reading; it reads any 84 bytes or more as binary): an ASCII STL whose
/// keywords are not all lower case ("Solid", "FACET") was read as facets of the text's bytes,
/// and refused later for what those made (an open boundary at 1e+31, a duplicate of a facet the
/// file does not have). The text is scanned as CGAL's ASCII reading goes; text that it reads is
/// CGAL's ASCII reading and is kept.
/// @return the scan's problem, with the keyword's case named; empty if the file is not text, or
///         CGAL read it as ASCII
StlDiagnosis text_read_as_binary(const std::string& bytes);

}  // namespace shellcontract
