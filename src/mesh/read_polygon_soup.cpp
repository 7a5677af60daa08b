// Reading a mesh file into a polygon soup (read_input_mesh's first step): the whole
// file is read into memory first, so that every reader can bound what a header declares by the
// bytes that are really there.
#include "mesh/read_polygon_soup.hpp"

#include <CGAL/IO/STL.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/classic_locale.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/formats.hpp"
#include "mesh/gltf_reader.hpp"
#include "mesh/obj_scan.hpp"
#include "mesh/ply_reader.hpp"
#include "mesh/stl_diagnosis.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& path, const std::string& problem, const std::string& details) {
  throw InputError(path + ": " + problem + ": " + details);
}

/// Text formats: drops a UTF-8 byte-order mark, and turns classic-Mac line ends (a lone "\r")
/// into "\n", which CGAL's readers and the OFF scan split lines at ("\r\n" already works there).
/// Only a file without any "\n" is converted, so the data of an "OFF BINARY" file is never touched.
void normalize_text(std::string& s) {
  if (s.compare(0, 3, "\xEF\xBB\xBF") == 0) s.erase(0, 3);
  if (s.find('\n') == std::string::npos) std::replace(s.begin(), s.end(), '\r', '\n');
}

using Polygons = std::vector<std::vector<std::size_t>>;

void read_ply_soup(const std::string& path, const std::string& bytes, std::vector<Point3>& points,
                   Polygons& polygons, SourceLines& lines) {
  PlyData d = read_ply(path, bytes);
  points.reserve(d.points.size());
  for (const auto& p : d.points) points.emplace_back(p[0], p[1], p[2]);
  polygons = std::move(d.faces);
  lines.vertex_line = std::move(d.vertex_line);
  lines.face_line = std::move(d.face_line);
}

/// .gltf is JSON, .glb binary: the reader tells them by their first bytes.
void read_gltf_soup(const std::string& path, const std::string& bytes, std::vector<Point3>& points,
                    Polygons& polygons, std::vector<std::string>* notes) {
  GltfSoup g = read_gltf(path, bytes);
  // A shellcontract --gltf animation is such a file: its base shape is the run's input, so
  // `check RUN.glb --against INPUT` would judge the input against itself.
  if (notes && g.morphed)
    notes->push_back(
        "the file's morph targets (an animation, on " + std::to_string(g.morphed) +
        (g.morphed == 1 ? " primitive" : " primitives") +
        ") are not applied: the mesh read is its base shape (of a shellcontract --gltf "
        "animation, the run's input; its last frame is the run's -o result)");
  points.reserve(g.points.size());
  for (const auto& p : g.points) points.emplace_back(p[0], p[1], p[2]);
  polygons = std::move(g.faces);
}

/// Read by the scan (off_scan.hpp says why not by CGAL).
void read_off_soup(const std::string& path, const std::string& bytes, std::vector<Point3>& points,
                   Polygons& polygons, SourceLines& lines, std::vector<std::string>* warnings,
                   MissingVertices missing) {
  OffScan scan = scan_off(path, bytes, missing);
  if (warnings && !scan.ignored_tail.empty()) warnings->push_back(scan.ignored_tail);
  points.reserve(scan.points.size());
  for (const auto& p : scan.points) points.emplace_back(p[0], p[1], p[2]);
  polygons = std::move(scan.faces);
  lines = std::move(scan.lines);
}

/// Read by the scan (obj_scan.hpp says why not by CGAL).
void read_obj_soup(const std::string& path, const std::string& bytes, std::vector<Point3>& points,
                   Polygons& polygons, SourceLines& lines, MissingVertices missing) {
  ObjScan scan = scan_obj(path, bytes, missing);
  points.reserve(scan.points.size());
  for (const auto& p : scan.points) points.emplace_back(p[0], p[1], p[2]);
  polygons = std::move(scan.faces);
  lines = std::move(scan.lines);
}

