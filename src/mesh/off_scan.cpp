// The OFF reader (see off_scan.hpp). CGAL's OFF reader returns a bare `false` on a truncated or
// garbled file, and it resizes its arrays to the declared counts (and each face to its declared
// corner count) before reading them: a header that announces 10^12 vertices aborted the tool
// with std::bad_alloc. This scan walks the file line by line (one vertex or face per line, '#'
// comments) without trusting any count: it says which line is wrong, records the line of every
// vertex and face for later messages, and keeps what it parsed (CGAL's reader, which the scan
// once only checked files for, parsed them a second time).
#include "mesh/off_scan.hpp"

#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <regex>
#include <string_view>

#include "core/decimal_text.hpp"
#include "core/plural.hpp"
#include "core/token_text.hpp"
#include "mesh/scan_errors.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/face_error.hpp"

namespace shellcontract {
namespace {

using scan_errors::fail;
using scan_errors::fail_face;

/// index()'s `corner_of` for a token that is no face's corner.
constexpr std::size_t NOT_A_CORNER = SIZE_MAX;

/// What an OFF keyword (ST)?C?N?4?n?OFF says about each vertex line.
struct OffVariant {
  bool homogeneous = false;  ///< "4": x y z w
  bool dimensional = false;  ///< "n": a dimension precedes the counts
  std::size_t vertex_numbers = 3;  ///< numbers a vertex line holds at least (colours are optional)
};

class OffScanner {
 public:
  OffScanner(const std::string& path, const std::string& text, MissingVertices missing)
      : path_(path), text_(text), missing_(missing) {}

