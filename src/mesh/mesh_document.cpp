// What the OBJ and PLY documents share (docs/design/attributes.md): the map from the simulation's
// triangles back to the file's polygons, the check that a document stands for a mesh, and the
// texture coordinates per triangle corner for the glTF.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "mesh/formats.hpp"
#include "mesh/read_polygon_soup.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {

std::string format_double(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip text
  return std::string(buf, r.ptr);
}

std::size_t MeshDocument::triangle_count() const {
  std::size_t n = 0;
  for (std::size_t p = 0; p < polygon_count(); ++p)
    n += polygon_start_[p + 1] - polygon_start_[p] - 2;
  return n;
}

std::vector<std::size_t> MeshDocument::face_origins() const {
  // read_input_mesh: polygon i's first triangle is face i; the other n - 3 triangles of each
  // split polygon are appended after the last polygon, in polygon order.
  const std::size_t np = polygon_count();
  std::vector<std::size_t> origin(np);
  for (std::size_t p = 0; p < np; ++p) origin[p] = p;
  for (std::size_t p = 0; p < np; ++p) {
    const std::size_t n = polygon_start_[p + 1] - polygon_start_[p];
    for (std::size_t k = 3; k < n; ++k) origin.push_back(p);
  }
  return origin;
}

bool MeshDocument::matches(const Mesh& mesh) const {
  // By the input's vertices: a mesh welded along its seams (mesh_io.hpp) names them too.
  if (mesh.has_garbage() || input_vertex_count(mesh) != vertex_count_ || polygon_count() == 0)
    return false;
  for (std::size_t p = 0; p < polygon_count(); ++p)
    if (polygon_start_[p + 1] - polygon_start_[p] < 3) return false;
  if (mesh.number_of_faces() != triangle_count()) return false;
  const std::vector<std::size_t> origin = face_origins();
  const std::vector<std::array<std::size_t, 3>> corners = input_faces(mesh);
  for (std::size_t f = 0; f < corners.size(); ++f) {
    const std::size_t p = origin[f];
    const auto b = corner_vertex_.begin() + static_cast<std::ptrdiff_t>(polygon_start_[p]);
    const auto e = corner_vertex_.begin() + static_cast<std::ptrdiff_t>(polygon_start_[p + 1]);
    for (const std::size_t v : corners[f])
      if (std::find(b, e, v) == e) return false;
  }
  return true;
}

namespace {

/// Per simulation face, per corner (faces_array's order): the file corner it is, in
/// `polygon_start`/`corner_vertex` (MeshDocument's); `origin` is face_origins().
std::vector<std::array<std::size_t, 3>> file_corners(const Mesh& mesh,
                                                     const std::vector<std::size_t>& origin,
                                                     const std::vector<std::size_t>& polygon_start,
                                                     const std::vector<std::size_t>& corner_vertex,
                                                     const char* caller) {
  // Corners in the order of faces_array (vertices_around_face from the face's halfedge), by the
  // input's vertex (a welded mesh's too); a vertex appears once in a polygon (read_input_mesh
  // refuses repeats), so it names the corner.
  const std::vector<std::array<std::size_t, 3>> corners = input_faces(mesh);
  std::vector<std::array<std::size_t, 3>> out(corners.size());
  for (std::size_t f = 0; f < corners.size(); ++f) {
    const std::size_t p = origin.at(f);
    for (std::size_t k = 0; k < 3; ++k) {
      std::size_t c = polygon_start[p];
      while (c < polygon_start[p + 1] && corner_vertex[c] != corners[f][k]) ++c;
      if (c == polygon_start[p + 1])
        throw std::invalid_argument(std::string(caller) +
                                    ": the mesh is not this document's (call matches first)");
      out[f][k] = c;
    }
  }
  return out;
}

}  // namespace

CornerTexcoords MeshDocument::texcoords(const Mesh& mesh) const {
  CornerTexcoords t;
  if (uv_.empty() || corner_uv_.empty() ||
      std::any_of(corner_uv_.begin(), corner_uv_.end(), [](long long i) { return i < 0; }))
    return t;
  const std::vector<std::array<std::size_t, 3>> corners =
      file_corners(mesh, face_origins(), polygon_start_, corner_vertex_, "MeshDocument::texcoords");
  t.face_uv.resize(corners.size());
  for (std::size_t f = 0; f < corners.size(); ++f)
    for (std::size_t k = 0; k < 3; ++k)
      t.face_uv[f][k] = static_cast<std::size_t>(corner_uv_[corners[f][k]]);
  t.uv = uv_;
  return t;
}

CornerColours MeshDocument::colours(const Mesh& mesh) const {
  CornerColours c;
  if (colour_.size() != vertex_count_ || vertex_count_ == 0) return c;
  // A corner's colour is its file vertex's: input_faces names the file's vertices, a welded
  // mesh's copies too (their colours may differ, as their texture coordinates do).
  c.face_colour = input_faces(mesh);
  c.rgba = colour_;
  c.channels = colour_channels_;
  return c;
}

