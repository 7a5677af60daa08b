// An OBJ file kept as a document (docs/design/attributes.md). The file's bytes are
// kept; writing replaces only the text of the `v` lines' x y z and of the `vn` lines, so texture
// coordinates, face corners (v/vt/vn), groups, objects, materials, smoothing groups, comments and
// polygons come back exactly as read. The one exception: a `vn` line whose corners no longer share
// a normal (obj_normals.hpp) becomes several lines, and the corners' normal indices are
// renumbered to match. A file written to another folder also gets its `mtllib`
// paths rewritten, so that they name the same .mtl files from there (obj_material_paths.hpp).
//
// Vertex i of the simulation is the i-th `v` line: scan_obj, which read_input_mesh uses,
// keeps the `v` lines in order and never merges duplicates, so no map is needed besides the
// identity (MeshDocument::matches checks it). Quads and larger polygons are split into triangles
// for the simulation only (by a fan, a quad's diagonal or ear clipping: polygon_split.hpp); their
// corners keep their vertices here, which move with the simulation.
//
// Continued lines (a backslash at a line's end) are read as scan_obj reads them, each statement
// on the line where it starts. A continued `v` keeps its continuations (each number is replaced
// on its own); a continued `vn` that is rewritten becomes one line, as an unchanged one is kept.
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/decimal_text.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/line_tokens.hpp"
#include "mesh/obj_material_paths.hpp"
#include "mesh/obj_normals.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

/// A `vn` line's value after its keyword ([at, end) of `text`) as a unit vector, for the normal
/// groups (obj_normals.hpp); zero when it is not three finite numbers or has no length. The reader
/// skips `vn` lines (obj_scan.cpp), so such a line is no error: its corners are grouped as corners
/// without a value.
Vec3 normal_value(const std::string& text, std::size_t at, std::size_t end) {
  Vec3 n = Vec3::Zero();
  for (Eigen::Index k = 0; k < 3; ++k) {
    const Span t = next_token(text, at, end);
    double v = 0.0;
    if (t.begin == t.end ||
        !parse_c_number(std::string_view(text).substr(t.begin, t.end - t.begin), v) ||
        !std::isfinite(v))
      return Vec3::Zero();
    n[k] = v;
  }
  const double len = n.norm();
  return len > 0.0 && std::isfinite(len) ? Vec3(n / len) : Vec3::Zero();
}

class ObjDocument final : public MeshDocument {
 public:
  ObjDocument(const std::string& name, std::string bytes, std::string path);

  std::string format() const override { return "obj"; }
  std::string text(const Positions& x) const override { return compose(x, {}); }
  std::string text_for(const std::string& output_path, const Positions& x,
                       std::vector<std::string>* warnings) const override {
    return compose(x, material_library_edits(statements(), mtllib_, path_, output_path, warnings));
  }

 private:
  [[noreturn]] void fail(std::size_t line, const std::string& problem,
                         const std::string& what) const {
    throw InputError(name_ + ": " + problem + ": line " + std::to_string(line) + ": " + what);
  }
  double number(const Span& t, std::size_t line, const char* what) const;
  /// A face corner's index ("3", "-1"): 0-based, relative ones resolved against `count`.
  long long index(const std::string& token, std::size_t count, std::size_t line,
                  const char* what) const;
  void read_face(std::size_t at, std::size_t end, std::size_t line);
  /// A usemtl line's name, [at, end) the line after its keyword: the faces that follow use it.
  void use_material(std::size_t at, std::size_t end);
  /// The file with the positions x, the normals of their polygons and `edits` (mtllib lines).
  std::string compose(const Positions& x, std::vector<TextEdit> edits) const;
  /// The corners of a welded vertex with the same `vn` value, whatever lines hold it, are one
  /// normal group, as they share a normal in the OBJ result (obj_normals.hpp). None when no
  /// corner has a `vn`.
  std::vector<long long> corner_normal_groups(const Mesh& mesh) const override {
    for (const long long n : corner_vn_)
      if (n >= 0) return obj_corner_groups(input_vertex_map(mesh), corners());
    return {};
  }
  std::string uv_place(std::size_t uv) const override {
    return "line " + std::to_string(vt_line_.at(uv)) + " (vt " + std::to_string(uv + 1) + ")";
  }
  std::string vertex_place(std::size_t v) const override {
    return "line " + std::to_string(v_line_.at(v)) + " (v " + std::to_string(v + 1) + ")";
  }
  ObjCorners corners() const { return {&polygon_start_, &corner_vertex_, &corner_vn_, &vn_dir_}; }
  /// The file's text with its continued lines joined: the bytes themselves when it has none.
  const std::string& statements() const { return joined_.empty() ? bytes_ : joined_; }

