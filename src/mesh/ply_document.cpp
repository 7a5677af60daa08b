// A PLY file kept as a document (docs/design/attributes.md): its header and every
// element come back byte for byte, but the vertices' x, y, z, which take the new positions in
// their declared floating-point type (an integer type becomes double: a result's positions are
// not integers; text_keeping_gap makes a float one double too where 32-bit floats would undo the
// run's contacts, float32_positions.hpp) and the file's format (ascii text, or binary of either
// byte order), and their nx, ny, nz if the file has them, which take the normals of the new shape
// (also as double where the file's are integers: a unit normal is not an integer). Extra vertex
// properties (texture coordinates, colours, weights, ...), face properties and other elements are
// therefore kept. The header's `comment TextureFile` lines, with the faces' `texnumber`, are its
// face materials (ply_textures.hpp). Its callers (the CLI's run, Python's write_mesh(like=...))
// read the same file with read_input_mesh first, so the bytes are ones read_ply accepted: the
// header is read_ply's own (ply_header.hpp), the body's checks are short, and any surprise is an
// InputError (the CLI then falls back to the plain writer).
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/decimal_text.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/float32_positions.hpp"
#include "mesh/normal_groups.hpp"
#include "mesh/ply_header.hpp"
#include "mesh/ply_slots.hpp"
#include "mesh/ply_textures.hpp"
#include "mesh/seam_weld.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

using ply::Slot;
using ply::written_type;

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

class PlyDocument final : public MeshDocument {
 public:
  PlyDocument(const std::string& name, std::string bytes);
  std::string format() const override { return "ply"; }
  std::string text(const Positions& x) const override { return render(x, {}, false); }
  /// text(x) with the header's TextureFile paths rewritten for a file in another folder, as an
  /// OBJ's mtllib lines are (ply_textures.hpp, texture_file_edits).
  std::string text_for(const std::string& output_path, const Positions& x,
                       std::vector<std::string>* warnings) const override {
    return render(x, ply::texture_file_edits(bytes_, name_, output_path, warnings), false);
  }
  /// text_for with the float32 x, y, z written as double where `widen` (float32_positions.hpp).
  std::string text_widened(const std::string& output_path, const Positions& x, bool widen,
                           std::vector<std::string>* warnings) const {
    return render(x, ply::texture_file_edits(bytes_, name_, output_path, warnings), widen);
  }
  /// The float32 spacing at the largest |coordinate| of x that a float32 x, y or z holds (0: none).
  double float32_spacing(const Positions& x) const {
    double largest = -1.0;
    for (std::size_t k = 0; k < slots_.size(); ++k)
      if (slots_[k].type == ply::Type::Float32)
        largest = std::max(largest, std::abs(x(static_cast<Eigen::Index>(k / 3),
                                               static_cast<Eigen::Index>(k % 3))));
    return largest < 0.0 ? 0.0 : shellcontract::float32_spacing(largest);
  }
  /// x with the values of the float32 x, y, z rounded to float32, as the file holds them.
  Positions rounded(Positions x) const {
    for (std::size_t k = 0; k < slots_.size(); ++k)
      if (slots_[k].type == ply::Type::Float32) {
        double& v = x(static_cast<Eigen::Index>(k / 3), static_cast<Eigen::Index>(k % 3));
        v = static_cast<double>(static_cast<float>(v));
      }
    return x;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(name_ + ": PLY document: " + what);
  }
  /// The next value of type t in the body at pos_ (and its span).
  double next_value(ply::Type t, Slot& where);
  /// The file with positions x, the header's type edits (type_edits_, and float_edits_ where
  /// `widen`) and `header_edits` (spans of the header in bytes_) applied.
  std::string render(const Positions& x, std::vector<TextEdit> header_edits, bool widen) const;

