// Words of one line of an OBJ or MTL file: the readers of the OBJ document, its `mtllib` paths
// and the glTF's .mtl materials split lines the same way. The OBJ readers (scan_obj, the
// document, its mtllib paths) join continued lines first, with join_continued_lines.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>

namespace shellcontract {

/// Blank within a line: a "\r" of "\r\n" counts, "\n" (the end of the line) does not.
inline bool is_line_space(char c) {
  return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == '\r';
}

/// A span of a string's bytes, [begin, end).
struct Span {
  std::size_t begin = 0, end = 0;
};

/// The next blank-separated word of [at, end) in s; `at` moves past it. An empty span at `end`
/// when there is none.
inline Span next_token(const std::string& s, std::size_t& at, std::size_t end) {
  while (at < end && is_line_space(s[at])) ++at;
  Span t{at, at};
  while (at < end && !is_line_space(s[at])) ++at;
  t.end = at;
  return t;
}

/// The OBJ spec's line continuation: a backslash with nothing but blanks after it on its line (the
/// "\r" of "\r\n" among them) joins the next line to its line. This holds for every statement,
/// comments too, as Blender's importer reads them. Each such backslash and the line end after it
/// become spaces in `s`: a statement is then one line of `s`, and every byte keeps its offset, so
/// the OBJ document's edits still apply to the file's own bytes. `eol` is the file's line end
/// ('\n', or '\r' in a file without any '\n').
/// @return the offset of a continuation that no line follows (the file ends after its backslash,
///   blanks or line end), std::string::npos when there is none; the continuations before it are
///   joined
inline std::size_t join_continued_lines(std::string& s, char eol) {
  for (std::size_t b = s.find('\\'); b != std::string::npos; b = s.find('\\', b + 1)) {
    std::size_t e = b + 1;
    while (e < s.size() && s[e] != eol && is_line_space(s[e])) ++e;
    if (e == s.size() || (s[e] == eol && e + 1 == s.size())) return b;
    if (s[e] != eol) continue;  // a backslash within the line (a Windows path): text
    s[b] = ' ';
    s[e] = ' ';
    b = e;
  }
  return std::string::npos;
}

/// The physical line (from 1) of offset `at` in a file's text whose lines end with `eol`.
inline std::size_t line_of(const std::string& s, std::size_t at, char eol) {
  return 1 + static_cast<std::size_t>(
                 std::count(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(at), eol));
}

}  // namespace shellcontract
