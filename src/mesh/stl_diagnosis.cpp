// The STL diagnosis (see stl_diagnosis.hpp). The ASCII scan follows CGAL 5.5's parse_ASCII_STL
// step by step: at the top level only "solid", "facet" and "endsolid" count (other words, such as
// a solid's name, are skipped), inside a facet only "vertex" and "endfacet" ("normal", "outer
// loop", "endloop" are skipped), and a vertex's numbers are read by the same stream extraction
// (`is >> double`) from the same place. What CGAL skips is not reported: the scan reports only a
// file whose reading CGAL stops, at the place where it stops, except for a facet whose 'endloop'
// or 'endfacet' line is missing: CGAL reads on into what follows and stops there (at the next
// facet's first vertex), and the scan names the line where the closing word was expected.
#include "mesh/stl_diagnosis.hpp"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <locale>
#include <sstream>
#include <string_view>

#include "core/decimal_text.hpp"
#include "core/token_text.hpp"

namespace shellcontract {
namespace {

/// Blanks as the "C" locale's isspace, which CGAL's `is >> word` splits at.
bool blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

/// An STL's texts are quoted longer than the other readers' tokens: a line ("vertex 1 2 3"), a
/// solid's name.
constexpr std::size_t QUOTED_CHARS = 40;

std::string quote(std::string_view s) { return "'" + shorten(s, QUOTED_CHARS) + "'"; }

/// Text: no control byte but blanks and line ends (a name in UTF-8 is text too).
bool is_text(const std::string& bytes) {
  for (char ch : bytes) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 && !blank(ch)) return false;
  }
  return true;
}

class AsciiScan {
 public:
  explicit AsciiScan(const std::string& text) : text_(text) {}

  StlDiagnosis run() {
    bool in_solid = false, solid_found = false;
    std::size_t solid_line = 0;
    std::string_view w;
    while (word(w)) {
      const std::size_t line = line_at(at_);
      if (w == "solid") {
        if (in_solid)
          return {"parse error", where(line) + ": expected 'endsolid' to close the solid begun on line " +
                                     std::to_string(solid_line) + ", got " + quote(line_text(at_))};
        in_solid = true;
        solid_line = line;
      }
      if (w == "facet") {
        StlDiagnosis d = facet(line);
        if (!d.problem.empty()) return d;
      } else if (w == "endsolid") {
        in_solid = false;
        solid_found = true;
      }
    }
    if (in_solid)
      return {"truncated file", "the solid begun on line " + std::to_string(solid_line) + " has no 'endsolid': the file ends at " +
                                    last_line()};
    if (!solid_found)
      return {"parse error", "no 'solid NAME' ... 'endsolid' in the file (an ASCII STL begins with 'solid NAME' on line 1), and it is not "
                             "a binary STL either (" + std::to_string(text_.size()) + " bytes of text)"};
    return {};
  }

