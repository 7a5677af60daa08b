// What `repair` writes (see repair_output.hpp). A usable input is not rewritten by a writer of
// ours: whatever such a writer left out (UVs, groups, materials, polygons, a binary encoding)
// would be lost while the report says that nothing changed.
#include "mesh/repair_output.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "core/plural.hpp"
#include "mesh/file_extras.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/formats.hpp"
#include "mesh/gltf_mesh_writer.hpp"
#include "mesh/obj_material_paths.hpp"
#include "mesh/output_check.hpp"
#include "mesh/read_polygon_soup.hpp"
#include "mesh/soup_writer.hpp"
#include "mesh/stl_positions.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

using Polygon = std::vector<std::size_t>;

/// The triangles of `mesh`, the mesh read_input_mesh made of `polygons`, each in the winding of
/// the polygon it comes from: read_input_mesh turns inside-out components outward, and a usable
/// input is written with its own winding, as a copy would have it.
std::vector<Polygon> file_triangles(const Mesh& mesh, const std::vector<Polygon>& polygons) {
  // read_input_mesh: polygon i's first triangle is face i; the other triangles of split polygons
  // follow the last polygon, in polygon order.
  std::vector<std::size_t> origin(polygons.size());
  for (std::size_t p = 0; p < polygons.size(); ++p) origin[p] = p;
  for (std::size_t p = 0; p < polygons.size(); ++p)
    for (std::size_t k = 3; k < polygons[p].size(); ++k) origin.push_back(p);
  std::vector<Polygon> triangles;
  triangles.reserve(mesh.number_of_faces());
  for (const FaceIndex f : mesh.faces()) {
    Polygon t;
    for (const VertexIndex v : vertices_around_face(mesh.halfedge(f), mesh)) t.push_back(v.idx());
    // Fan triangles keep their polygon's cyclic order: the corners' positions in the polygon,
    // counted from the first corner's, increase; a flipped triangle's decrease.
    const Polygon& p = polygons[origin[f.idx()]];
    const std::size_t n = p.size();
    std::array<std::size_t, 3> at{};
    for (std::size_t k = 0; k < 3; ++k)
      at[k] = static_cast<std::size_t>(std::find(p.begin(), p.end(), t[k]) - p.begin());
    if ((at[1] + n - at[0]) % n > (at[2] + n - at[0]) % n) std::swap(t[1], t[2]);
    triangles.push_back(std::move(t));
  }
  return triangles;
}

/// Two vertices at the same stored position (repair splits a pinched vertex into two such;
/// floats can make two close ones equal) would come back as one (stl_positions.hpp).
void require_distinct_stl_points(const std::string& output, const std::vector<Point3>& points,
                                 bool floats) {
  std::vector<std::array<double, 3>> p(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    p[i] = {points[i].x(), points[i].y(), points[i].z()};
  require_distinct_stl_positions("cannot write '" + output + "'", p, {}, floats);
}

/// A .gltf copied into another folder names its buffers and images by paths relative to its own:
/// each one that is beside the input but not beside the copy is a warning (the OBJ's mtllib
/// paths are rewritten instead; a .gltf's bytes stay the input's).
void warn_missing_gltf_files(const std::string& input, const std::string& output,
                             const std::string& bytes, std::vector<std::string>& warnings) {
  namespace fs = std::filesystem;
  const fs::path from = fs::path(input).parent_path(), to = fs::path(output).parent_path();
  std::error_code ec;
  for (const std::string& uri : gltf_file_uris(bytes)) {
    const fs::path rel(uri);
    if (rel.is_absolute() || !fs::exists(from / rel, ec) || fs::exists(to / rel, ec)) continue;
    warnings.push_back(output + ": names '" + printable(uri) + "', a file beside " + input +
                       " but not beside the copy: copy it there too");
  }
}

bool is_gltf(const std::string& ext) { return is_mesh_format(ext, &MeshFormat::gltf); }

/// What repair writes: a plain writer's format, or a glTF by write_gltf_output.
bool repair_writes(const MeshFormat& f) { return f.plain_writer || f.gltf; }

/// The formats that keep every position as given, for a message whose positions do not fit the
/// chosen one: ".off, .obj or .ply".
std::string exact_formats() { return extension_list(&MeshFormat::exact_positions); }

/// The mesh's vertices and triangles as write_mesh_atomic writes them: a welded mesh's as its
/// input numbered them.
void mesh_triangles(const Mesh& mesh, std::vector<Point3>& points,
                    std::vector<Polygon>& triangles) {
  const Positions x = input_positions(mesh, positions_from_mesh(mesh));
  for (Eigen::Index i = 0; i < x.rows(); ++i) points.emplace_back(x(i, 0), x(i, 1), x(i, 2));
  for (const auto& f : input_faces(mesh)) triangles.emplace_back(f.begin(), f.end());
}

/// Writes a .glb or .gltf of the triangles (gltf_mesh_writer.hpp). glTF stores 32-bit floats
/// (relative to the bounding-box centre, the node's translation): when that rounds a position, the
/// rounded mesh goes through the usability check first, as rounding can make a face degenerate or
/// two faces meet, and a file that `check` refuses must not be written as repair's usable output;
/// the lost digits are named among the dropped.
/// @throws UsageError naming the check's reason when the rounded mesh is not usable
void write_gltf_output(const std::string& output, const std::vector<Point3>& points,
                       const std::vector<Polygon>& triangles, bool binary, RepairOutput& o) {
  const std::vector<Point3> stored = points_as_stored_in_gltf(points);
  for (const Point3& p : stored)
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
      throw UsageError("cannot write '" + output +
                       "': the positions span more than glTF's 32-bit floats hold (about 3.4e38 "
                       "from the bounding box's centre); write " +
                       exact_formats());
  std::size_t rounded = 0;
  for (std::size_t i = 0; i < points.size(); ++i) rounded += stored[i] != points[i];
  if (rounded > 0) {
    o.dropped.push_back("the positions' digits beyond 32-bit floats (" +
                        counted(rounded, "vertex", "vertices") + " rounded: glTF stores floats)");
    try {
      InputReport ignored;
      check_input_soup(output, stored, triangles, &ignored);
    } catch (const InputError& e) {
      throw UsageError(
          "cannot write '" + output +
          "': glTF stores 32-bit floats, and with its positions rounded to them the mesh is not "
          "usable (" +
          e.what() + "); write " + exact_formats());
    }
  }
  write_gltf_mesh_atomic(output, points, triangles, binary);
}

}  // namespace

