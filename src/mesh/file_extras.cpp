// The extras of a mesh file (see file_extras.hpp): a second, forgiving look at bytes the readers
// accepted, which only counts and names what lies beyond positions and polygons.
#include "mesh/file_extras.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <map>
#include <regex>
#include <string_view>
#include <unordered_set>

#include "core/token_text.hpp"
#include "mesh/formats.hpp"
#include "mesh/line_tokens.hpp"
#include "mesh/ply_header.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {
namespace {

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f' || c == '\n'; }

/// A name from the file for a message: at most 24 characters, non-printable bytes as '?'.
std::string printable_name(std::string_view s) { return shorten(s, 24); }

/// "a, b, c, ..." of the first three names.
std::string name_list(const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t i = 0; i < names.size() && i < 3; ++i) s += (i ? ", " : "") + names[i];
  return names.size() > 3 ? s + ", ..." : s;
}

/// Distinct names in order of first use; a set beside the list, as a search of the list made a
/// file of many distinct names cost their square.
struct Names {
  std::vector<std::string> list;
  std::unordered_set<std::string> seen;
};

void add_once(Names& names, std::string_view name) {
  std::string n = printable_name(name);
  if (names.seen.insert(n).second) names.list.push_back(std::move(n));
}

/// "1 comment line", "3 comment lines".
std::string counted(std::size_t n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

/// The text's lines split into blank-separated tokens, as the text readers see them: a UTF-8
/// byte-order mark skipped, "\r" a line end in a file without any "\n" (read_polygon_soup).
std::vector<std::vector<std::string_view>> token_lines(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  const char eol = text.find('\n') == std::string_view::npos ? '\r' : '\n';
  std::vector<std::vector<std::string_view>> lines;
  for (std::size_t pos = 0; pos < text.size();) {
    std::size_t end = text.find(eol, pos);
    if (end == std::string_view::npos) end = text.size();
    std::vector<std::string_view> t;
    for (std::size_t i = pos; i < end;) {
      while (i < end && blank(text[i])) ++i;
      const std::size_t start = i;
      while (i < end && !blank(text[i])) ++i;
      if (i > start) t.push_back(text.substr(start, i - start));
    }
    lines.push_back(std::move(t));
    pos = end + 1;
  }
  return lines;
}

FileExtras obj_extras(const std::string& bytes) {
  // A statement continued over lines (a backslash at a line's end) is one, as the readers see it.
  std::string joined;
  if (bytes.find('\\') != std::string::npos) {
    joined = bytes;
    join_continued_lines(joined, bytes.find('\n') == std::string::npos ? '\r' : '\n');
  }
  const std::string_view text(joined.empty() ? bytes : joined);
  std::size_t vt = 0, vn = 0, colour_lines = 0, comments = 0, smoothing = 0;
  Names groups, objects, materials, libraries;
  std::map<std::string, std::size_t> other;
  for (const auto& t : token_lines(text)) {
    if (t.empty()) continue;
    const std::string_view k = t[0];
    if (k.front() == '#') ++comments;
    else if (k == "v") colour_lines += t.size() > 4 && t[4].front() != '#';
    else if (k == "vt") ++vt;
    else if (k == "vn") ++vn;
    else if (k == "g") for (std::size_t i = 1; i < t.size(); ++i) add_once(groups, t[i]);
    else if (k == "o" && t.size() > 1) add_once(objects, t[1]);
    else if (k == "usemtl" && t.size() > 1) add_once(materials, t[1]);
    else if (k == "mtllib") for (std::size_t i = 1; i < t.size(); ++i) add_once(libraries, t[i]);
    else if (k == "s") smoothing += t.size() > 1 && t[1] != "off" && t[1] != "0";
    else if (k != "f") ++other[printable_name(k)];
  }
  FileExtras e;
  if (vt) e.items.push_back(counted(vt, "texture coordinate (vt)", "texture coordinates (vt)"));
  if (vn) e.items.push_back(counted(vn, "normal (vn)", "normals (vn)"));
  if (!groups.list.empty())
    e.items.push_back(counted(groups.list.size(), "group", "groups") + " (g " +
                      name_list(groups.list) + ")");
  if (!objects.list.empty())
    e.items.push_back(counted(objects.list.size(), "object", "objects") + " (o " +
                      name_list(objects.list) + ")");
  if (!materials.list.empty())
    e.items.push_back(counted(materials.list.size(), "material", "materials") + " (usemtl " +
                      name_list(materials.list) + ")");
  if (!libraries.list.empty())
    e.items.push_back("the material library (mtllib " + name_list(libraries.list) + ")");
  if (smoothing) e.items.push_back("smoothing groups (s)");
  if (colour_lines) e.items.push_back("vertex colours (numbers after x y z on " + counted(colour_lines, "v line)", "v lines)"));
  if (comments) e.items.push_back(counted(comments, "comment line", "comment lines"));
  for (const auto& [k, n] : other) e.items.push_back(counted(n, "'" + k + "' statement", "'" + k + "' statements"));
  return e;
}

FileExtras ply_extras(const std::string& bytes) {
  FileExtras e;
  ply::Header h;
  try {
    h = ply::read_ply_header("", bytes);
  } catch (const InputError&) {
    return e;
  }
  e.binary = h.format != ply::Format::Ascii;
  bool vertex_seen = false, face_seen = false;
  std::vector<std::string> vertex_props, face_props, elements;
  for (const ply::Element& el : h.elements) {
    const bool is_vertex = el.name == "vertex" && !vertex_seen;
    const bool is_face = el.name == "face" && !face_seen;
    vertex_seen |= is_vertex;
    face_seen |= is_face;
    if (!is_vertex && !is_face) {
      elements.push_back(std::to_string(el.count) + " '" + printable_name(el.name) + "'");
      continue;
    }
    for (const ply::Property& p : el.properties) {
      if (is_vertex && (p.name == "x" || p.name == "y" || p.name == "z")) continue;
      if (is_face && (p.name == "vertex_indices" || p.name == "vertex_index")) continue;
      (is_vertex ? vertex_props : face_props).push_back(printable_name(p.name));
    }
  }
  if (!vertex_props.empty()) e.items.push_back("vertex properties " + name_list(vertex_props));
  if (!face_props.empty()) e.items.push_back("face properties " + name_list(face_props));
  if (!elements.empty()) e.items.push_back("other elements (" + name_list(elements) + ")");
  std::size_t comments = 0;
  for (const auto& t : token_lines(std::string_view(bytes).substr(0, h.body)))
    comments += !t.empty() && (t[0] == "comment" || t[0] == "obj_info");
  if (comments) e.items.push_back(counted(comments, "comment line", "comment lines") + " (comment, obj_info)");
  return e;
}

FileExtras off_extras(std::string_view text) {
  FileExtras e;
  std::vector<std::vector<std::string_view>> lines;
  std::size_t comments = 0;
  for (auto t : token_lines(text)) {
    const auto hash = std::find_if(t.begin(), t.end(), [](std::string_view s) { return s.front() == '#'; });
    comments += hash != t.end();
    t.erase(hash, t.end());
    if (!t.empty()) lines.push_back(std::move(t));
  }
  if (comments) e.items.push_back(counted(comments, "comment line", "comment lines"));
  if (lines.empty()) return e;
  static const std::regex keyword("(ST)?(C)?(N)?(4)?(n)?OFF");
  std::smatch m;
  const std::string header(lines[0][0]);
  if (!std::regex_match(header, m, keyword)) return e;
  if (m[1].matched) e.items.push_back("texture coordinates (STOFF)");
  if (m[2].matched) e.items.push_back("vertex colours (COFF)");
  if (m[3].matched) e.items.push_back("vertex normals (NOFF)");
  if (lines[0].size() > 1 && lines[0][1] == "BINARY") {
    e.binary = true;
    return e;
  }
  // The numbers after the keyword: [dimension] vertex count, face count, edge count.
  std::vector<std::string_view> numbers(lines[0].begin() + 1, lines[0].end());
  std::size_t at = 1;
  const std::size_t wanted = m[5].matched ? 3 : 2;
  for (; numbers.size() < wanted && at < lines.size(); ++at) numbers.insert(numbers.end(), lines[at].begin(), lines[at].end());
  if (numbers.size() < wanted) return e;
  const std::size_t nv = std::strtoull(std::string(numbers[wanted - 2]).c_str(), nullptr, 10);
  const std::size_t nf = std::strtoull(std::string(numbers[wanted - 1]).c_str(), nullptr, 10);
  const std::size_t vertex_numbers = 3 + (m[4].matched ? 1 : 0) + (m[3].matched ? 3 : 0) + (m[1].matched ? 2 : 0);
  std::size_t coloured_vertices = 0, coloured_faces = 0;
  for (std::size_t i = 0; i < nv && at < lines.size(); ++i, ++at) coloured_vertices += lines[at].size() > vertex_numbers;
  for (std::size_t j = 0; j < nf && at < lines.size(); ++j, ++at)
    coloured_faces += lines[at].size() > 1 + std::strtoull(std::string(lines[at][0]).c_str(), nullptr, 10);
  if (coloured_vertices && !m[2].matched)
    e.items.push_back("vertex colours (numbers after the vertex data on " +
                      counted(coloured_vertices, "vertex line)", "vertex lines)"));
  if (coloured_faces) e.items.push_back("face colours (on " + counted(coloured_faces, "face)", "faces)"));
  return e;
}

FileExtras stl_extras(const std::string& bytes) {
  FileExtras e;
  std::uint32_t n = 0;
  if (bytes.size() >= 84) {
    const auto* b = reinterpret_cast<const unsigned char*>(bytes.data()) + 80;
    n = static_cast<std::uint32_t>(b[0]) | static_cast<std::uint32_t>(b[1]) << 8 |
        static_cast<std::uint32_t>(b[2]) << 16 | static_cast<std::uint32_t>(b[3]) << 24;
  }
  // The size of a binary STL is 84 + 50 bytes per facet; an ascii file of that size would have
  // to hold, at bytes 80 to 83, the facet count that makes it so.
  e.binary = bytes.size() >= 84 && (bytes.size() - 84) % 50 == 0 && (bytes.size() - 84) / 50 == n;
  if (e.binary) {
    std::string_view header(bytes.data(), 80);
    while (!header.empty() && (blank(header.back()) || header.back() == '\0')) header.remove_suffix(1);
    while (!header.empty() && blank(header.front())) header.remove_prefix(1);
    // CGAL's binary writer (which `repair` uses) puts "FileType: Binary" in the header and two
    // spaces in every facet's attribute bytes: those come back, they are not the file's own.
    if (!header.empty() && header.rfind("FileType: Binary", 0) != 0)
      e.items.push_back("the 80-byte header ('" + printable_name(header) + "')");
    std::size_t attributes = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const char a = bytes[84 + 50 * i + 48], b = bytes[84 + 50 * i + 49];
      attributes += !((a == 0 && b == 0) || (a == ' ' && b == ' '));
    }
    if (attributes) e.items.push_back("attribute bytes, often colours (on " + counted(attributes, "facet)", "facets)"));
    return e;
  }
  std::size_t solids = 0;
  Names names;
  for (const auto& t : token_lines(bytes))
    if (!t.empty() && t[0] == "solid") {
      ++solids;
      if (t.size() > 1) add_once(names, t[1]);
    }
  if (!names.list.empty()) e.items.push_back("the solid's name (" + name_list(names.list) + ")");
  if (solids > 1) e.items.push_back(std::to_string(solids) + " solids (written as one)");
  return e;
}

}  // namespace

FileExtras describe_file_extras(const std::string& ext, const std::string& bytes) {
  const MeshFormat* format = find_mesh_format(ext);
  if (!format) return {};
  switch (format->id) {
    case FormatId::Obj:
      return obj_extras(bytes);
    case FormatId::Ply:
      return ply_extras(bytes);
    case FormatId::Off:
      return off_extras(bytes);
    case FormatId::Stl:
      return stl_extras(bytes);
    case FormatId::Glb:
    case FormatId::Gltf:
      return describe_gltf_extras(bytes);
  }
  return {};
}

}  // namespace shellcontract