 private:
  /// After the word "facet" (on line `begun`): its vertices, up to "endfacet".
  StlDiagnosis facet(std::size_t begun) {
    const std::string facet_begun = "the facet begun on line " + std::to_string(begun);
    int count = 0;
    // After the 3rd vertex only 'endloop' and 'endfacet' belong. CGAL skips any other word there
    // and fails only later (at the next facet's first vertex, taken for a 4th, or at the end of
    // the file), so the first such word, where the closing line was missing, is kept to name it.
    bool endloop = false;
    std::size_t stray_at = 0, stray_line = 0;
    const auto missing = [&]() -> StlDiagnosis {
      return {"parse error", where(stray_line) + ": expected '" + (endloop ? "endfacet" : "endloop") + "' after the 3 vertices of " +
                                 facet_begun + ", got " + quote(line_text(stray_at))};
    };
    std::string_view w;
    while (word(w)) {
      const std::size_t line = line_at(at_);
      if (w == "endfacet") {
        if (count != 3)
          return {"parse error", where(line) + ": " + facet_begun + " ends with " + std::to_string(count) +
                                     (count == 1 ? " vertex" : " vertices") + "; STL facets are triangles (3 vertices)"};
        return {};
      }
      if (count == 3 && stray_line == 0) {
        if (w == "endloop" && !endloop) {
          endloop = true;
          continue;
        }
        if (w != "vertex" || endloop) {  // a vertex right after the 3rd is a 4th (below)
          stray_at = at_;
          stray_line = line;
        }
      }
      if (w != "vertex") continue;
      const std::size_t vertex_at = at_;
      if (count >= 3) {
        if (stray_line != 0) return missing();
        return {"parse error", where(line) + ": a 4th vertex in " + facet_begun + ", got " + quote(line_text(vertex_at)) +
                                   "; STL facets are triangles (3 vertices)"};
      }
      for (int k = 0; k < 3; ++k) {
        StlDiagnosis d = number(vertex_at, k, facet_begun);
        if (!d.problem.empty()) return d;
      }
      ++count;
    }
    if (stray_line != 0) return missing();
    const std::string expected = count < 3 ? "vertex " + std::to_string(count + 1) + " of 3"
                                           : std::string(endloop ? "'endfacet'" : "'endloop'") + " after its 3 vertices";
    return {"truncated file", "the file ends at " + last_line() + " inside " + facet_begun + " (expected " + expected + ")"};
  }

  /// Coordinate k of the vertex whose word "vertex" is at byte `vertex_at`, read as CGAL reads it.
  StlDiagnosis number(std::size_t vertex_at, int k, const std::string& facet_begun) {
    const std::size_t vertex_line = line_at(vertex_at);
    skip_blanks();
    if (pos_ >= text_.size())
      return {"truncated file", "the file ends at " + last_line() + " inside " + facet_begun + ", in the vertex of line " +
                                    std::to_string(vertex_line) + " (expected 'vertex X Y Z')"};
    // A number holds no blank, so a stream over the next word alone reads what CGAL's stream
    // over the whole file reads from there (and the file is not copied).
    std::size_t end = pos_;
    while (end < text_.size() && !blank(text_[end])) ++end;
    const std::string token = text_.substr(pos_, end - pos_);
    std::istringstream in(token);
    in.imbue(std::locale::classic());  // as read_polygon_soup reads it (core/classic_locale.hpp)
    double x = 0.0;
    if (in >> x) {
      const std::streamoff p = in.tellg();
      pos_ += p < 0 ? token.size() : static_cast<std::size_t>(p);
      return {};
    }
    // A token that strtod reads in full to a non-finite value ("nan", "inf", "1e999"): the stream
    // refuses it as a number, the message says why.
    double v = 0.0;
    const bool whole = parse_c_number(token, v);
    // The vertex's line; the number's too where CGAL read on to a later line for it.
    const std::size_t line = line_at(pos_);
    const std::string also = line == vertex_line ? "" : " (then line " + std::to_string(line) + ": " + quote(token) + ")";
    if (whole && !std::isfinite(v))
      return {"non-finite coordinate", where(vertex_line) + ": the vertex of " + facet_begun +
                                           " has coordinate " + "xyz"[k] + " = " +
                                           shorten(token, QUOTED_CHARS) + also};
    return {"parse error", where(vertex_line) + ": expected 'vertex X Y Z' with three numbers, got " + quote(line_text(vertex_at)) + also};
  }

