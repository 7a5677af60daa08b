// The region face-list file format, the f:region map and the coloured PLY; the selection itself
// is in cap_finder.cpp (header has the algorithm and the meaning of every threshold).
#include "shellcontract/regions.hpp"

#include <CGAL/IO/Color.h>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include "geometry/cap_internal.hpp"
#include "geometry/curvature.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/properties.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

/// What a region file may hold beyond its face ids: comment lines, blank lines, wide spacing.
constexpr std::uint64_t REGION_FILE_SLACK_BYTES = 1 << 20;

std::string line_error(const std::string& path, std::size_t line, const std::string& what) {
  return path + ":" + std::to_string(line) + ": " + what;
}

}  // namespace

std::size_t mark_spherical_regions(Mesh& mesh, const Positions& x, const RegionOptions& options,
                                   RegionReport* report) {
  CurvatureField curvature;  // the finder's own, for the PLY's per-vertex columns
  const std::vector<int> region = detail::select_spherical_regions(mesh, x, options, report, &curvature);
  store_curvature(mesh, curvature);
  store_regions(mesh, region);
  return regions_from_face_ids(region).size();
}

void store_regions(Mesh& mesh, const std::vector<int>& region_of_face) {
  if (region_of_face.size() != mesh.number_of_faces() || mesh.has_garbage())
    throw UsageError("store_regions: " + std::to_string(region_of_face.size()) + " ids for " +
                     std::to_string(mesh.number_of_faces()) + " faces");
  Mesh::Property_map<FaceIndex, int> map;
  try {
    map = property::get_map<FaceIndex, int>(mesh, property::REGION);
  } catch (const UsageError&) {  // not attached yet; add_map refuses existing maps on purpose
    map = property::add_map<FaceIndex, int>(mesh, property::REGION, -1);
  }
  for (FaceIndex f : mesh.faces()) map[f] = region_of_face[f.idx()];
}

std::vector<int> stored_regions(const Mesh& mesh) {
  std::vector<int> ids(mesh.number_of_faces(), -1);
  const auto [map, found] = mesh.property_map<FaceIndex, int>(property::REGION);
  if (found)
    for (FaceIndex f : mesh.faces()) ids[f.idx()] = map[f];
  return ids;
}

std::vector<std::vector<int>> regions_from_face_ids(const std::vector<int>& region_of_face) {
  int max_id = -1;
  for (int id : region_of_face) max_id = std::max(max_id, id);
  std::vector<std::vector<int>> regions(static_cast<std::size_t>(max_id + 1));
  for (std::size_t f = 0; f < region_of_face.size(); ++f)
    if (region_of_face[f] >= 0) regions[static_cast<std::size_t>(region_of_face[f])].push_back(static_cast<int>(f));
  return regions;
}

std::vector<int> face_ids_from_regions(const std::vector<std::vector<int>>& regions, std::size_t num_faces) {
  std::vector<int> id(num_faces, -1);
  for (std::size_t r = 0; r < regions.size(); ++r)
    for (int f : regions[r]) {
      if (f < 0 || static_cast<std::size_t>(f) >= num_faces)
        throw UsageError("region " + std::to_string(r) + ": face " + std::to_string(f) + " is out of range (" +
                         std::to_string(num_faces) + " faces)");
      if (id[static_cast<std::size_t>(f)] != -1)
        throw UsageError("face " + std::to_string(f) + " is in regions " + std::to_string(id[static_cast<std::size_t>(f)]) +
                         " and " + std::to_string(r));
      id[static_cast<std::size_t>(f)] = static_cast<int>(r);
    }
  return id;
}

std::vector<std::vector<int>> read_region_file(const std::string& path, std::size_t num_faces) {
  return read_region_file_with_strengths(path, num_faces).regions;
}