  std::string name_;
  std::string bytes_;
  std::string path_;                  ///< the file read; empty: unknown
  /// The bytes with their continued lines joined (join_continued_lines), each statement one line
  /// at the bytes' own offsets; empty when no line is continued (no copy of most files).
  std::string joined_;
  std::vector<MtllibLine> mtllib_;    ///< the spans of the mtllib lines' names
  std::vector<Span> v_numbers_;       ///< per `v` line: the span of its "x y z" text
  std::vector<std::size_t> v_line_, vt_line_;  ///< per `v` / `vt` line: its line number
  std::vector<Span> vn_text_;         ///< per `vn` line: the span from "vn" to the line's end
  std::vector<Vec3> vn_dir_;          ///< per `vn` line: its unit value; zero: none (normal_value)
  std::vector<long long> corner_vn_;  ///< per corner: index of its `vn` line; -1 none
  std::vector<Span> corner_vn_token_;  ///< per corner: the span of its normal index's text
  std::vector<std::size_t> corner_vn_before_;  ///< per corner: `vn` lines before its face
  std::string eol_ = "\n";            ///< the file's line end, for lines it gains
  int material_ = -1;                 ///< the material of the faces read next (usemtl); -1 none
  std::unordered_map<std::string, int> material_index_;  ///< per name: its index in materials_
};

double ObjDocument::number(const Span& t, std::size_t line, const char* what) const {
  if (t.begin == t.end) fail(line, "parse error", std::string("missing ") + what);
  const std::string s = bytes_.substr(t.begin, t.end - t.begin);
  double v = 0.0;
  if (!parse_c_number(s, v))
    fail(line, "parse error", std::string(what) + " '" + s + "' is not a number");
  return v;
}

long long ObjDocument::index(const std::string& token, std::size_t count, std::size_t line,
                             const char* what) const {
  char* end = nullptr;
  const long long i = std::strtoll(token.c_str(), &end, 10);
  if (token.empty() || end != token.c_str() + token.size())
    fail(line, "parse error", std::string(what) + " index '" + printable(token) + "' is not an integer");
  const long long n = static_cast<long long>(count);
  // Negative indices count back from the last element defined so far (OBJ's relative references).
  const long long zero_based = i > 0 ? i - 1 : n + i;
  if (i == 0 || zero_based < 0 || zero_based >= n)
    fail(line, "index out of range",
         std::string(what) + " index " + token + " refers to none of the " + std::to_string(count) +
             " defined so far");
  return zero_based;
}

void ObjDocument::read_face(std::size_t at, std::size_t end, std::size_t line) {
  std::size_t corners = 0;
  const std::string& text = statements();
  for (Span t = next_token(text, at, end); t.begin != t.end; t = next_token(text, at, end)) {
    const std::string tok = bytes_.substr(t.begin, t.end - t.begin);
    if (tok[0] == '#') break;  // a comment after the corners
    const std::size_t s1 = tok.find('/');
    const std::size_t s2 = s1 == std::string::npos ? std::string::npos : tok.find('/', s1 + 1);
    corner_vertex_.push_back(
        static_cast<std::size_t>(index(tok.substr(0, s1), v_numbers_.size(), line, "vertex")));
    long long vt = -1, vn = -1;
    Span vn_token{t.end, t.end};
    if (s1 != std::string::npos) {
      const std::string t_vt =
          tok.substr(s1 + 1, s2 == std::string::npos ? std::string::npos : s2 - s1 - 1);
      if (!t_vt.empty()) vt = index(t_vt, uv_.size(), line, "texture coordinate");
      if (s2 != std::string::npos) {
        vn = index(tok.substr(s2 + 1), vn_text_.size(), line, "normal");
        vn_token.begin = t.begin + s2 + 1;
      }
    }
    corner_uv_.push_back(vt);
    corner_vn_.push_back(vn);
    corner_vn_token_.push_back(vn_token);
    corner_vn_before_.push_back(vn_text_.size());
    ++corners;
  }
  if (corners == 0) fail(line, "parse error", "a face without corners");
  polygon_start_.push_back(corner_vertex_.size());
  polygon_material_.push_back(material_);
}