  std::string name_, bytes_;
  bool ascii_ = true, big_endian_ = false;
  std::size_t pos_ = 0;
  std::size_t body_ = 0;  ///< where the body starts in bytes_
  /// `double` in place of each integer type of the vertices' x, y, z (and nx, ny, nz when written)
  std::vector<TextEdit> type_edits_;
  /// `double` in place of the float32 x, y, z types, for a result float32 cannot hold closely
  /// enough (float32_positions.hpp, text_keeping_gap)
  std::vector<TextEdit> float_edits_;
  std::vector<Slot> slots_;  ///< 3 per vertex: x, y, z
  /// 3 per vertex: nx, ny, nz; empty when a vertex lacks one (the file's normals are then kept)
  std::vector<Slot> normal_slots_;
  /// Per vertex, the file's normal as a unit vector (zero: none or of no length); for the normal
  /// groups of normals() (a flat-shaded side's corners keep their side's normal).
  std::vector<Vec3> input_normals_;
  /// The vertex normals at positions x (see text()); a row of NaN keeps the file's normal.
  Positions normals(const Positions& x) const;
  std::string uv_place(std::size_t uv) const override {
    if (uv_face_.empty()) return "vertex " + std::to_string(uv);  // per-vertex coordinates
    return "face " + std::to_string(uv_face_.at(uv)) + "'s texcoord";
  }
  /// Per texture coordinate of a face's `texcoord` list, the first face that has it; empty
  /// for per-vertex coordinates.
  std::vector<std::size_t> uv_face_;
  /// By the normal groups of normals(): copies of a welded vertex with their own normals (a
  /// flat-shaded side's corners) are groups of their own. None when the file's are kept.
  std::vector<long long> corner_normal_groups(const Mesh& mesh) const override {
    if (normal_slots_.empty()) return {};
    return soup::welded_corner_groups(input_vertex_map(mesh), input_normals_, corner_vertex_);
  }
};

double PlyDocument::next_value(ply::Type t, Slot& where) {
  where.type = t;
  where.set = true;
  if (ascii_) {
    while (pos_ < bytes_.size() && is_space(bytes_[pos_])) ++pos_;
    where.begin = pos_;
    while (pos_ < bytes_.size() && !is_space(bytes_[pos_])) ++pos_;
    where.end = pos_;
    if (where.begin == where.end) fail("the body ends early");
    const std::string tok = bytes_.substr(where.begin, where.end - where.begin);
    double v = 0.0;
    if (!parse_c_number(tok, v)) fail("'" + printable(tok) + "' is not a number");
    return v;
  }
  const auto size = static_cast<std::size_t>(ply::size_of(t));
  if (bytes_.size() - pos_ < size) fail("the body ends early");
  unsigned char b[8];
  std::memcpy(b, bytes_.data() + pos_, size);
  if (big_endian_) std::reverse(b, b + size);
  where.begin = pos_;
  where.end = pos_ += size;
  if (!ply::is_integer(t)) {
    if (size == 4) {
      float f;
      std::memcpy(&f, b, 4);
      return f;
    }
    double d;
    std::memcpy(&d, b, 8);
    return d;
  }
  std::uint64_t u = 0;
  for (std::size_t i = size; i-- > 0;) u = (u << 8) | b[i];
  if (ply::is_signed(t) && (u >> (8 * size - 1)) & 1u)
    return static_cast<double>(static_cast<std::int64_t>(u) - (std::int64_t{1} << (8 * size)));
  return static_cast<double>(u);
}