  OffScan scan() {
    std::vector<std::string_view> t;
    if (!next(t)) fail(path_, "empty file", "no OFF header, the file holds only blank or comment lines");
    const std::size_t header_line = line_;
    static const std::regex keyword("(ST)?(C)?(N)?(4)?(n)?OFF");
    std::smatch m;
    const std::string header(t[0]);
    if (!std::regex_match(header, m, keyword))
      fail(path_, "parse error", "line " + std::to_string(line_) + ": expected the OFF header, found '" + shorten(t[0]) + "'");
    OffVariant variant;
    variant.homogeneous = m[4].matched;
    variant.dimensional = m[5].matched;
    variant.vertex_numbers = 3 + (m[4].matched ? 1 : 0) + (m[3].matched ? 3 : 0) + (m[1].matched ? 2 : 0);
    t.erase(t.begin());
    if (!t.empty() && t[0] == "BINARY") {
      if (m.length(0) != 3)
        fail(path_, "unsupported OFF variant", "line " + std::to_string(line_) + ": only plain 'OFF BINARY' is read among the binary variants");
      return scan_binary();
    }
    if (t.empty() && !next(t))
      fail(path_, "truncated file", "the file ends after the OFF header (line " + std::to_string(header_line) + "), before the vertex and face counts");
    if (variant.dimensional) {
      if (count(t[0], "dimension") != 3)
        fail(path_, "unsupported OFF variant", "line " + std::to_string(line_) + ": dimension " + shorten(t[0]) + ", only 3 is read");
      t.erase(t.begin());
      if (t.empty() && !next(t))
        fail(path_, "truncated file", "the file ends before the vertex and face counts");
    }
    if (t.size() < 2)
      fail(path_, "parse error", "line " + std::to_string(line_) + ": expected the vertex, face and edge counts");
    const std::size_t counts_line = line_;
    const std::size_t nv = count(t[0], "vertex count");
    const std::size_t nf = count(t[1], "face count");
    if (nv == 0 || nf == 0)
      fail(path_, "empty mesh", "line " + std::to_string(counts_line) + " announces " + counted(nv, "vertex", "vertices") + " and " + counted(nf, "face", "faces"));
    // The edge count is not used, but CGAL 5.5's OFF header reader doubles it in an int
    // (File_header_OFF_impl.h:404): beyond INT_MAX / 2 a signed overflow, undefined behaviour that
    // UBSan reports (scripts/sanitize.sh); beyond INT_MAX its read fails. Refused here, with a reason.
    if (t.size() >= 3) {
      errno = 0;
      char* end = nullptr;
      const long long ne = std::strtoll(t[2].data(), &end, 10);
      if (end != t[2].data() && (errno == ERANGE || ne > INT_MAX / 2 || ne < INT_MIN / 2))
        fail(path_, "parse error", "line " + std::to_string(counts_line) + ": edge count " + shorten(t[2]) + " is out of range (at most " + std::to_string(INT_MAX / 2) + ")");
    }

    const std::string announced = "the header (line " + std::to_string(counts_line) + ") announces " + counted(nv, "vertex", "vertices") + " and " + counted(nf, "face", "faces");
    OffScan scan;
    SourceLines& out = scan.lines;
    // Never reserve a declared count as such: a vertex line has at least 6 bytes.
    out.vertex_line.reserve(std::min(nv, text_.size() / 6 + 1));
    scan.points.reserve(std::min(nv, text_.size() / 6 + 1));
    for (std::size_t i = 0; i < nv; ++i) {
      if (!next(t))
        fail(path_, "truncated file", announced + ", but the file ends after " + counted(i, "vertex", "vertices") + " (line " + std::to_string(line_) + ")");
      // Built only for a message (see next()): most files never need one.
      auto where = [&] { return "vertex " + std::to_string(i) + " (line " + std::to_string(line_) + ")"; };
      if (t.size() < variant.vertex_numbers) {
        if (at_end()) fail(path_, "truncated file", announced + ", but the file ends inside " + where());
        fail(path_, "parse error", where() + " has " + std::to_string(t.size()) + " numbers, expected " + std::to_string(variant.vertex_numbers));
      }
      double c4[4] = {0.0, 0.0, 0.0, 1.0};
      for (std::size_t k = 0; k < variant.vertex_numbers; ++k) {
        double c = 0.0;
        // Hexadecimal floats are strtod's (parse_c_number reads them): CGAL's reader (a stream)
        // refuses them, so do we.
        if (!parse_c_number(t[k], c) || t[k].find_first_of("xX") != std::string_view::npos)
          fail(path_, "parse error", where() + ": '" + shorten(t[k]) + "' is not a number");
        if (k < 3 && !std::isfinite(c))
          fail(path_, "non-finite coordinate", where() + " has coordinate " + "xyz"[k] + " = " + std::string(t[k]));
        if (k == 3 && variant.homogeneous && !(std::isfinite(c) && c != 0.0))
          fail(path_, "non-finite coordinate", where() + " has the homogeneous coordinate w = " + std::string(t[k]));
        if (k < 3 || (k == 3 && variant.homogeneous)) c4[k] = c;
      }
      // As CGAL's fill_point: x / w (exact for w = 1).
      scan.points.push_back({c4[0] / c4[3], c4[1] / c4[3], c4[2] / c4[3]});
      out.vertex_line.push_back(line_);
    }
    out.face_line.reserve(std::min(nf, text_.size() / 8 + 1));
    scan.faces.reserve(std::min(nf, text_.size() / 8 + 1));
    for (std::size_t j = 0; j < nf; ++j) {
      if (!next(t))
        fail(path_, "truncated file", announced + ", but the file ends after " + counted(j, "face", "faces") + " (line " + std::to_string(line_) + ")");
      auto where = [&] { return "face " + std::to_string(j) + " (line " + std::to_string(line_) + ")"; };
      const std::size_t n = index(t[0], [&] { return where() + ": vertex count"; });
      if (t.size() - 1 < n) {
        if (at_end()) fail(path_, "truncated file", announced + ", but the file ends inside " + where());
        fail(path_, "parse error", where() + " announces " + counted(n, "vertex", "vertices") + " but lists " + std::to_string(t.size() - 1));
      }
      std::vector<std::size_t> face(n);
      for (std::size_t k = 1; k <= n; ++k) {
        const std::size_t v = index(t[k], where, j);
        if (v >= nv && missing_ == MissingVertices::Refuse)
          fail_face(path_, "vertex index out of range",
                    where() + " refers to vertex " + std::to_string(v) + ", but the file has " +
                        counted(nv, "vertex", "vertices") + " (0.." + std::to_string(nv - 1) + ")",
                    j);
        face[k - 1] = v;
      }
      scan.faces.push_back(std::move(face));
      out.face_line.push_back(line_);
    }
    // Lines after the declared faces are not read: more faces than the header says, or another
    // file appended. Said, so that a mesh that then fails its checks (an open boundary where the
    // dropped faces were) is not a riddle.
    if (next(t)) {
      const std::size_t first = line_;
      std::size_t more = 1;
      while (next(t)) ++more;
      scan.ignored_tail = path_ + ": line " + std::to_string(first) + ": " + counted(more, "line", "lines") +
                          " after the " + counted(nf, "declared face", "declared faces") +
                          " not read (the header's counts decide what is read)";
    }
    return scan;
  }