ObjDocument::ObjDocument(const std::string& name, std::string bytes, std::string path)
    : name_(name), bytes_(std::move(bytes)), path_(std::move(path)) {
  polygon_start_.push_back(0);
  // Lines end at "\n" ("\r\n" too: the "\r" counts as space); a file with no "\n" at all ends
  // its lines with a lone "\r" (classic Mac), as read_polygon_soup accepts.
  const char eol = bytes_.find('\n') == std::string::npos ? '\r' : '\n';
  const std::size_t first_eol = bytes_.find(eol);
  if (eol == '\r') eol_ = "\r";
  else if (first_eol != std::string::npos && first_eol > 0 && bytes_[first_eol - 1] == '\r') eol_ = "\r\n";
  if (bytes_.find('\\') != std::string::npos) {
    joined_ = bytes_;
    const std::size_t dangling = join_continued_lines(joined_, eol);
    if (dangling != std::string::npos)
      fail(line_of(bytes_, dangling, eol), "parse error",
           "a line continuation ('\\') with no line after it");
    if (joined_ == bytes_) joined_.clear();
  }
  file_name_ = name_;
  bool vertex_without_colour = false;
  const std::string& text = statements();
  std::size_t begin = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;  // a UTF-8 byte-order mark
  // `line`: where the statement starts, as scan_obj counts (obj_scan.hpp).
  for (std::size_t line = 1; begin < text.size(); ++line) {
    std::size_t end = text.find(eol, begin);
    if (end == std::string::npos) end = text.size();
    std::size_t at = begin;
    const Span key = next_token(text, at, end);
    const std::string k = text.substr(key.begin, key.end - key.begin);
    if (k == "v") {
      Span numbers;
      for (const char* c : {"x", "y", "z"}) {
        const Span t = next_token(text, at, end);
        number(t, line, c);
        if (c[0] == 'x') numbers.begin = t.begin;
        numbers.end = t.end;
      }
      v_numbers_.push_back(numbers);
      v_line_.push_back(line);
      // Vertex colours as MeshLab and Blender write them: `v x y z r g b`, three numbers after
      // x y z (one alone is a weight w). Not numbers: no colour, as for any other reader.
      std::array<double, 4> rgba{0.0, 0.0, 0.0, 1.0};
      std::size_t n = 0;
      bool numbers_only = true;
      for (Span t = next_token(text, at, end); t.begin != t.end; t = next_token(text, at, end)) {
        if (text[t.begin] == '#') break;
        double value = 0.0;
        if (n >= 3 || !parse_c_number(text.substr(t.begin, t.end - t.begin), value)) {
          numbers_only = false;
          break;
        }
        rgba[n++] = value;
      }
      if (numbers_only && n == 3) {
        if (colour_.size() + 1 == v_numbers_.size()) colour_.push_back(rgba);
      } else {
        vertex_without_colour = true;
      }
    } else if (k == "vt") {
      vt_line_.push_back(line);
      const double u = number(next_token(text, at, end), line, "u");
      const Span tv = next_token(text, at, end);
      uv_.push_back({u, tv.begin == tv.end ? 0.0 : number(tv, line, "v")});
    } else if (k == "vn") {
      std::size_t e = end;
      while (e > key.begin && is_line_space(text[e - 1])) --e;  // keep a "\r" of "\r\n" outside
      vn_text_.push_back({key.begin, e});
      vn_dir_.push_back(normal_value(text, at, end));
    } else if (k == "f") {
      read_face(at, end, line);
    } else if (k == "mtllib") {
      mtllib_.push_back(mtllib_line(text, at, end, line));
    } else if (k == "usemtl") {
      use_material(at, end);
    }
    if (!joined_.empty())  // the line ends this statement's continuations joined
      line += static_cast<std::size_t>(
          std::count(bytes_.begin() + static_cast<std::ptrdiff_t>(begin),
                     bytes_.begin() + static_cast<std::ptrdiff_t>(end), eol));
    begin = end + 1;
  }
  vertex_count_ = v_numbers_.size();
  // Colours only when every vertex has one (glTF's COLOR_0 has one per vertex).
  if (vertex_without_colour) colour_.clear();
  colour_channels_ = 3;
  // The libraries, by the names mtllib_names finds (a name with spaces in it too); without the
  // file's path their folder is unknown, and so are they.
  const std::filesystem::path folder = std::filesystem::path(path_).parent_path();
  if (!path_.empty())
    for (const MtllibLine& l : mtllib_)
      for (const MtllibName& n : mtllib_names(text, l, folder))
        materials_.libraries.push_back({(folder / n.name).string(), l.line, n.found});
  materials_.source = name_;
  // A texture coordinate only where every corner of every polygon has one (the glTF's TEXCOORD_0
  // needs one per vertex): otherwise none at all.
  for (const long long t : corner_uv_)
    if (t < 0) {
      corner_uv_.assign(corner_uv_.size(), -1);
      break;
    }
}