PlyDocument::PlyDocument(const std::string& name, std::string bytes)
    : name_(name), bytes_(std::move(bytes)) {
  file_name_ = name_;
  // read_ply's own header parse: the document runs after read_ply accepted these bytes.
  ply::Header header = ply::read_ply_header(name_, bytes_);
  ascii_ = header.format == ply::Format::Ascii;
  big_endian_ = header.format == ply::Format::BinaryBigEndian;
  pos_ = body_ = header.body;
  bool vertices_seen = false, faces_seen = false;
  polygon_start_.push_back(0);
  std::vector<double> u_values, v_values;
  std::vector<int> texnumbers;  ///< per face: its integer `texnumber` property, if it has one
  std::vector<TextEdit> normal_type_edits;  ///< `double` for integer nx, ny, nz (kept below)
  // MeshLab's wedge texture coordinates: a face list `texcoord` of u v per corner. Used where the
  // vertices have none, and only when every face has two numbers per corner.
  std::vector<std::array<double, 2>> wedge_uv;
  std::vector<std::size_t> wedge_face;  ///< per entry of wedge_uv: its face
  // Vertex colours: red, green, blue and alpha (each optional but the first three), on glTF's
  // scale (integer types divided by their largest value).
  std::vector<std::array<double, 4>> colours;
  bool has_alpha = false;
  std::size_t face_number = 0;
  bool wedges_whole = true, wedges_seen = false;
  for (const ply::Element& e : header.elements) {
    const bool is_vertex = e.name == "vertex" && !vertices_seen;
    const bool is_face = e.name == "face" && !faces_seen;
    vertices_seen |= is_vertex;
    faces_seen |= is_face;
    // Nothing to read in an element without properties, whatever its count (read_ply skips it).
    if (e.properties.empty()) continue;
    // Texture coordinates under the names that PLY writers use (Blender: s, t; others: u, v).
    int u_prop = -1, v_prop = -1;
    // The properties that hold x, y, z: the first of each name, as read_ply reads them.
    int axis_prop[3] = {-1, -1, -1};
    // The properties that hold nx, ny, nz: the first of each name, the only ones written.
    int normal_prop[3] = {-1, -1, -1};
    // The properties that hold red, green, blue, alpha (the first of each name).
    int colour_prop[4] = {-1, -1, -1, -1};
    if (is_vertex) {
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const ply::Property& p = e.properties[k];
        const std::string& n = p.name;
        const int c = n == "red" || n == "diffuse_red"       ? 0
                      : n == "green" || n == "diffuse_green" ? 1
                      : n == "blue" || n == "diffuse_blue"   ? 2
                      : n == "alpha" || n == "diffuse_alpha" ? 3
                                                             : -1;
        if (!p.list && c >= 0 && colour_prop[c] < 0) colour_prop[c] = static_cast<int>(k);
      }
      if (colour_prop[0] < 0 || colour_prop[1] < 0 || colour_prop[2] < 0)
        colour_prop[0] = colour_prop[1] = colour_prop[2] = colour_prop[3] = -1;
      has_alpha = colour_prop[0] >= 0 && colour_prop[3] >= 0;
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const ply::Property& p = e.properties[k];
        const int axis = p.name == "x" ? 0 : p.name == "y" ? 1 : p.name == "z" ? 2 : -1;
        if (p.list || axis < 0 || axis_prop[axis] >= 0) continue;
        axis_prop[axis] = static_cast<int>(k);
        // A result's positions are not integers: stored in an integer type they would be
        // rounded (a small mesh flattened to a few lattice points, with exit 0). The header
        // says double instead, the other properties keep theirs (output-safety.md).
        if (ply::is_integer(p.type))
          type_edits_.push_back(TextEdit{p.type_begin, p.type_end, "double"});
        else if (p.type == ply::Type::Float32)
          float_edits_.push_back(TextEdit{p.type_begin, p.type_end, "double"});
      }
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const ply::Property& p = e.properties[k];
        const int axis = p.name == "nx" ? 0 : p.name == "ny" ? 1 : p.name == "nz" ? 2 : -1;
        if (p.list || axis < 0 || normal_prop[axis] >= 0) continue;
        normal_prop[axis] = static_cast<int>(k);
        // A new unit normal rounded to an integer type is -1, 0 or 1: garbage shading with exit
        // 0. Widened like x, y, z, once it is known that every vertex has its normal written.
        if (ply::is_integer(p.type))
          normal_type_edits.push_back(TextEdit{p.type_begin, p.type_end, "double"});
      }
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const std::string& n = e.properties[k].name;
        if (n == "u" || n == "s" || n == "texture_u" || n == "texture_s")
          u_prop = static_cast<int>(k);
        if (n == "v" || n == "t" || n == "texture_v" || n == "texture_t")
          v_prop = static_cast<int>(k);
      }
      // Each vertex needs at least one byte per property: a count beyond the bytes is refused
      // before anything is reserved for it.
      if (e.count > bytes_.size()) fail("more vertices declared than bytes in the file");
      slots_.resize(3 * e.count);
      normal_slots_.resize(3 * e.count);
      input_normals_.assign(e.count, Vec3::Zero());
      if (colour_prop[0] >= 0) colours.assign(e.count, {0.0, 0.0, 0.0, 1.0});
      vertex_count_ = e.count;
    }
    for (std::size_t i = 0; i < e.count; ++i) {
      const std::size_t corners_before = corner_vertex_.size();
      std::vector<double> face_uv;
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const ply::Property& p = e.properties[k];
        Slot s;
        if (p.list) {
          const double n = next_value(p.count_type, s);
          if (!(n >= 0) || n > static_cast<double>(bytes_.size()))
            fail("a list count is out of range");
          const bool corners = is_face && (p.name == "vertex_indices" || p.name == "vertex_index");
          const bool texcoords = is_face && p.name == "texcoord";
          wedges_seen |= texcoords;
          for (std::size_t j = 0; j < static_cast<std::size_t>(n); ++j) {
            const double value = next_value(p.type, s);
            if (corners) corner_vertex_.push_back(static_cast<std::size_t>(std::max(value, 0.0)));
            if (texcoords) face_uv.push_back(value);
          }
          if (corners) polygon_start_.push_back(corner_vertex_.size());
          continue;
        }
        const double value = next_value(p.type, s);
        if (is_face && p.name == "texnumber" && ply::is_integer(p.type))
          texnumbers.push_back(static_cast<int>(std::clamp(value, -1.0, double{INT_MAX})));
        if (!is_vertex) continue;
        const int kk = static_cast<int>(k);
        for (std::size_t c = 0; c < 4; ++c)
          if (kk == colour_prop[c]) colours[i][c] = ply::colour_value(p.type, value);
        if (kk == axis_prop[0] || kk == axis_prop[1] || kk == axis_prop[2]) {
          slots_[3 * i + (kk == axis_prop[0] ? 0 : kk == axis_prop[1] ? 1 : 2)] = s;
        } else if (kk == normal_prop[0] || kk == normal_prop[1] || kk == normal_prop[2]) {
          const auto axis = static_cast<std::size_t>(p.name[1] - 'x');
          s.original = value;
          normal_slots_[3 * i + axis] = s;
          input_normals_[i][static_cast<Eigen::Index>(axis)] = value;
        } else if (static_cast<int>(k) == u_prop)
          u_values.push_back(value);
        else if (static_cast<int>(k) == v_prop)
          v_values.push_back(value);
      }
      if (is_face) ++face_number;
      if (!is_face || !wedges_seen) continue;
      // The list may come before or after the corners: matched once the face is read.
      const std::size_t corners = corner_vertex_.size() - corners_before;
      if (face_uv.size() != 2 * corners) wedges_whole = false;
      for (std::size_t c = 0; wedges_whole && c < corners; ++c) {
        wedge_uv.push_back({face_uv[2 * c], face_uv[2 * c + 1]});
        wedge_face.push_back(face_number - 1);
      }
    }
  }
  // The texture files: a face's texnumber chooses one (gltf_materials warns for one out of
  // range); without that property every face has the first.
  materials_ = ply::texture_materials(name_, header.comments);
  if (!materials_.names.empty()) {
    if (texnumbers.size() == polygon_count())
      polygon_material_ = texnumbers;
    else
      polygon_material_.assign(polygon_count(), 0);
  }
  for (const Slot& s : slots_)
    if (!s.set) fail("a vertex lacks x, y or z");
  if (!std::all_of(normal_slots_.begin(), normal_slots_.end(), [](const Slot& s) { return s.set; }))
    normal_slots_.clear();
  else
    type_edits_.insert(type_edits_.end(), normal_type_edits.begin(), normal_type_edits.end());
  for (Vec3& n : input_normals_) {
    const double len = n.norm();
    n = len > 0.0 && std::isfinite(len) ? Vec3(n / len) : Vec3::Zero();
  }
  if (u_values.size() == vertex_count_ && v_values.size() == vertex_count_ && vertex_count_ > 0) {
    for (std::size_t i = 0; i < vertex_count_; ++i) uv_.push_back({u_values[i], v_values[i]});
    corner_uv_.assign(corner_vertex_.begin(), corner_vertex_.end());  // per-vertex coordinates
  } else if (wedges_seen && wedges_whole && wedge_uv.size() == corner_vertex_.size() &&
             !wedge_uv.empty()) {
    // Equal pairs are one texture coordinate, as an OBJ's `vt` line shared by corners: the glTF
    // splits a vertex only where its corners' coordinates differ (a seam), not at every corner.
    std::map<std::array<double, 2>, long long> index_of;
    for (std::size_t c = 0; c < wedge_uv.size(); ++c) {
      const std::array<double, 2>& uv = wedge_uv[c];
      const auto it = index_of.emplace(uv, static_cast<long long>(uv_.size()));
      if (it.second) {
        uv_.push_back(uv);
        uv_face_.push_back(wedge_face[c]);
      }
      corner_uv_.push_back(it.first->second);
    }
  }
  colour_ = std::move(colours);
  colour_channels_ = has_alpha ? 4 : 3;
}