  void skip_blanks() {
    while (pos_ < text_.size() && blank(text_[pos_])) ++pos_;
  }
  /// The next word (as `is >> std::string`), its first byte in at_; false at the end of the file.
  bool word(std::string_view& w) {
    skip_blanks();
    if (pos_ >= text_.size()) return false;
    at_ = pos_;
    while (pos_ < text_.size() && !blank(text_[pos_])) ++pos_;
    w = std::string_view(text_).substr(at_, pos_ - at_);
    return true;
  }
  /// The line (from 1) of byte `pos`; positions asked for never go back. "\n", "\r\n" and a lone
  /// "\r" end a line.
  std::size_t line_at(std::size_t pos) {
    for (; counted_ < pos && counted_ < text_.size(); ++counted_) {
      const char c = text_[counted_];
      if (c == '\n' || (c == '\r' && (counted_ + 1 >= text_.size() || text_[counted_ + 1] != '\n'))) ++line_;
    }
    return line_;
  }
  static std::string where(std::size_t line) { return "line " + std::to_string(line); }
  /// The line that holds byte `pos`, without its blanks at either end.
  std::string_view line_text(std::size_t pos) const {
    const std::string_view t(text_);
    std::size_t b = pos, e = pos;
    while (b > 0 && t[b - 1] != '\n' && t[b - 1] != '\r') --b;
    while (e < t.size() && t[e] != '\n' && t[e] != '\r') ++e;
    while (b < e && blank(t[b])) ++b;
    while (e > b && blank(t[e - 1])) --e;
    return t.substr(b, e - b);
  }
  /// "line N ('text')" for the file's last line that is not blank.
  std::string last_line() {
    std::size_t e = text_.size();
    while (e > 0 && blank(text_[e - 1])) --e;
    if (e == 0) return "line 1";
    const std::size_t pos = e - 1;
    return where(line_at(pos)) + " (" + quote(line_text(pos)) + ")";
  }

  const std::string& text_;
  std::size_t pos_ = 0;    ///< the next byte to read
  std::size_t at_ = 0;     ///< the first byte of the last word
  std::size_t counted_ = 0, line_ = 1;
};

StlDiagnosis binary_non_finite(const std::string& bytes, std::uint32_t count);

StlDiagnosis diagnose_binary(const std::string& bytes) {
  const std::uint64_t size = bytes.size();
  if (size < 84)
    return {"truncated file", "the file has " + std::to_string(size) + " bytes, a binary STL has at least 84 (an 80-byte header and a 4-byte facet count)"};
  std::uint32_t count = 0;  // as CGAL reads it: the machine's byte order
  std::memcpy(&count, bytes.data() + 80, sizeof count);
  const std::uint64_t need = 84 + 50 * static_cast<std::uint64_t>(count);
  if (size < need) {
    const std::uint64_t whole = (size - 84) / 50, part = (size - 84) % 50;
    std::string s = "the header says " + std::to_string(count) + " facets (" + std::to_string(need) + " bytes), the file has " +
                    std::to_string(size) + " bytes; ";
    if (part != 0)
      s += "facet " + std::to_string(whole) + " is cut after " + std::to_string(part) + " of its 50 bytes";
    else
      s += "it ends after " + std::to_string(whole) + " whole facets";
    return {"truncated file", s};
  }
  return binary_non_finite(bytes, count);
}

/// The first non-finite vertex coordinate of a binary file's `count` facets (all in the file).
StlDiagnosis binary_non_finite(const std::string& bytes, std::uint32_t count) {
  for (std::uint64_t f = 0; f < count; ++f)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) {
        float x = 0.0F;
        std::memcpy(&x, bytes.data() + 84 + 50 * f + 12 * (c + 1) + 4 * k, sizeof x);
        if (!std::isfinite(x)) {
          std::ostringstream v;
          v.imbue(std::locale::classic());  // core/classic_locale.hpp
          v << x;
          return {"non-finite coordinate", "facet " + std::to_string(f) + " (bytes " + std::to_string(84 + 50 * f) + " to " +
                                               std::to_string(84 + 50 * f + 49) + ") has corner " + std::to_string(c) +
                                               " with coordinate " + "xyz"[k] + " = " + v.str()};
        }
      }
  return {};
}

/// As CGAL 5.5's read_STL decides: after blanks, "solid" and a blank ('\n', '\r', ' ') make it
/// try ASCII first. Fewer than 6 bytes there: CGAL reads an empty file.
enum class FirstTry { ascii, binary, nothing };
FirstTry cgal_first_try(const std::string& bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && blank(bytes[i])) ++i;
  if (bytes.size() - i < 6) return FirstTry::nothing;
  const char c = bytes[i + 5];
  return bytes.compare(i, 5, "solid") == 0 && (c == '\n' || c == '\r' || c == ' ') ? FirstTry::ascii : FirstTry::binary;
}

