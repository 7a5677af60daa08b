// What `repair` writes (see repair_output.hpp). A usable input is not rewritten by a writer of
// ours: whatever such a writer left out (UVs, groups, materials, polygons, a binary encoding)
// would be lost while the report says that nothing changed.
#include "mesh/repair_output.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <iomanip>
#include <map>
#include <sstream>

#include "core/plural.hpp"
#include "mesh/file_extras.hpp"
#include "mesh/obj_material_paths.hpp"
#include "mesh/read_polygon_soup.hpp"
#include "mesh/soup_writer.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

using Polygon = std::vector<std::size_t>;

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

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

/// An STL stores each facet's corners as coordinates, and its readers (CGAL's, ours) merge equal
/// ones into one vertex: two vertices at the same stored position (repair splits a pinched vertex
/// into two such; floats can make two close ones equal) would come back as one, a mesh other than
/// the one written, and `check` would refuse it.
/// @throws UsageError naming both vertices and the position
void require_distinct_stl_positions(const std::string& output, const std::vector<Point3>& points, bool floats) {
  std::map<std::array<double, 3>, std::size_t> seen;
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::array<double, 3> key{points[i].x(), points[i].y(), points[i].z()};
    if (floats)
      for (double& c : key) c = static_cast<float>(c);
    const auto [at, fresh] = seen.emplace(key, i);
    if (fresh) continue;
    std::ostringstream where;
    where << std::setprecision(9) << '(' << key[0] << ", " << key[1] << ", " << key[2] << ')';
    throw UsageError("cannot write '" + output + "': an STL keeps no vertex identity, and vertices " +
                     std::to_string(at->second) + " and " + std::to_string(i) + " would both be stored at " +
                     where.str() + (floats ? " (as 32-bit floats)" : "") +
                     ": read back, they would be one vertex, and the mesh another; write .off, .obj or .ply");
  }
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

RepairOutput write_repair_output(const std::string& input, const std::string& output, const Mesh& mesh,
                                 const RepairReport& report) {
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
      write_text_atomic(output, bytes);
    }
    return o;
  }
  o.dropped = extras.items;
  // A binary PLY holds doubles: any position fits. A binary STL holds floats: only an STL's own.
  o.binary = extras.binary && (out_ext == "ply" || (out_ext == "stl" && in_ext == "stl"));
  if (extras.binary && !o.binary)
    o.dropped.push_back(std::string("the binary encoding (written as text") +
                        (out_ext == "stl" ? ": a binary STL holds 32-bit floats)" : ")"));
  if (!report.already_usable) {
    o.kind = RepairOutput::Kind::Repaired;
    if (report.polygons_triangulated > 0)
      o.dropped.push_back(counted(report.polygons_triangulated, "polygon", "polygons") +
                          " with more than 3 corners (triangulated)");
    const Positions x = positions_from_mesh(mesh);
    if (out_ext == "stl") {
      std::vector<Point3> points;
      for (Eigen::Index i = 0; i < x.rows(); ++i) points.emplace_back(x(i, 0), x(i, 1), x(i, 2));
      require_distinct_stl_positions(output, points, o.binary);
    }
    write_mesh_atomic(output, mesh, x, o.binary);
    return o;
  }
  o.kind = RepairOutput::Kind::Converted;
  std::vector<Point3> points;
  std::vector<Polygon> polygons;
  SourceLines lines;
  read_polygon_soup(input, in_ext, points, polygons, lines);
  if (out_ext == "stl") {
    const auto split = static_cast<std::size_t>(
        std::count_if(polygons.begin(), polygons.end(), [](const Polygon& p) { return p.size() > 3; }));
    if (split > 0)
      o.dropped.push_back(counted(split, "polygon", "polygons") + " with more than 3 corners (STL holds triangles: " +
                          std::to_string(mesh.number_of_faces() - (polygons.size() - split)) +
                          " triangles written for them)");
    polygons = file_triangles(mesh, polygons);
    require_distinct_stl_positions(output, points, o.binary);
  }
  write_polygon_soup_atomic(output, points, polygons, o.binary);
  return o;
}

}  // namespace shellcontract
