// The lines of the tool's own line-based text files (face lists, weights files): "\n", "\r\n"
// and a lone "\r" (classic Mac OS line ends, which some exporters still write) each end a line,
// as the OBJ and PLY readers take them. A reader that split at "\n" alone read a file of "\r"
// line ends as one line: a face list's regions merged into one without a word.
#pragma once

#include <cstddef>
#include <string_view>

namespace shellcontract {

/// A UTF-8 byte order mark, which Windows editors write at a text file's start: not text.
inline std::size_t skip_utf8_bom(std::string_view text) {
  return text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
}

/// The line of `text` that starts at `begin`, without its line end; `begin` moves to the start of
/// the next line (text.size() after the last one). Call while begin < text.size().
inline std::string_view next_line(std::string_view text, std::size_t& begin) {
  const std::size_t start = begin;
  const std::size_t end = text.find_first_of("\r\n", start);
  if (end == std::string_view::npos) {
    begin = text.size();
    return text.substr(start);
  }
  begin = end + 1;
  if (text[end] == '\r' && begin < text.size() && text[begin] == '\n') ++begin;
  return text.substr(start, end - start);
}

}  // namespace shellcontract