void MeshDocument::require_gltf_values() const {
  // A glTF stores these as float32: a double beyond its range would be written as inf, and
  // glTF (and its validator) allows no inf or NaN in an accessor.
  const auto fits = [](double v) {
    return std::isfinite(v) &&
           std::abs(v) <= static_cast<double>(std::numeric_limits<float>::max());
  };
  const auto refuse = [&](const std::string& where, const std::string& what, double v) {
    throw InputError(file_name_ + ": not writable as a glTF: " + where + ": " + what + " " +
                     format_double(v) +
                     (std::isfinite(v) ? " is beyond the largest 32-bit float (3.40282347e+38)"
                                       : " is not a finite number"));
  };
  const bool every_corner_has_uv =
      !uv_.empty() && !corner_uv_.empty() &&
      std::none_of(corner_uv_.begin(), corner_uv_.end(), [](long long i) { return i < 0; });
  if (every_corner_has_uv) {  // texcoords' condition: only then is TEXCOORD_0 written
    std::vector<char> checked(uv_.size(), 0);
    for (const long long t : corner_uv_) {
      const auto i = static_cast<std::size_t>(t);
      if (checked[i]) continue;
      checked[i] = 1;
      for (std::size_t k = 0; k < 2; ++k)
        if (!fits(uv_[i][k]))
          refuse(uv_place(i), std::string("texture coordinate ") + "uv"[k], uv_[i][k]);
    }
  }
  if (colour_.size() == vertex_count_)
    for (std::size_t v = 0; v < colour_.size(); ++v)
      for (std::size_t k = 0; k < 4; ++k)
        if (!fits(colour_[v][k]))
          refuse(vertex_place(v), std::string("colour component ") + "rgba"[k], colour_[v][k]);
}

CornerNormalGroups MeshDocument::normal_groups(const Mesh& mesh) const {
  CornerNormalGroups g;
  const std::vector<long long> group = corner_normal_groups(mesh);
  if (group.empty()) return g;
  if (group.size() != corner_vertex_.size())
    throw std::logic_error("MeshDocument::normal_groups: " + std::to_string(group.size()) +
                           " groups for " + std::to_string(corner_vertex_.size()) + " corners");
  g.face_polygon = face_origins();
  const std::vector<std::array<std::size_t, 3>> corners = file_corners(
      mesh, g.face_polygon, polygon_start_, corner_vertex_, "MeshDocument::normal_groups");
  g.face_group.resize(corners.size());
  for (std::size_t f = 0; f < corners.size(); ++f)
    for (std::size_t k = 0; k < 3; ++k) g.face_group[f][k] = group[corners[f][k]];
  return g;
}

FaceMaterials MeshDocument::face_materials(const Mesh& mesh) const {
  FaceMaterials m = materials_;
  if (m.names.empty() || polygon_material_.size() != polygon_count()) return FaceMaterials{};
  const std::vector<std::size_t> origin = face_origins();
  if (origin.size() != mesh.number_of_faces())
    throw std::invalid_argument(
        "MeshDocument::face_materials: the mesh is not this document's (call matches first)");
  m.face_material.resize(origin.size());
  for (std::size_t f = 0; f < origin.size(); ++f) m.face_material[f] = polygon_material_[origin[f]];
  return m;
}

std::unique_ptr<MeshDocument> read_mesh_document(const std::string& path) {
  const MeshFormat* format = mesh_format_of(path);
  if (!format || !format->document) return nullptr;
  switch (format->id) {
    case FormatId::Obj:
      return parse_obj_document(path, read_file_bytes(path), path);
    case FormatId::Ply:
      return parse_ply_document(path, read_file_bytes(path));
    case FormatId::Glb:
      return parse_gltf_document(path, read_file_bytes(path), true);
    case FormatId::Gltf:
      return parse_gltf_document(path, read_file_bytes(path), false);
    case FormatId::Off:
    case FormatId::Stl:
      break;  // no document (document is false)
  }
  return nullptr;
}

namespace {

/// Whether run's document rule asks anything of a run with this output and animation: only a
/// glTF (the result or the --gltf animation) needs the document, or its values as float32; an
/// OBJ or PLY result without one is written by the plain writer, with run's warning.
bool document_rule_applies(const std::string& output_ext, bool gltf_animation) {
  return gltf_animation || is_mesh_format(output_ext, &MeshFormat::gltf);
}

}  // namespace

void require_run_document(const std::string& input, const MeshDocument* document,
                          const std::string& why_none, const std::string& output_ext,
                          bool gltf_animation) {
  if (!document_rule_applies(output_ext, gltf_animation)) return;
  // Checked before the run: a result that cannot be written is not worth computing.
  if (!document && is_mesh_format(output_ext, &MeshFormat::gltf))
    throw InputError(input + ": the ." + output_ext +
                     " result would be this file with new positions, and it cannot be written "
                     "so (" +
                     why_none + "); choose an " + extension_list(&MeshFormat::plain_writer) +
                     " output");
  // What a glTF holds as float32 (texture coordinates, colours), checked before the run too:
  // found after it, the animation failed with no file or element named.
  if (document) document->require_gltf_values();
}

void check_run_input(const std::string& path) {
  const Mesh mesh = read_input_mesh(path);
  // The result is in the input's format. An STL input has no two vertices at one position (its
  // reader merged them), so run's STL check of the result's positions cannot refuse it.
  const std::string ext = lower_extension(path);
  if (!document_rule_applies(ext, false)) return;  // the document would not be read for it
  std::unique_ptr<MeshDocument> document;
  std::string why_none;
  try {
    document = read_mesh_document(path);
  } catch (const InputError& e) {
    why_none = e.what();
  }
  if (document && !document->matches(mesh)) {
    document.reset();
    why_none = "the mesh is not the file's";
  }
  require_run_document(path, document.get(), why_none, ext, false);
}

void write_mesh_document_atomic(const std::string& path, const MeshDocument& doc,
                                const Positions& x, std::vector<std::string>* warnings) {
  write_text_atomic(path, doc.text_for(path, x, warnings));
}

}  // namespace shellcontract