/// Read by CGAL; a file it refuses is diagnosed for the message (stl_diagnosis.hpp). Binary, so
/// not normalize_text's.
void read_stl_soup(const std::string& path, const std::string& bytes, std::vector<Point3>& points,
                   Polygons& polygons) {
  ClassicIStringStream in(bytes);
  // An exception inside a stream operation (std::bad_alloc while CGAL's reader reads a line)
  // would otherwise only set badbit, and the reader would return the part read so far.
  in.exceptions(std::ios::badbit);
  // A direct call rather than CGAL's read_polygon_soup: the extension is already known.
  const bool ok = CGAL::IO::read_STL(in, points, polygons);
  if (in.bad()) fail(path, "cannot read file", "the reader's stream failed");
  if (ok) {
    // Text that CGAL read as binary facets of its bytes (an upper-case 'Solid'): refused here,
    // for what it is, not later for the garbage it made.
    const StlDiagnosis text = text_read_as_binary(bytes);
    if (!text.problem.empty()) fail(path, text.problem, text.details);
    // A NaN in a binary file: CGAL gives no error and puts another point in its place.
    const StlDiagnosis d = non_finite_in_binary_stl(bytes);
    if (!d.problem.empty()) fail(path, d.problem, d.details);
    return;
  }
  // CGAL says only that it failed: the diagnosis says where (stl_diagnosis.hpp). Valid files are
  // read by CGAL alone, as before.
  const StlDiagnosis d = diagnose_stl(bytes);
  if (!d.problem.empty()) fail(path, d.problem, d.details);
  fail(path, "parse error", "CGAL could not read it as a .stl file (truncated file or garbage)");
}

}  // namespace

std::string read_file_bytes(const std::string& path) {
  // Regular files only, read to their end with every read checked: a device or FIFO that never
  // ends is refused before reading, and memory running out while reading passes as bad_alloc
  // (read_input_mesh: exit code 2), never as a file cut short (file_safety.hpp).
  return read_regular_file(path);
}

const MeshFormat& require_mesh_extension(const std::string& path, const std::string& ext) {
  if (const MeshFormat* format = find_mesh_format(ext)) return *format;
  // What the path is (missing, a folder, a device) says more than its extension does.
  regular_file_size(path);
  // The format is told by the extension alone, so a file without one names none.
  const std::string expected = "expected " + extension_list(any_format);
  if (ext.empty()) fail(path, "the file name has no extension", expected);
  fail(path, "unknown extension", "'." + ext + "' (" + expected + ")");
}

void read_polygon_soup(const std::string& path, const std::string& ext, std::vector<Point3>& points,
                       std::vector<std::vector<std::size_t>>& polygons, SourceLines& lines,
                       std::vector<std::string>* warnings, MissingVertices missing,
                       std::vector<std::string>* notes) {
  // Before the bytes: a file of another format must not be read as the last reader's (an
  // unknown extension was read as STL by `repair`).
  const FormatId format = require_mesh_extension(path, ext).id;
  std::string bytes = read_file_bytes(path);
  if (std::all_of(bytes.begin(), bytes.end(),
                  [](char c) { return std::isspace(static_cast<unsigned char>(c)); }))
    fail(path, "empty file", "the file holds no data");
  switch (format) {
    case FormatId::Ply:
      return read_ply_soup(path, bytes, points, polygons, lines);
    case FormatId::Glb:
    case FormatId::Gltf:
      return read_gltf_soup(path, bytes, points, polygons, notes);
    case FormatId::Off:
      normalize_text(bytes);
      return read_off_soup(path, bytes, points, polygons, lines, warnings, missing);
    case FormatId::Obj:
      normalize_text(bytes);
      return read_obj_soup(path, bytes, points, polygons, lines, missing);
    case FormatId::Stl:
      return read_stl_soup(path, bytes, points, polygons);
  }
}

}  // namespace shellcontract