RegionFile read_region_file_with_strengths(const std::string& path, std::size_t num_faces) {
  // A face is listed once at most, in at most 20 characters with its separator: a real file is
  // bounded by the mesh. Larger files (a huge sparse file; /dev/zero is refused as a device)
  // are refused before they are read; so are longer lines.
  const std::uint64_t max_line = REGION_FILE_SLACK_BYTES + 21 * static_cast<std::uint64_t>(num_faces);
  const std::uint64_t max_bytes = REGION_FILE_SLACK_BYTES + 64 * static_cast<std::uint64_t>(num_faces);
  const std::string bytes = read_regular_file(path, max_bytes);
  RegionFile file;
  std::vector<std::size_t> first_line(num_faces, 0);  // line where a face was listed, 0 = not yet
  std::size_t line = 0;
  for (std::size_t begin = 0; begin < bytes.size();) {
    std::size_t end = bytes.find('\n', begin);
    if (end == std::string::npos) end = bytes.size();
    ++line;
    if (end - begin > max_line)
      throw InputError(line_error(printable(path), line, "the line has " + std::to_string(end - begin) +
                                                             " characters, more than a region of this mesh can need (" +
                                                             std::to_string(max_line) + ")"));
    std::string text = bytes.substr(begin, end - begin);
    begin = end + 1;
    if (!text.empty() && text.back() == '\r') text.pop_back();  // files written on Windows
    const std::size_t start = text.find_first_not_of(" \t");
    if (start == std::string::npos || text[start] == '#') continue;
    std::vector<int> region;
    std::istringstream tokens(text);
    std::string token;
    double strength = 1.0;
    bool first = true;
    while (tokens >> token) {
      if (std::exchange(first, false) && token.size() > 1 && token.back() == ':') {
        // The region's strength: the whole token but its ':' must be a number (strtod's end).
        const std::string number = token.substr(0, token.size() - 1);
        char* end = nullptr;
        strength = std::strtod(number.c_str(), &end);
        if (end != number.c_str() + number.size() || !std::isfinite(strength) || strength < 0.0 || strength > 1.0)
          throw InputError(line_error(printable(path), line, "strength '" + printable(number, 40) +
                                                                 "' is not a number in [0, 1]"));
        continue;
      }
      // Digits only: "-1", "3.5", "1e3", "0x10" and "12abc" are all refused rather than
      // half-parsed by stol. The token is quoted printable (a NUL would cut the message).
      if (!std::all_of(token.begin(), token.end(), [](unsigned char ch) { return std::isdigit(ch) != 0; }))
        throw InputError(line_error(printable(path), line, "'" + printable(token, 40) +
                                                               "' is not a face index (a non-negative integer)"));
      if (token.size() > 18 || std::stoull(token) >= num_faces)
        throw InputError(line_error(printable(path), line, "face " + printable(token, 40) + " is out of range (the mesh has " +
                                                    std::to_string(num_faces) + " faces)"));
      const auto f = static_cast<std::size_t>(std::stoull(token));
      if (first_line[f] != 0)
        throw InputError(line_error(printable(path), line, "face " + token + " is already listed on line " +
                                                    std::to_string(first_line[f])));
      first_line[f] = line;
      region.push_back(static_cast<int>(f));
    }
    if (region.empty()) throw InputError(line_error(printable(path), line, "a strength with no face after it"));
    file.regions.push_back(std::move(region));
    file.strength.push_back(strength);
  }
  return file;
}

void write_region_file(const std::string& path, const std::vector<int>& region_of_face) {
  const std::vector<std::vector<int>> regions = regions_from_face_ids(region_of_face);
  std::string text;
  for (std::size_t r = 0; r < regions.size(); ++r) {
    // An empty line would be skipped on reading and shift every later id.
    if (regions[r].empty())
      throw UsageError("write_region_file: region " + std::to_string(r) + " has no face (ids must be 0..n-1)");
    for (std::size_t i = 0; i < regions[r].size(); ++i) text += (i ? " " : "") + std::to_string(regions[r][i]);
    text += '\n';
  }
  write_text_atomic(path, text);
}

std::array<unsigned char, 3> region_colour(int id) {
  if (id < 0) return {160, 160, 160};
  // Hue = id * golden angle (mod 1), full saturation, value 0.95; HSV -> RGB.
  const double hue = std::fmod(static_cast<double>(id) * 0.6180339887498949, 1.0) * 6.0;
  const double v = 0.95, s = 0.85;
  const int sector = static_cast<int>(hue) % 6;
  const double frac = hue - std::floor(hue);
  const double p = v * (1.0 - s), q = v * (1.0 - s * frac), t = v * (1.0 - s * (1.0 - frac));
  double r = v, g = t, b = p;
  switch (sector) {
    case 0: r = v; g = t; b = p; break;
    case 1: r = q; g = v; b = p; break;
    case 2: r = p; g = v; b = t; break;
    case 3: r = p; g = q; b = v; break;
    case 4: r = t; g = p; b = v; break;
    default: r = v; g = p; b = q; break;
  }
  const auto byte = [](double c) { return static_cast<unsigned char>(std::lround(std::clamp(c, 0.0, 1.0) * 255.0)); };
  return {byte(r), byte(g), byte(b)};
}

void write_region_ply(const std::string& path, const Mesh& mesh, const Positions& x) {
  const std::vector<int> region_of_face = stored_regions(mesh);
  const auto [H_in, has_H] = mesh.property_map<VertexIndex, double>(property::MEAN_CURVATURE);
  const auto [K_in, has_K] = mesh.property_map<VertexIndex, double>(property::GAUSSIAN_CURVATURE);
  if (static_cast<std::size_t>(x.rows()) != mesh.number_of_vertices())
    throw UsageError("write_region_ply: " + std::to_string(x.rows()) + " positions for " +
                     std::to_string(mesh.number_of_vertices()) + " vertices");
  // Attached in the order of the file's columns: colour and id per face, curvature per vertex.
  Mesh out = mesh_for_output(mesh, x);
  auto colour = property::add_map<FaceIndex, CGAL::IO::Color>(out, property::FACE_COLOR);
  auto id = property::add_map<FaceIndex, int>(out, property::REGION, -1);
  for (FaceIndex f : out.faces()) {
    const auto rgb = region_colour(region_of_face[f.idx()]);
    colour[f] = CGAL::IO::Color(rgb[0], rgb[1], rgb[2]);
    id[f] = region_of_face[f.idx()];
  }
  if (has_H && has_K) {
    auto H = property::add_map<VertexIndex, double>(out, property::MEAN_CURVATURE);
    auto K = property::add_map<VertexIndex, double>(out, property::GAUSSIAN_CURVATURE);
    for (VertexIndex v : out.vertices()) {
      H[v] = H_in[v];
      K[v] = K_in[v];
    }
  }
  write_ply_atomic(path, out, "shellcontract regions: face colour = region, grey = none");
}

}  // namespace shellcontract