 private:
  /// Next non-blank, non-comment line (text before a '#') split at blanks into views of text_;
  /// false at end of file. Views rather than strings, and no stream: a string stream per line and
  /// a string per token were most of the scan's cost on bear x16 (lab/pages/scale.md).
  bool next(std::vector<std::string_view>& tokens) {
    const std::string_view text(text_);
    while (pos_ < text.size()) {
      ++line_;
      std::size_t eol = text.find('\n', pos_);
      if (eol == std::string_view::npos) eol = text.size();
      std::string_view s = text.substr(pos_, eol - pos_);
      pos_ = eol + 1;
      const auto hash = s.find('#');
      if (hash != std::string_view::npos) s = s.substr(0, hash);
      tokens.clear();
      for (std::size_t i = 0; i < s.size();) {
        while (i < s.size() && blank(s[i])) ++i;
        const std::size_t start = i;
        while (i < s.size() && !blank(s[i])) ++i;
        if (i > start) tokens.push_back(s.substr(start, i - start));
      }
      if (!tokens.empty()) return true;
    }
    return false;
  }
  /// isspace of the "C" locale, inline (a library call per byte showed in the profile of
  /// reading a large mesh: lab/regions/speed.md), and the same whatever locale a host program
  /// (Python) has set.
  static bool blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }
  bool at_end() const {
    for (std::size_t i = pos_; i < text_.size(); ++i)
      if (!blank(text_[i])) return false;
    return true;
  }
  /// strtoll reads the token in place (see the vertex loop); `where` names it, for messages only.
  /// Reads what strtoll would accept as the whole token (an optional sign, decimal digits, no
  /// overflow), without its per-call locale and errno work (millions of face indices). A
  /// negative corner index (of face `corner_of`) is SIZE_MAX under MissingVertices::Keep.
  template <class Where>
  std::size_t index(std::string_view tok, const Where& where,
                    std::size_t corner_of = NOT_A_CORNER) {
    const char* p = tok.data();
    const char* const e = p + tok.size();
    const bool negative = p != e && *p == '-';
    if (p != e && (*p == '+' || *p == '-')) ++p;
    bool ok = p != e;
    unsigned long long v = 0;
    // The magnitude of LLONG_MIN is one more than LLONG_MAX.
    const unsigned long long limit = static_cast<unsigned long long>(LLONG_MAX) + (negative ? 1 : 0);
    for (; ok && p != e; ++p) {
      const unsigned d = static_cast<unsigned>(static_cast<unsigned char>(*p)) - '0';
      ok = d < 10 && v <= (limit - d) / 10;
      v = v * 10 + d;
    }
    if (!ok) fail(path_, "parse error", where() + ": '" + shorten(tok) + "' is not an integer");
    if (negative && v != 0) {
      if (corner_of == NOT_A_CORNER)
        fail(path_, "vertex index out of range",
             where() + " has the negative index " + std::string(tok));
      if (missing_ == MissingVertices::Keep) return SIZE_MAX;
      fail_face(path_, "vertex index out of range",
                where() + " has the negative index " + std::string(tok), corner_of);
    }
    return static_cast<std::size_t>(v);
  }
  /// A count CGAL reads as a 32-bit int: larger ones are refused here, never misread there.
  std::size_t count(std::string_view tok, const std::string& what) {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(tok.data(), &end, 10);
    if (end != tok.data() + tok.size() || errno == ERANGE || v < 0)
      fail(path_, "parse error", "line " + std::to_string(line_) + ": " + what + " '" + shorten(tok) + "' is not a non-negative integer");
    return static_cast<std::size_t>(v);
  }