Positions PlyDocument::normals(const Positions& x) const {
  // Copies of a seam vertex (input_positions puts each at its vertex's position) with one normal
  // in the file share one new normal, so a seam does not show in the shading; copies with their
  // own normals (a flat-shaded side's corners, a hard edge) each get their own polygons' sum, so
  // the edge stays hard (normal_groups.hpp, as the glTF document's normals).
  const std::vector<std::size_t> group =
      soup::normal_groups(soup::first_at_same_position(x), input_normals_);
  // Each vertex gets the sum of its polygons' Newell vectors (twice their area along their
  // normal), as an OBJ's smooth normals do (obj_normals.hpp), in the file's winding, with the
  // corners relative to the polygon's first (obj_normals.cpp says why: a mesh far from the origin).
  Positions sum = Positions::Zero(x.rows(), 3);
  for (std::size_t p = 0; p + 1 < polygon_start_.size(); ++p) {
    const std::size_t b = polygon_start_[p], e = polygon_start_[p + 1];
    const auto valid = [&](std::size_t c) { return corner_vertex_[c] < vertex_count_; };
    const auto at = [&](std::size_t c) {
      return Vec3(x.row(static_cast<Eigen::Index>(corner_vertex_[c])));
    };
    std::size_t first = b;
    while (first < e && !valid(first)) ++first;
    const Vec3 p0 = first < e ? at(first) : Vec3::Zero();
    Vec3 newell = Vec3::Zero();
    for (std::size_t c = b; c < e; ++c) {
      const std::size_t next = c + 1 < e ? c + 1 : b;
      if (valid(c) && valid(next)) newell += (at(c) - p0).cross(at(next) - p0);
    }
    for (std::size_t c = b; c < e; ++c)
      if (valid(c))
        sum.row(static_cast<Eigen::Index>(group[corner_vertex_[c]])) += newell.transpose();
  }
  Positions n(x.rows(), 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const Vec3 v = sum.row(static_cast<Eigen::Index>(group[static_cast<std::size_t>(i)]));
    const double len = v.norm();
    // No area around the vertex (or none at all): its normal stays as the file gave it.
    const bool ok = len > 0.0 && std::isfinite(len);
    const Vec3 unit = ok ? Vec3(v / len) : Vec3::Constant(std::nan(""));
    n.row(i) = unit.transpose();
  }
  return n;
}