/// The first STL keyword in other case than CGAL's ("Solid", "FACET": some CAD exporters), with
/// its line; an empty problem if there is none.
StlDiagnosis keyword_not_in_lower_case(const std::string& bytes) {
  std::size_t i = 0, line = 1;
  for (;;) {
    while (i < bytes.size() && blank(bytes[i])) line += bytes[i++] == '\n';
    if (i == bytes.size()) return {};
    std::size_t e = i;
    while (e < bytes.size() && !blank(bytes[e])) ++e;
    const std::string word(bytes, i, e - i);
    std::string lower = word;
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (lower != word && (lower == "solid" || lower == "facet" || lower == "vertex" ||
                          lower == "endfacet" || lower == "endsolid"))
      return {"parse error", "line " + std::to_string(line) + ": the keyword " + quote(word) +
                                 " is not in lower case (an ASCII STL's keywords are)"};
    i = e;
  }
}

/// A UTF-8 byte-order mark before the text: invisible in an editor, it makes the first word
/// something other than 'solid' to CGAL.
StlDiagnosis byte_order_mark(const std::string& bytes) {
  if (bytes.compare(0, 3, "\xEF\xBB\xBF") != 0) return {};
  return {"parse error",
          "line 1: the text begins with a UTF-8 byte-order mark (3 bytes before 'solid', unseen in "
          "an editor), which an ASCII STL may not have: save the file without it"};
}

/// Why text is no ASCII STL to CGAL, most telling first: a byte-order mark, a keyword not in
/// lower case, then the scan's own finding.
StlDiagnosis text_problem(const std::string& bytes, const StlDiagnosis& scan) {
  const StlDiagnosis mark = byte_order_mark(bytes);
  if (!mark.problem.empty()) return mark;
  const StlDiagnosis keyword = keyword_not_in_lower_case(bytes);
  if (!keyword.problem.empty()) return keyword;
  return scan;
}

}  // namespace

StlDiagnosis non_finite_in_binary_stl(const std::string& bytes) {
  const FirstTry first = cgal_first_try(bytes);
  if (first == FirstTry::nothing || bytes.size() < 84) return {};
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, sizeof count);
  if (bytes.size() < 84 + 50 * static_cast<std::uint64_t>(count)) return {};  // not read as binary
  // A file that begins with "solid" was read as binary only if CGAL's ASCII reading failed.
  if (first == FirstTry::ascii && AsciiScan(bytes).run().problem.empty()) return {};
  return binary_non_finite(bytes, count);
}

StlDiagnosis text_read_as_binary(const std::string& bytes) {
  // Text is never a binary STL: each byte of its facet count (bytes 80-83) is 0x20 or more, so
  // the count is at least 0x20202020, more facets (50 bytes each) than the text's size holds.
  const FirstTry first = cgal_first_try(bytes);
  if (first == FirstTry::nothing || !is_text(bytes)) return {};
  const StlDiagnosis scan = AsciiScan(bytes).run();
  if (first == FirstTry::ascii && scan.problem.empty()) return {};  // CGAL's ASCII reading
  // Read as binary facets of the text: why it is no ASCII STL to CGAL.
  const StlDiagnosis why = text_problem(bytes, scan);
  if (!why.problem.empty()) return why;
  return {"parse error",
          "line 1: an ASCII STL begins with 'solid' and a space or a line end (other text, such "
          "as 'solid' and a tab, is read as binary facets of its bytes)"};
}

StlDiagnosis diagnose_stl(const std::string& bytes) {
  if (is_text(bytes)) {
    const StlDiagnosis scan = AsciiScan(bytes).run();
    return scan.problem.empty() ? scan : text_problem(bytes, scan);
  }
  return diagnose_binary(bytes);
}

}  // namespace shellcontract
