// Words of one line of an OBJ or MTL file: the readers of the OBJ document, its `mtllib` paths
// and the glTF's .mtl materials split lines the same way.
#pragma once

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

}  // namespace shellcontract