std::string PlyDocument::render(const Positions& x, std::vector<TextEdit> header_edits,
                                bool widen) const {
  if (static_cast<std::size_t>(x.rows()) != vertex_count_)
    throw std::invalid_argument("PlyDocument::text: " + std::to_string(x.rows()) +
                                " positions for " + std::to_string(vertex_count_) + " vertices");
  if (!x.allFinite()) throw std::invalid_argument("PlyDocument::text: a position is not finite");
  // Widened, every x, y, z is a double: nothing for float32 to refuse.
  if (!widen) ply::require_representable(name_, slots_, x);
  // Every value to write with its place: the positions, then the normals that have one.
  std::vector<std::pair<const Slot*, double>> values;
  values.reserve(slots_.size() + normal_slots_.size());
  for (std::size_t k = 0; k < slots_.size(); ++k)
    values.emplace_back(&slots_[k],
                        x(static_cast<Eigen::Index>(k / 3), static_cast<Eigen::Index>(k % 3)));
  if (!normal_slots_.empty()) {
    const Positions n = normals(x);
    for (std::size_t k = 0; k < normal_slots_.size(); ++k) {
      const double v = n(static_cast<Eigen::Index>(k / 3), static_cast<Eigen::Index>(k % 3));
      // A vertex with no new normal keeps the file's; a widened one rewritten as double.
      if (std::isfinite(v))
        values.emplace_back(&normal_slots_[k], v);
      else if (ply::is_integer(normal_slots_[k].type))
        values.emplace_back(&normal_slots_[k], normal_slots_[k].original);
    }
  }
  header_edits.insert(header_edits.end(), type_edits_.begin(), type_edits_.end());
  if (widen) header_edits.insert(header_edits.end(), float_edits_.begin(), float_edits_.end());
  std::sort(header_edits.begin(), header_edits.end(),
            [](const TextEdit& a, const TextEdit& b) { return a.begin < b.begin; });
  std::string out = apply_edits(bytes_.substr(0, body_), header_edits);
  out.reserve(bytes_.size() + (ascii_ ? 24 * values.size() : 4 * slots_.size()));
  // In file order (a header may declare z before x).
  std::sort(values.begin(), values.end(),
            [](const auto& a, const auto& b) { return a.first->begin < b.first->begin; });
  std::size_t at = body_;
  for (const auto& [slot, v] : values) {
    const Slot& s = *slot;
    out.append(bytes_, at, s.begin - at);
    at = s.end;
    const bool position = &s >= slots_.data() && &s < slots_.data() + slots_.size();
    const ply::Type type = widen && position ? ply::Type::Float64 : written_type(s);
    const int size = ply::size_of(type);  // 4 or 8: written_type is never an integer
    if (ascii_) {
      char buf[64];
      // A float property gets the shortest text of the float: what a reader stores anyway.
      const auto r = size == 4 ? std::to_chars(buf, buf + sizeof buf, static_cast<float>(v))
                                       : std::to_chars(buf, buf + sizeof buf, v);
      out.append(buf, r.ptr);
    } else {
      unsigned char b[8];
      if (size == 4) {
        const auto f = static_cast<float>(v);
        std::memcpy(b, &f, 4);
      } else {
        std::memcpy(b, &v, 8);
      }
      if (big_endian_) std::reverse(b, b + size);
      out.append(reinterpret_cast<const char*>(b), static_cast<std::size_t>(size));
    }
  }
  out.append(bytes_, at, std::string::npos);
  return out;
}

}  // namespace

std::unique_ptr<MeshDocument> parse_ply_document(const std::string& name,
                                                 const std::string& bytes) {
  return std::make_unique<PlyDocument>(name, bytes);
}

std::optional<double> ply_float32_spacing(const MeshDocument& doc, const Positions& x) {
  const auto* ply = dynamic_cast<const PlyDocument*>(&doc);
  return ply ? std::optional<double>(ply->float32_spacing(x)) : std::nullopt;
}

std::optional<std::string> ply_text_for(const MeshDocument& doc, const std::string& output_path,
                                        const Positions& x, bool widen,
                                        std::vector<std::string>* warnings) {
  const auto* ply = dynamic_cast<const PlyDocument*>(&doc);
  if (!ply) return std::nullopt;
  return ply->text_widened(output_path, x, widen, warnings);
}

std::optional<Positions> ply_rounded(const MeshDocument& doc, const Positions& x) {
  const auto* ply = dynamic_cast<const PlyDocument*>(&doc);
  return ply ? std::optional<Positions>(ply->rounded(x)) : std::nullopt;
}

}  // namespace shellcontract
