// PLY reader (Greg Turk's format as documented by Paul Bourke's "PLY - Polygon File Format"):
// a header of lines, then the elements in header order, ascii or binary. Ours rather than
// CGAL 5.5's because that one segfaults on a `property` line before any `element` line, on
// integer-typed coordinates, and trusts declared counts (README, Limitations).
//
// The header is parsed and checked first; then every declared count is bounded by the bytes that
// follow the header (each element instance needs a known minimum of bytes), and only then is
// memory reserved. Every failure is an InputError naming the file, the problem and the header
// line, body line (ascii) or byte offset (binary). The header's parse and checks alone are
// read_ply_header (ply_header.hpp), which the PLY document (ply_document.cpp) uses.
#include "mesh/ply_reader.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <limits>
#include <locale>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/decimal_text.hpp"
#include "core/token_text.hpp"
#include "mesh/ply_header.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {
namespace {

using ply::Element;
using ply::Format;
using ply::is_integer;
using ply::Property;
using ply::size_of;
using ply::Type;

struct TypeName {
  const char* name;
  Type type;
};

constexpr TypeName TYPES[] = {
    {"char", Type::Int8},     {"int8", Type::Int8},       {"uchar", Type::UInt8},  {"uint8", Type::UInt8},
    {"short", Type::Int16},   {"int16", Type::Int16},     {"ushort", Type::UInt16}, {"uint16", Type::UInt16},
    {"int", Type::Int32},     {"int32", Type::Int32},     {"uint", Type::UInt32},  {"uint32", Type::UInt32},
    {"float", Type::Float32}, {"float32", Type::Float32}, {"double", Type::Float64}, {"float64", Type::Float64}};

/// The type's name as the PLY specification spells it (for messages).
const char* type_name(Type t) {
  for (const TypeName& n : TYPES)
    if (n.type == t) return n.name;
  return "?";
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

class PlyParser {
 public:
  PlyParser(const std::string& path, const std::string& bytes) : path_(path), bytes_(bytes) {}

  /// The checked header and where the body starts (read_ply_header).
  ply::Header header() {
    parse_header();
    check_empty_counts();
    return ply::Header{format_, elements_, pos_, body_line_, comments_};
  }

  PlyData parse() {
    parse_header();
    check_counts_fit();
    PlyData out;
    bool vertices_seen = false, faces_seen = false;
    for (const Element& e : elements_) {
      const bool is_vertex = e.name == "vertex" && !vertices_seen;
      const bool is_face = e.name == "face" && !faces_seen;
      vertices_seen |= is_vertex;
      faces_seen |= is_face;
      read_element(e, is_vertex, is_face, out);
    }
    check_empty_counts();
    return out;
  }

 private:
  [[noreturn]] void fail(const std::string& problem, const std::string& details) const {
    throw InputError(path_ + ": " + problem + ": " + details);
  }
  std::string at_line(std::size_t line) const { return "line " + std::to_string(line); }

  // ---------------------------------------------------------------- header

  /// Next header line (ends at "\n", "\r\n" or a lone "\r"); false at the end of the bytes.
  bool header_line(std::string& line) {
    if (pos_ >= bytes_.size()) return false;
    const std::size_t end = bytes_.find_first_of("\r\n", pos_);
    if (end == std::string::npos) {
      line = bytes_.substr(pos_);
      pos_ = bytes_.size();
    } else {
      line = bytes_.substr(pos_, end - pos_);
      pos_ = end + 1;
      if (bytes_[end] == '\r' && pos_ < bytes_.size() && bytes_[pos_] == '\n') ++pos_;
    }
    ++line_;
    return true;
  }

  static std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> t;
    std::size_t i = 0;
    while (i < s.size()) {
      while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
      const std::size_t b = i;
      while (i < s.size() && s[i] != ' ' && s[i] != '\t') ++i;
      if (i > b) t.push_back(s.substr(b, i - b));
    }
    return t;
  }

  Type type_of(const std::string& name) const {
    for (const TypeName& n : TYPES)
      if (name == n.name) return n.type;
    fail("parse error", at_line(line_) + ": unknown property type '" + shorten(name) + "'");
  }

  std::uint64_t element_count(const std::string& tok) const {
    std::uint64_t v = 0;
    bool ok = !tok.empty() && tok.size() <= 20;
    for (char c : tok) {
      if (c < '0' || c > '9' || v > (std::numeric_limits<std::uint64_t>::max() - 9) / 10) ok = false;
      if (!ok) break;
      v = 10 * v + static_cast<std::uint64_t>(c - '0');
    }
    if (!ok) fail("parse error", at_line(line_) + ": element count '" + shorten(tok) + "' is not a non-negative integer");
    return v;
  }

  void parse_header() {
    // A UTF-8 byte-order mark is not part of the format, but harmless to skip.
    if (bytes_.compare(0, 3, "\xEF\xBB\xBF") == 0) pos_ = 3;
    std::string line;
    std::size_t line_start = pos_;  ///< byte offset of `line` in bytes_
    if (!header_line(line) || split(line) != std::vector<std::string>{"ply"})
      fail("parse error", "line 1: not a PLY file (the first line must be 'ply')");
    bool format_seen = false;
    while (true) {
      line_start = pos_;
      if (!header_line(line)) fail("truncated file", "the header has no 'end_header' line (the file ends at line " + std::to_string(line_) + ")");
      const std::vector<std::string> t = split(line);
      if (!t.empty() && t[0] == "comment")
        comments_.push_back({line_, line.substr(line.find("comment") + 7)});
      if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
      if (t[0] == "end_header") break;
      if (t[0] == "format") {
        if (format_seen) fail("parse error", at_line(line_) + ": a second 'format' line");
        if (t.size() != 3) fail("parse error", at_line(line_) + ": expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
        if (t[1] == "ascii") format_ = Format::Ascii;
        else if (t[1] == "binary_little_endian") format_ = Format::BinaryLittleEndian;
        else if (t[1] == "binary_big_endian") format_ = Format::BinaryBigEndian;
        else fail("parse error", at_line(line_) + ": unknown format '" + shorten(t[1]) + "'");
        format_seen = true;
      } else if (t[0] == "element") {
        if (t.size() != 3) fail("parse error", at_line(line_) + ": expected 'element <name> <count>'");
        elements_.push_back(Element{t[1], element_count(t[2]), line_, {}});
      } else if (t[0] == "property") {
        if (elements_.empty()) fail("parse error", at_line(line_) + ": a 'property' line before any 'element' line");
        Property p;
        if (t.size() == 5 && t[1] == "list") {
          p.list = true;
          p.count_type = type_of(t[2]);
          p.type = type_of(t[3]);
          p.name = t[4];
          if (!is_integer(p.count_type)) fail("parse error", at_line(line_) + ": the count type of list '" + shorten(p.name) + "' is not an integer type");
        } else if (t.size() == 3 && t[1] != "list") {
          p.type = type_of(t[1]);
          p.name = t[2];
          // The type is the first token after "property" (split's separators: blanks, tabs).
          const std::size_t keyword = line.find("property");
          p.type_begin = line_start + line.find(t[1], keyword + 8);
          p.type_end = p.type_begin + t[1].size();
        } else {
          fail("parse error", at_line(line_) + ": expected 'property <type> <name>' or 'property list <count type> <type> <name>'");
        }
        elements_.back().properties.push_back(p);
      } else {
        fail("parse error", at_line(line_) + ": unknown header keyword '" + shorten(t[0]) + "'");
      }
    }
    if (!format_seen) fail("parse error", "the header has no 'format' line");
    body_line_ = line_ + 1;
  }

  /// An element without properties takes no bytes, so check_counts_fit cannot bound its count,
  /// and a loop over its instances (the PLY document's) would run for as long as the count says.
  /// No file declares more instances than it has bytes: refused by read_ply (after the elements
  /// it refuses for lacking properties, with their own message) and read_ply_header alike.
  void check_empty_counts() const {
    for (const Element& e : elements_)
      if (e.properties.empty() && e.count > bytes_.size())
        fail("implausible count",
             "element '" + shorten(e.name) + "' (" + at_line(e.line) +
                 ") has no properties but declares " + std::to_string(e.count) +
                 " instances, more than the file's " + std::to_string(bytes_.size()) + " bytes");
  }

  /// Every element instance needs some bytes (binary: its scalars and list counts; ascii: one
  /// character and one separator per property); a declared count that does not fit in what
  /// follows the header is a truncated file, refused before anything is allocated for it.
  void check_counts_fit() const {
    const std::uint64_t remaining = bytes_.size() - pos_;
    std::uint64_t total = 0;
    for (const Element& e : elements_) {
      std::uint64_t min_bytes = 0;
      for (const Property& p : e.properties)
        min_bytes += format_ == Format::Ascii ? 2 : static_cast<std::uint64_t>(size_of(p.list ? p.count_type : p.type));
      if (min_bytes == 0 || e.count == 0) continue;
      // The last separator of an ascii file may be missing: hence the + 1.
      if (e.count > (remaining + 1) / min_bytes || total + e.count * min_bytes > remaining + 1)
        fail("truncated file", "the header declares " + std::to_string(e.count) + " '" + shorten(e.name) + "' elements (" +
                                   at_line(e.line) + ") of at least " + std::to_string(min_bytes) + " bytes each, but only " +
                                   std::to_string(remaining) + " bytes follow the header");
      total += e.count * min_bytes;
    }
  }

  // ---------------------------------------------------------------- body

  /// Where the reader is, for messages.
  std::string where() const {
    return format_ == Format::Ascii ? at_line(body_line_) : "byte offset " + std::to_string(pos_);
  }

  /// Skips ascii separators, counting lines ("\n", "\r\n" and a lone "\r" each end one).
  void skip_space() {
    for (; pos_ < bytes_.size(); ++pos_) {
      const char c = bytes_[pos_];
      if (!is_space(c)) break;
      if (c == '\n' || (c == '\r' && (pos_ + 1 >= bytes_.size() || bytes_[pos_ + 1] != '\n'))) ++body_line_;
    }
  }

  /// Skips blanks up to the end of the current ascii line; whether a value follows on it.
  bool more_on_line() {
    while (pos_ < bytes_.size() && is_space(bytes_[pos_]) && bytes_[pos_] != '\n' &&
           bytes_[pos_] != '\r')
      ++pos_;
    return pos_ < bytes_.size() && bytes_[pos_] != '\n' && bytes_[pos_] != '\r';
  }

  /// Values from pos_ to the end of the current ascii line (pos_ does not move).
  std::size_t values_left_on_line() const {
    std::size_t n = 0;
    for (std::size_t i = pos_; i < bytes_.size() && bytes_[i] != '\n' && bytes_[i] != '\r';) {
      if (is_space(bytes_[i])) {
        ++i;
        continue;
      }
      ++n;
      while (i < bytes_.size() && !is_space(bytes_[i])) ++i;
    }
    return n;
  }

  /// Next ascii token, a view of bytes_; false at the end of the bytes.
  bool token(std::string_view& tok) {
    // Inside an element instance, its values must all be on its line (line_check_).
    if (line_check_.on && line_check_.values > 0 && !more_on_line()) {
      skip_space();
      if (pos_ < bytes_.size()) wrong_value_count(line_check_.values);
      // Nothing follows at all: a truncated file, said by the caller.
    }
    skip_space();
    if (pos_ >= bytes_.size()) return false;
    const std::size_t b = pos_;
    while (pos_ < bytes_.size() && !is_space(bytes_[pos_])) ++pos_;
    tok = std::string_view(bytes_).substr(b, pos_ - b);
    ++line_check_.values;
    return true;
  }

  /// An ascii element instance is one line (the format's own layout; every writer keeps it). A
  /// value too many or too few was read as a stream of tokens before: the values after it
  /// shifted into the next properties and elements, and the message named some later face
  /// ("face 0 (line 51) has 0 vertices" for an extra value on line 10).
  struct LineCheck {
    bool on = false;
    const Element* element = nullptr;
    std::size_t index = 0, line = 0;
    std::size_t values = 0;      ///< read so far on the instance's line
    std::size_t expected = 0;    ///< one per property, plus the items of the lists read so far
    std::size_t lists_left = 0;  ///< lists whose length is not read yet
  };

  [[noreturn]] void wrong_value_count(std::size_t found) const {
    const LineCheck& c = line_check_;
    std::size_t lists = 0;
    for (const Property& p : c.element->properties) lists += p.list ? 1 : 0;
    const std::string expected =
        lists == 0
            ? "its header declares " + std::to_string(c.expected) +
                  (c.expected == 1 ? " property" : " properties")
            : "its header's properties take " + std::string(c.lists_left > 0 ? "at least " : "") +
                  std::to_string(c.expected) + " (a list: its length, then its items)";
    fail("parse error", "'" + shorten(c.element->name) + "' element " + std::to_string(c.index) +
                            " (" + at_line(c.line) + ") has " + std::to_string(found) +
                            (found == 1 ? " value" : " values") + ", but " + expected);
  }

  /// One scalar as a double (integers of every PLY type are exact in a double). `what()` names
  /// it, built only for a message: a string per value was the same waste as in the OFF scan
  /// (lab/pages/scale.md). An ascii value of an integer type must be an integer that the type
  /// holds, as a binary file's value is by construction: '0.5' for an `int x` was read as 0.5,
  /// and the PLY document then wrote the result back as integers (a flattened mesh). `whole`
  /// checks its own values (its message says what a count or an index must be).
  template <class What>
  double scalar(Type t, const What& what, bool check_integer = true) {
    if (format_ == Format::Ascii) {
      std::string_view tok;
      if (!token(tok)) fail("truncated file", "the file ends before " + what() + " (" + where() + ")");
      // strtod's forms in the "C" locale (core/decimal_text.hpp), whatever locale a host set.
      double v = 0.0;
      if (!parse_c_number(tok, v))
        fail("parse error", where() + ": '" + shorten(std::string(tok)) + "' is not a number (" + what() + ")");
      if (check_integer && is_integer(t)) {
        const int bits = 8 * size_of(t);
        const double lo = ply::is_signed(t) ? -std::ldexp(1.0, bits - 1) : 0.0;
        const double hi = std::ldexp(1.0, ply::is_signed(t) ? bits - 1 : bits) - 1.0;
        if (!(v >= lo && v <= hi) || v != std::floor(v)) {
          std::ostringstream range;
          range.imbue(std::locale::classic());  // core/classic_locale.hpp
          range << std::fixed << std::setprecision(0) << lo << " to " << hi;
          fail("parse error", where() + ": " + what() + " is '" + shorten(std::string(tok)) +
                                  "', not an integer from " + range.str() +
                                  " (the header declares it " + type_name(t) + ")");
        }
      }
      return v;
    }
    const int n = size_of(t);
    if (bytes_.size() - pos_ < static_cast<std::size_t>(n))
      fail("truncated file", "the file ends inside " + what() + " (" + where() + ")");
    std::uint64_t u = 0;
    for (int i = 0; i < n; ++i) {
      const int shift = 8 * (format_ == Format::BinaryBigEndian ? n - 1 - i : i);
      u |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes_[pos_ + static_cast<std::size_t>(i)])) << shift;
    }
    pos_ += static_cast<std::size_t>(n);
    switch (t) {
      case Type::Int8: return static_cast<std::int8_t>(u);
      case Type::UInt8: return static_cast<std::uint8_t>(u);
      case Type::Int16: return static_cast<std::int16_t>(u);
      case Type::UInt16: return static_cast<std::uint16_t>(u);
      case Type::Int32: return static_cast<std::int32_t>(u);
      case Type::UInt32: return static_cast<std::uint32_t>(u);
      case Type::Float32: {
        const auto bits = static_cast<std::uint32_t>(u);
        float f = 0.0f;
        std::memcpy(&f, &bits, 4);
        return f;
      }
      case Type::Float64: {
        double d = 0.0;
        std::memcpy(&d, &u, 8);
        return d;
      }
    }
    return 0.0;
  }