std::string RepairOutput::kind_name() const {
  switch (kind) {
    case Kind::Copy: return "copy";
    case Kind::Converted: return "converted";
    case Kind::Repaired: return "repaired";
  }
  return "";
}

void check_repair_output_name(const std::string& option, const std::string& output) {
  const std::string ext = lower_extension(output);
  if (is_mesh_format(ext, repair_writes)) return;
  throw UsageError(option + " " + quoted_path(output) +
                   (ext.empty() ? std::string(": no file extension to name the mesh format")
                                : ": unknown mesh format '." + printable(ext) + "'") +
                   " (expected " + extension_list(repair_writes) + ")");
}

RepairOutput write_repair_output(const std::string& input, const std::string& output, const Mesh& mesh,
                                 const RepairReport& report) {
  check_repair_output_name("-o", output);
  const std::string in_ext = lower_extension(input), out_ext = lower_extension(output);
  const std::string bytes = read_file_bytes(input);
  const FileExtras extras = describe_file_extras(in_ext, bytes);
  RepairOutput o;
  if (report.already_usable && in_ext == out_ext) {
    o.binary = extras.binary;
    if (in_ext == "obj") {
      // A copy elsewhere must still find its materials (the mtllib paths are relative).
      const std::string moved = relocate_material_libraries(bytes, input, output, &o.warnings);
      o.material_paths_rewritten = moved != bytes;
      write_text_atomic(output, moved);
    } else {
      if (in_ext == "gltf") warn_missing_gltf_files(input, output, bytes, o.warnings);
      write_text_atomic(output, bytes);
    }
    return o;
  }
  o.dropped = extras.items;
  // A binary PLY holds doubles: any position fits. A binary STL holds floats: only an STL's own.
  // A .glb is binary whatever the input (its floats are named in write_gltf_output).
  o.binary = is_gltf(out_ext)
                 ? out_ext == "glb"
                 : extras.binary && (out_ext == "ply" || (out_ext == "stl" && in_ext == "stl"));
  if (extras.binary && !o.binary && !is_gltf(out_ext))
    o.dropped.push_back(std::string("the binary encoding (written as text") +
                        (out_ext == "stl" ? ": a binary STL holds 32-bit floats)" : ")"));
  if (!report.already_usable) {
    o.kind = RepairOutput::Kind::Repaired;
    if (report.polygons_triangulated > 0)
      o.dropped.push_back(counted(report.polygons_triangulated, "polygon", "polygons") +
                          " with more than 3 corners (triangulated)");
    if (is_gltf(out_ext)) {
      std::vector<Point3> points;
      std::vector<Polygon> triangles;
      mesh_triangles(mesh, points, triangles);
      write_gltf_output(output, points, triangles, o.binary, o);
      return o;
    }
    const Positions x = positions_from_mesh(mesh);
    if (out_ext == "stl") {
      std::vector<Point3> points;
      for (Eigen::Index i = 0; i < x.rows(); ++i) points.emplace_back(x(i, 0), x(i, 1), x(i, 2));
      require_distinct_stl_points(output, points, o.binary);
    }
    write_mesh_atomic(output, mesh, x, o.binary);
    return o;
  }
  o.kind = RepairOutput::Kind::Converted;
  std::vector<Point3> points;
  std::vector<Polygon> polygons;
  SourceLines lines;
  read_polygon_soup(input, in_ext, points, polygons, lines);
  if (out_ext == "stl" || is_gltf(out_ext)) {
    const auto split = static_cast<std::size_t>(
        std::count_if(polygons.begin(), polygons.end(), [](const Polygon& p) { return p.size() > 3; }));
    if (split > 0)
      o.dropped.push_back(counted(split, "polygon", "polygons") + " with more than 3 corners (" +
                          (out_ext == "stl" ? "STL" : "glTF") + " holds triangles: " +
                          std::to_string(mesh.number_of_faces() - (polygons.size() - split)) +
                          " triangles written for them)");
    // file_triangles maps the mesh's faces back onto the polygons; a soup of triangles is
    // already what it would give (and a glTF's seam copies, welded in the mesh, stay copies).
    if (out_ext == "stl" || split > 0) polygons = file_triangles(mesh, polygons);
    if (is_gltf(out_ext)) {
      write_gltf_output(output, points, polygons, o.binary, o);
      return o;
    }
    require_distinct_stl_points(output, points, o.binary);
  }
  write_polygon_soup_atomic(output, points, polygons, o.binary);
  return o;
}

}  // namespace shellcontract
