// The region face-list file format and the f:region map; the coloured PLY is in region_ply.cpp,
// the selection itself in cap_finder.cpp (header has the algorithm and the meaning of every threshold).
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
#include <string_view>
#include <utility>

#include "core/cancellation.hpp"
#include "core/decimal_text.hpp"
#include "core/text_lines.hpp"
#include "geometry/cap_internal.hpp"
#include "geometry/curvature.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/properties.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/regions.hpp"

namespace shellcontract {
namespace {

/// What a region file may hold beyond its face ids: comment lines, blank lines, wide spacing.
constexpr std::uint64_t REGION_FILE_SLACK_BYTES = 1 << 20;

std::string line_error(const std::string& path, std::size_t line, const std::string& what) {
  return path + ":" + std::to_string(line) + ": " + what;
}

}  // namespace

std::vector<int> detail::with_cancel_hook(const RegionOptions& options, const char* who,
                                          const std::function<std::vector<int>()>& search) {
  if (!options.cancelled) return search();
  try {
    const CancellationScope scope(options.cancelled);
    return search();
  } catch (const PreparationCancelled&) {
    throw RegionSearchCancelled(std::string(who) + ": cancelled");
  }
}

std::size_t mark_spherical_regions(Mesh& mesh, const Positions& x, const RegionOptions& options,
                                   RegionReport* report) {
  CurvatureField curvature;  // the finder's own, for the PLY's per-vertex columns
  const std::vector<int> region = detail::with_cancel_hook(options, "mark_spherical_regions", [&] {
    return detail::select_spherical_regions(mesh, x, options, report, &curvature);
  });
  store_curvature(mesh, curvature);
  store_regions(mesh, region);
  return regions_from_face_ids(region).size();
}

namespace {

/// Region ids are -1 (none) or a region's index: a lower one was read as "none" without a word.
void check_region_ids(const char* who, const std::vector<int>& region_of_face) {
  for (std::size_t f = 0; f < region_of_face.size(); ++f)
    if (region_of_face[f] < -1)
      throw UsageError(std::string(who) + ": face " + std::to_string(f) + " has region id " +
                       std::to_string(region_of_face[f]) + " (ids are -1 for none, or 0, 1, ...)");
}

}  // namespace

void store_regions(Mesh& mesh, const std::vector<int>& region_of_face) {
  // Face f's id is region_of_face[f]: with removed faces (garbage) the indices are not 0..n-1.
  if (mesh.has_garbage())
    throw UsageError("store_regions: the mesh has removed elements (call collect_garbage first)");
  if (region_of_face.size() != mesh.number_of_faces())
    throw UsageError("store_regions: " + std::to_string(region_of_face.size()) + " ids for " +
                     std::to_string(mesh.number_of_faces()) + " faces");
  check_region_ids("store_regions", region_of_face);
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
  for (std::size_t begin = skip_utf8_bom(bytes); begin < bytes.size();) {
    const std::string_view whole = next_line(bytes, begin);  // "\n", "\r\n" or "\r" ends it
    ++line;
    if (whole.size() > max_line)
      throw InputError(line_error(printable(path), line,
                                  "the line has " + std::to_string(whole.size()) +
                                      " characters, more than a region of this mesh can need (" +
                                      std::to_string(max_line) + ")"));
    std::string text(whole);
    const std::size_t start = text.find_first_not_of(" \t");
    if (start == std::string::npos || text[start] == '#') continue;
    std::vector<int> region;
    double strength = 1.0;
    // The region's strength: what comes before the line's ':' ("0.5: 12 13", "0.5:12 13",
    // " 0.5 : 12"), blanks around it allowed; the whole of it must be a number in the grammar of
    // every option's (parse_decimal: decimal, whatever locale a host program set; no hexadecimal,
    // which strtod's reading took as 0x0.8 = 0.5, no inf or nan).
    const std::size_t colon = text.find(':');
    if (colon != std::string::npos) {
      // text[start] is not a blank, so the search back from the ':' stops at start at the latest.
      const std::string number =
          colon == start ? ""
                         : text.substr(start, text.find_last_not_of(" \t", colon - 1) + 1 - start);
      if (number.empty())
        throw InputError(line_error(printable(path), line, "a ':' with no strength before it"));
      if (!parse_decimal(number, strength) || !std::isfinite(strength) || strength < 0.0 ||
          strength > 1.0)
        throw InputError(
            line_error(printable(path), line,
                       "strength '" + printable(number, 40) + "' is not a number in [0, 1]"));
      text.erase(0, colon + 1);
    }
    std::istringstream tokens(text);
    std::string token;
    while (tokens >> token) {
      // Digits only: "-1", "3.5", "1e3", "0x10" and "12abc" are all refused rather than
      // half-parsed by stol. The token is quoted printable (a NUL would cut the message).
      if (!std::all_of(token.begin(), token.end(), [](unsigned char ch) { return std::isdigit(ch) != 0; }))
        throw InputError(line_error(printable(path), line, "'" + printable(token, 40) +
                                                               "' is not a face index (a non-negative integer)"));
      // Leading zeros ("0001", as a spreadsheet pads) are no part of the value: counted in the
      // length that keeps stoull within range, they made a small id "out of range".
      const std::size_t nonzero = token.find_first_not_of('0');
      const std::string digits = nonzero == std::string::npos ? "0" : token.substr(nonzero);
      if (digits.size() > 18 || std::stoull(digits) >= num_faces)
        throw InputError(line_error(printable(path), line, "face " + printable(token, 40) + " is out of range (the mesh has " +
                                                    std::to_string(num_faces) + " faces)"));
      const auto f = static_cast<std::size_t>(std::stoull(digits));
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
  check_region_ids("write_region_file", region_of_face);
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

}  // namespace shellcontract