  /// A list count or an index: a non-negative integer below 2^53 (exact in a double).
  template <class What>
  std::size_t whole(Type t, const What& what) {
    const double v = scalar(t, what, false);
    if (!(v >= 0.0 && v < 9.0e15) || v != std::floor(v)) {
      std::ostringstream s;
      s.imbue(std::locale::classic());  // core/classic_locale.hpp
      s << std::setprecision(17) << v;
      fail("parse error", where() + ": " + what() + " is " + s.str() + ", not a non-negative integer");
    }
    return static_cast<std::size_t>(v);
  }

  void read_element(const Element& e, bool is_vertex, bool is_face, PlyData& out) {
    int ix = -1, iy = -1, iz = -1, inx = -1, iny = -1, inz = -1, iidx = -1;
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      const Property& p = e.properties[k];
      const int kk = static_cast<int>(k);
      if (is_vertex && !p.list) {
        int* slot = p.name == "x" ? &ix : p.name == "y" ? &iy : p.name == "z" ? &iz : p.name == "nx" ? &inx
                  : p.name == "ny" ? &iny : p.name == "nz" ? &inz : nullptr;
        if (slot && *slot < 0) *slot = kk;
      }
      if (is_face && p.list && (p.name == "vertex_indices" || p.name == "vertex_index") && iidx < 0) iidx = kk;
    }
    if (is_vertex && (ix < 0 || iy < 0 || iz < 0))
      fail("parse error", "element 'vertex' (" + at_line(e.line) + ", " + std::to_string(e.count) +
                              " declared) lacks one of the properties x, y, z");
    if (is_face && iidx < 0)
      fail("parse error", "element 'face' (" + at_line(e.line) + ") has no list property 'vertex_indices' or 'vertex_index'");
    if (is_face && !is_integer(e.properties[static_cast<std::size_t>(iidx)].type))
      fail("parse error", "element 'face' (" + at_line(e.line) + "): the vertex indices have a floating-point type");
    if (e.properties.empty()) return;  // nothing to read, whatever the count
    const bool normals = is_vertex && inx >= 0 && iny >= 0 && inz >= 0;
    // check_counts_fit bounded e.count by the file size, so these reservations are too.
    const auto n = static_cast<std::size_t>(e.count);
    if (is_vertex) out.points.reserve(n);
    if (normals) out.normals.reserve(n);
    if (is_face) out.faces.reserve(n);
    const bool ascii = format_ == Format::Ascii;
    std::size_t lists = 0;
    for (const Property& p : e.properties) lists += p.list ? 1 : 0;
    for (std::size_t i = 0; i < n; ++i) {
      auto instance = [&] { return "'" + shorten(e.name) + "' element " + std::to_string(i); };
      std::array<double, 6> v{};
      std::vector<std::size_t> face;
      if (ascii) {
        skip_space();  // so that the line is the one of the element's first value
        if (is_vertex || is_face)
          (is_vertex ? out.vertex_line : out.face_line).push_back(body_line_);
        line_check_ = LineCheck{true, &e, i, body_line_, 0, e.properties.size(), lists};
      }
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        auto what = [&] { return "property '" + shorten(p.name) + "' of " + instance(); };
        if (!p.list) {
          const double x = scalar(p.type, what);
          const int kk = static_cast<int>(k);
          if (kk == ix) v[0] = x;
          else if (kk == iy) v[1] = x;
          else if (kk == iz) v[2] = x;
          else if (kk == inx) v[3] = x;
          else if (kk == iny) v[4] = x;
          else if (kk == inz) v[5] = x;
          continue;
        }
        const std::size_t count = whole(p.count_type, [&] { return "the list length of " + what(); });
        if (ascii) {
          line_check_.expected += count;
          --line_check_.lists_left;
        }
        // Bound the list by the bytes left before reserving (ascii: 2 bytes an item at least).
        const std::size_t item_bytes = ascii ? 2 : static_cast<std::size_t>(size_of(p.type));
        if (count > (bytes_.size() - pos_ + 1) / item_bytes)
          fail("truncated file", what() + " announces " + std::to_string(count) + " items, more than the " +
                                     std::to_string(bytes_.size() - pos_) + " bytes left can hold (" + where() + ")");
        const bool indices = is_face && static_cast<int>(k) == iidx;
        if (indices) face.reserve(count);
        for (std::size_t j = 0; j < count; ++j) {
          if (indices) face.push_back(whole(p.type, [&] { return "vertex index " + std::to_string(j) + " of face " + std::to_string(i); }));
          else scalar(p.type, what);
        }
      }
      if (ascii && more_on_line()) wrong_value_count(line_check_.values + values_left_on_line());
      line_check_.on = false;
      if (is_vertex) out.points.push_back({v[0], v[1], v[2]});
      if (normals) out.normals.push_back({v[3], v[4], v[5]});
      if (is_face) out.faces.push_back(std::move(face));
    }
  }

  const std::string& path_;
  const std::string& bytes_;
  std::size_t pos_ = 0;        ///< next byte
  std::size_t line_ = 0;       ///< header line just read
  std::size_t body_line_ = 0;  ///< ascii body: current line
  Format format_ = Format::Ascii;
  std::vector<Element> elements_;
  std::vector<ply::Comment> comments_;
  LineCheck line_check_;  ///< ascii: the element instance being read
};

}  // namespace

namespace ply {

Header read_ply_header(const std::string& path, const std::string& bytes) { return PlyParser(path, bytes).header(); }

}  // namespace ply

PlyData read_ply(const std::string& path, const std::string& bytes) { return PlyParser(path, bytes).parse(); }

}  // namespace shellcontract