  /// "OFF BINARY" as CGAL writes it: after the header line, big-endian int32 counts (vertices,
  /// faces, edges), float32 x y z per vertex, then per face an int32 corner count, the int32
  /// indices, an int32 colour count (0 to 4) and that many float32.
  OffScan scan_binary() {
    OffScan out;
    const std::size_t nl = text_.find('\n');
    std::size_t pos = nl == std::string::npos ? text_.size() : nl + 1;
    auto int32 = [&](const std::string& what) {
      if (text_.size() - pos < 4) fail(path_, "truncated file", "binary OFF: the file ends inside " + what + " (byte offset " + std::to_string(pos) + ")");
      std::uint32_t u = 0;
      for (int i = 0; i < 4; ++i) u = (u << 8) | static_cast<unsigned char>(text_[pos + static_cast<std::size_t>(i)]);
      pos += 4;
      return static_cast<std::int32_t>(u);
    };
    const std::int32_t nv = int32("the vertex count"), nf = int32("the face count");
    int32("the edge count");
    if (nv <= 0 || nf <= 0)
      fail(path_, "empty mesh", "binary OFF: the header announces " + std::to_string(nv) + " " +
                                     // A negative count is refused too; it reads as a plural.
                                     one_or_many(static_cast<std::size_t>(nv), "vertex", "vertices") + " and " +
                                     std::to_string(nf) + " " + one_or_many(static_cast<std::size_t>(nf), "face", "faces"));
    const std::size_t vertex_bytes = 12 * static_cast<std::size_t>(nv);
    if (text_.size() - pos < vertex_bytes || (text_.size() - pos - vertex_bytes) / 8 < static_cast<std::size_t>(nf))
      fail(path_, "truncated file", "binary OFF: the header announces " + counted(static_cast<std::size_t>(nv), "vertex", "vertices") + " (12 bytes each) and " + counted(static_cast<std::size_t>(nf), "face", "faces") + " (8 bytes at least), but only " + std::to_string(text_.size() - pos) + " bytes follow");
    out.points.reserve(static_cast<std::size_t>(nv));
    for (std::int32_t i = 0; i < nv; ++i) {
      std::array<double, 3> p{};
      for (double& c : p) {
        const auto bits = static_cast<std::uint32_t>(int32("a coordinate"));
        float f = 0.0f;
        std::memcpy(&f, &bits, 4);
        c = f;
      }
      out.points.push_back(p);
    }
    out.faces.reserve(static_cast<std::size_t>(nf));
    for (std::int32_t f = 0; f < nf; ++f) {
      const std::string where = "face " + std::to_string(f);
      const std::int32_t n = int32(where + "'s corner count");
      if (n < 0 || static_cast<std::size_t>(n) > (text_.size() - pos) / 4)
        fail(path_, "parse error", "binary OFF: " + where + " announces " + counted(static_cast<std::size_t>(n), "corner", "corners") + " (byte offset " + std::to_string(pos - 4) + ")");
      std::vector<std::size_t> face;
      face.reserve(static_cast<std::size_t>(n));
      for (std::int32_t k = 0; k < n; ++k) {
        const std::int32_t v = int32(where);
        face.push_back(v < 0 ? SIZE_MAX : static_cast<std::size_t>(v));
        if ((v < 0 || v >= nv) && missing_ == MissingVertices::Refuse)
          fail_face(path_, "vertex index out of range",
                    "binary OFF: " + where + " refers to vertex " + std::to_string(v) +
                        ", but the file has " +
                        counted(static_cast<std::size_t>(nv), "vertex", "vertices"),
                    static_cast<std::size_t>(f));
      }
      const std::int32_t colours = int32(where + "'s colour count");
      if (colours < 0 || colours > 4 || text_.size() - pos < 4 * static_cast<std::size_t>(colours))
        fail(path_, "parse error", "binary OFF: " + where + " has a bad colour count " + std::to_string(colours));
      pos += 4 * static_cast<std::size_t>(colours);
      out.faces.push_back(std::move(face));
    }
    return out;
  }

  const std::string& path_;
  const std::string& text_;
  const MissingVertices missing_;
  std::size_t pos_ = 0;  ///< start of the next line in text_
  std::size_t line_ = 0;
};

}  // namespace

OffScan scan_off(const std::string& path, const std::string& text, MissingVertices missing) {
  return OffScanner(path, text, missing).scan();
}

}  // namespace shellcontract