void ObjDocument::use_material(std::size_t at, std::size_t end) {
  // The name is the rest of the line (names with spaces exist), without a comment at its end.
  const std::string& text = statements();
  while (at < end && is_line_space(text[at])) ++at;
  // The '#' looked for in this line only: up to the file's end, each usemtl of a file without
  // a later comment read the rest of the file.
  const std::size_t hash = std::string_view(text).substr(at, end - at).find('#');
  std::size_t e = hash == std::string_view::npos ? end : at + hash;
  while (e > at && is_line_space(text[e - 1])) --e;
  const std::string name = text.substr(at, e - at);
  if (name.empty()) {
    material_ = -1;
    return;
  }
  // By a map, not a search of the names: a file of many distinct names cost their square.
  const auto [found, added] =
      material_index_.emplace(name, static_cast<int>(materials_.names.size()));
  if (added) materials_.names.push_back(name);
  material_ = found->second;
}

std::string ObjDocument::compose(const Positions& x, std::vector<TextEdit> edits) const {
  if (static_cast<std::size_t>(x.rows()) != vertex_count_)
    throw std::invalid_argument("ObjDocument::text: " + std::to_string(x.rows()) +
                                " positions for " + std::to_string(vertex_count_) + " vertices");
  if (!x.allFinite()) throw std::invalid_argument("ObjDocument::text: a position is not finite");

  // Normals: the corners of one vertex that share a `vn` value get the area-weighted normal of
  // their polygons at the new positions (obj_normals.hpp).
  const ObjNormals normals = obj_normals(x, corners());

  // The pieces to replace, in file order (v, vn and mtllib spans are in statements of their own,
  // the corners' normal indices inside face statements).
  edits.reserve(edits.size() + v_numbers_.size() + vn_text_.size());
  for (std::size_t i = 0; i < v_numbers_.size(); ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    const Span n = v_numbers_[i];
    const std::size_t length = n.end - n.begin;
    if (joined_.empty() || joined_.compare(n.begin, length, bytes_, n.begin, length) == 0) {
      edits.push_back(
          {n.begin, n.end,
           format_double(x(r, 0)) + ' ' + format_double(x(r, 1)) + ' ' + format_double(x(r, 2))});
      continue;
    }
    // x y z continued over lines: each number replaced on its own, so that the continuations
    // (and the lines of the file) stay as they were.
    std::size_t at = n.begin;
    for (Eigen::Index k = 0; k < 3; ++k) {
      const Span t = next_token(joined_, at, n.end);
      edits.push_back({t.begin, t.end, format_double(x(r, k))});
    }
  }
  // first_written[j]: the 0-based index that the first line written for `vn` line j has.
  std::vector<std::size_t> first_written(vn_text_.size() + 1, 0);
  bool split = false;
  for (std::size_t j = 0; j < vn_text_.size(); ++j) {
    const std::vector<Vec3>& lines = normals.lines[j];
    first_written[j + 1] = first_written[j] + std::max<std::size_t>(1, lines.size());
    split |= lines.size() > 1;
    // A normal no polygon uses, or whose polygons have no area now, keeps its line.
    if (lines.empty()) continue;
    std::string text;
    for (const Vec3& n : lines)
      text += (text.empty() ? "vn " : eol_ + "vn ") + format_double(n.x()) + ' ' +
              format_double(n.y()) + ' ' + format_double(n.z());
    edits.push_back({vn_text_[j].begin, vn_text_[j].end, std::move(text)});
  }
  // Lines were added: every corner names its normal by its new index, a relative one (-k)
  // relative to the lines written before its face, as it was.
  for (std::size_t c = 0; split && c < corner_vn_.size(); ++c) {
    if (corner_vn_[c] < 0) continue;
    const Span t = corner_vn_token_[c];
    const std::size_t written = first_written[static_cast<std::size_t>(corner_vn_[c])] + normals.pick[c];
    const bool relative = bytes_[t.begin] == '-';
    const std::string text =
        relative ? std::to_string(static_cast<long long>(written) -
                                  static_cast<long long>(first_written[corner_vn_before_[c]]))
                 : std::to_string(written + 1);
    if (bytes_.compare(t.begin, t.end - t.begin, text) != 0) edits.push_back({t.begin, t.end, text});
  }
  std::sort(edits.begin(), edits.end(),
            [](const TextEdit& a, const TextEdit& b) { return a.begin < b.begin; });
  return apply_edits(bytes_, edits);
}

}  // namespace

std::unique_ptr<MeshDocument> parse_obj_document(const std::string& name,
                                                 const std::string& bytes,
                                                 const std::string& path) {
  return std::make_unique<ObjDocument>(name, bytes, path);
}

}  // namespace shellcontract
