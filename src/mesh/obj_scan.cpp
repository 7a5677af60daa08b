// The OBJ reader (see obj_scan.hpp): line by line, as the OFF scan, so that every error names its
// line and every vertex and face keeps its line for the checks' messages.
#include "mesh/obj_scan.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <string_view>

#include "core/decimal_text.hpp"
#include "core/plural.hpp"
#include "core/token_text.hpp"
#include "mesh/line_tokens.hpp"
#include "mesh/scan_errors.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/face_error.hpp"

namespace shellcontract {
namespace {

using scan_errors::fail;
using scan_errors::fail_face;

/// isspace of the "C" locale, whatever locale a host program (Python) has set.
bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/// The statements CGAL::IO::read_OBJ skips (CGAL/IO/OBJ.h): reading more or fewer files than it
/// did would change which inputs are usable. Comments (a first token starting with '#') too.
/// One more than CGAL: `l`, a polyline, which CGAL refuses; Blender's OBJ exporters write one for a
/// loose edge left in a closed mesh, and like a `p` point it holds no face, so the surface is the
/// same without it (the file was refused as a parse error, and `repair` could not read it either).
bool skipped_statement(std::string_view k) {
  static constexpr std::string_view skipped[] = {
      "vt", "vn", "vp", "bevel", "lod", "ctech", "c_interp", "usemap", "usemtl", "stech", "d_interp",
      "mtllib", "shadow_obj", "trace_obj", "o", "g", "s", "p", "cstype", "deg", "step", "bmat", "con",
      "curv", "curv2", "surf", "parm", "trim", "hole", "scrv", "sp", "end", "surf_1", "q0_1", "q1_1",
      "curv2d_1", "surf_2", "q0_2", "q1_2", "curv2d_2", "bsp", "bzp", "cdc", "cdp", "res"};
  return k.front() == '#' || k == "l" ||
         std::find(std::begin(skipped), std::end(skipped), k) != std::end(skipped);
}

/// A corner's vertex index as written ("3", "-1", "+2"): false unless the whole of `tok` is one
/// that fits a long long.
bool parse_index(std::string_view tok, long long& value) {
  const char* p = tok.data();
  const char* const e = p + tok.size();
  const bool negative = p != e && *p == '-';
  if (p != e && (*p == '+' || *p == '-')) ++p;
  if (p == e) return false;
  unsigned long long v = 0;
  const unsigned long long limit = static_cast<unsigned long long>(LLONG_MAX);
  for (; p != e; ++p) {
    const unsigned d = static_cast<unsigned>(static_cast<unsigned char>(*p)) - '0';
    if (d >= 10 || v > (limit - d) / 10) return false;
    v = v * 10 + d;
  }
  value = negative ? -static_cast<long long>(v) : static_cast<long long>(v);
  return true;
}

}  // namespace

ObjScan scan_obj(const std::string& path, const std::string& text_in, MissingVertices missing) {
  // Continued lines joined (line_tokens.hpp): a statement is one line of `text`, and names the
  // line it starts on. Only a file with a backslash needs the copy.
  std::string joined;
  const bool continued = text_in.find('\\') != std::string::npos;
  if (continued) {
    joined = text_in;
    const std::size_t dangling = join_continued_lines(joined, '\n');
    if (dangling != std::string::npos)
      fail(path, "parse error",
           "line " + std::to_string(line_of(text_in, dangling, '\n')) +
               ": a line continuation ('\\') with no line after it");
  }
  const std::string_view text(continued ? joined : text_in);
  ObjScan scan;
  std::vector<std::string_view> t;
  std::size_t line = 0, next_line = 1;
  for (std::size_t pos = 0; pos < text.size();) {
    line = next_line;
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    const std::string_view s = text.substr(pos, eol - pos);
    next_line = line + 1;
    if (continued)  // the line ends it joined
      next_line += static_cast<std::size_t>(
          std::count(text_in.begin() + static_cast<std::ptrdiff_t>(pos),
                     text_in.begin() + static_cast<std::ptrdiff_t>(eol), '\n'));
    pos = eol + 1;
    t.clear();
    for (std::size_t i = 0; i < s.size();) {
      while (i < s.size() && blank(s[i])) ++i;
      const std::size_t start = i;
      while (i < s.size() && !blank(s[i])) ++i;
      if (i > start) t.push_back(s.substr(start, i - start));
    }
    if (t.empty()) continue;
    if (t[0] == "v") {
      const std::size_t i = scan.points.size();
      auto where = [&] { return "vertex " + std::to_string(i) + " (line " + std::to_string(line) + ")"; };
      if (t.size() < 4)
        fail(path, "parse error", where() + " has " + std::to_string(t.size() - 1) + " numbers, expected 3 (x y z)");
      std::array<double, 3> p{};
      for (std::size_t k = 0; k < 3; ++k) {
        // Hexadecimal floats are strtod's (parse_c_number reads them): CGAL's reader (a stream)
        // refuses them, so do we.
        if (!parse_c_number(t[k + 1], p[k]) ||
            t[k + 1].find_first_of("xX") != std::string_view::npos)
          fail(path, "parse error", where() + ": '" + shorten(t[k + 1]) + "' is not a number");
        if (!std::isfinite(p[k]))
          fail(path, "non-finite coordinate", where() + " has coordinate " + "xyz"[k] + " = " + shorten(t[k + 1]));
      }
      scan.points.push_back(p);
      scan.lines.vertex_line.push_back(line);
    } else if (t[0] == "f") {
      const std::size_t j = scan.faces.size();
      auto where = [&] { return "face " + std::to_string(j) + " (line " + std::to_string(line) + ")"; };
      std::vector<std::size_t> face;
      for (std::size_t k = 1; k < t.size() && t[k].front() != '#'; ++k) {
        const std::string_view v = t[k].substr(0, t[k].find('/'));
        long long i = 0;
        if (!parse_index(v, i))
          fail(path, "parse error", where() + ": corner '" + shorten(t[k]) + "' does not start with a vertex index");
        const long long defined = static_cast<long long>(scan.points.size());
        if ((i == 0 || defined + i < 0) && missing == MissingVertices::Keep) {
          face.push_back(SIZE_MAX);
          continue;
        }
        if (i == 0)
          fail_face(path, "vertex index out of range",
                    where() + " has the vertex index 0 (OBJ counts vertices from 1)", j);
        if (i < 0 && defined + i < 0)
          fail_face(path, "vertex index out of range",
                    where() + " has the relative vertex index " + std::to_string(i) +
                        ", but only " +
                        counted(static_cast<std::size_t>(defined), "vertex is", "vertices are") +
                        " defined before it",
                    j);
        // Positive indices may name a vertex further down the file: checked after the last line.
        face.push_back(static_cast<std::size_t>(i > 0 ? i - 1 : defined + i));
      }
      scan.faces.push_back(std::move(face));
      scan.lines.face_line.push_back(line);
    } else if (!skipped_statement(t[0])) {
      fail(path, "parse error", "line " + std::to_string(line) + ": unsupported OBJ statement '" + shorten(t[0]) + "'");
    }
  }
  const std::size_t nv = scan.points.size();
  for (std::size_t j = 0; j < scan.faces.size() && missing == MissingVertices::Refuse; ++j)
    for (const std::size_t v : scan.faces[j])
      if (v >= nv)
        fail_face(path, "vertex index out of range",
                  "face " + std::to_string(j) + " (line " +
                      std::to_string(scan.lines.face_line[j]) + ") refers to vertex " +
                      std::to_string(v + 1) + ", but the file has " +
                      (nv == 0 ? std::string("no vertices")
                               : counted(nv, "vertex", "vertices") + " (OBJ counts from 1: 1.." +
                                     std::to_string(nv) + ")"),
                  j);
  return scan;
}

}  // namespace shellcontract
