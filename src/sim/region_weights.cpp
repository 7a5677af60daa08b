#include "sim/region_weights.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <locale>
#include <sstream>
#include <string>
#include <vector>

#include "core/decimal_text.hpp"
#include "core/text_lines.hpp"
#include "mesh/file_safety.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/regions.hpp"

namespace shellcontract {

namespace {

[[noreturn]] void line_error(const std::string& path, std::size_t line, const std::string& what) {
  throw InputError(path + ":" + std::to_string(line) + ": " + what);
}

/// What a weights file may hold beyond its weights: comment lines, blank lines, wide spacing.
constexpr std::uint64_t WEIGHTS_FILE_SLACK_BYTES = 1 << 20;

bool valid_weight(double w) { return std::isfinite(w) && w >= 0.0 && w <= 1.0; }

}  // namespace

std::vector<double> read_vertex_weights(const std::string& path, std::size_t num_vertices) {
  // Read whole by read_regular_file, as every other input: a folder, a device or a FIFO is
  // refused by name before anything is read (a stream opened a FIFO and waited for a writer for
  // ever, and read /dev/zero until memory ran out); a file-system failure carries its errno
  // (InputFileError: Python's FileNotFoundError and the like). A weight is a number in [0, 1] on
  // its own line: the shortest text that reads back as any double has at most 24 characters, so
  // 64 bytes a vertex leave room for blanks and a "\r\n", and the slack for comment lines. A
  // larger file (a wrong one, a huge sparse one) is refused by its size before it is read, as the
  // face list is: it was read whole, and copied, until memory ran out.
  const std::uint64_t max_bytes =
      WEIGHTS_FILE_SLACK_BYTES + 64 * static_cast<std::uint64_t>(num_vertices);
  const std::string bytes = read_regular_file(path, max_bytes);
  std::vector<double> weights;
  weights.reserve(num_vertices);
  std::size_t line = 0, last_line = 0;
  for (std::size_t begin = skip_utf8_bom(bytes); begin < bytes.size();) {
    std::istringstream tokens(std::string(next_line(bytes, begin)));  // "\n", "\r\n" or "\r"
    ++line;
    std::string token, extra;
    if (!(tokens >> token) || token[0] == '#') continue;
    if (tokens >> extra)
      line_error(path, line, "'" + printable(extra) + "' after the weight: one weight per line (vertex " +
                                 std::to_string(weights.size()) + ")");
    // A weight is written as an option's number is (parse_decimal): no hexadecimal, inf or nan.
    double w = 0.0;
    if (!parse_decimal(token, w) || !std::isfinite(w))
      line_error(path, line, "'" + printable(token) + "' is not a weight (a number in [0, 1])");
    if (!valid_weight(w))
      line_error(path, line, "weight " + token + " of vertex " + std::to_string(weights.size()) +
                                 " is outside [0, 1]");
    if (weights.size() == num_vertices)
      line_error(path, line, "more weights than the mesh's " + std::to_string(num_vertices) +
                                 " vertices (one weight per vertex, in the mesh's vertex order)");
    weights.push_back(w);
    last_line = line;
  }
  if (weights.size() != num_vertices)
    throw InputError(path + ": " + std::to_string(weights.size()) + " weights for " +
                     std::to_string(num_vertices) + " vertices (the last weight is on line " +
                     std::to_string(last_line) +
                     "); one weight per vertex, in the mesh's vertex order");
  return weights;
}

void check_vertex_weights(const std::vector<double>& weights, std::size_t num_vertices,
                          const std::string& what) {
  if (weights.size() != num_vertices)
    throw UsageError(what + ": " + std::to_string(weights.size()) + " weights for " +
                     std::to_string(num_vertices) + " vertices (one per vertex, in vertex order)");
  for (std::size_t i = 0; i < weights.size(); ++i)
    if (!valid_weight(weights[i])) {
      std::ostringstream w;
      w.imbue(std::locale::classic());  // core/classic_locale.hpp
      w << weights[i];
      throw UsageError(what + "[" + std::to_string(i) + "] = " + w.str() + " is outside [0, 1]");
    }
}

std::vector<double> face_weights(const Mesh& mesh, const std::vector<double>& vertex_weights) {
  // The weights are the input's, one per input vertex: a mesh welded along its seams
  // (mesh_io.hpp) reads each corner's weight from the copy the face used.
  const std::vector<std::array<std::size_t, 3>> corners = input_faces(mesh);
  std::vector<double> out(corners.size(), 0.0);
  for (std::size_t f = 0; f < corners.size(); ++f)
    out[f] = (vertex_weights[corners[f][0]] + vertex_weights[corners[f][1]] + vertex_weights[corners[f][2]]) / 3.0;
  return out;
}

std::size_t mark_weighted_regions(Mesh& mesh, const std::vector<double>& vertex_weights) {
  const std::vector<double> weight = face_weights(mesh, vertex_weights);
  // Edge-connected components of the weighted faces, grown from the lowest face id, so that the
  // ids follow the face order.
  std::vector<int> region(mesh.number_of_faces(), -1);
  int count = 0;
  std::vector<FaceIndex> stack;
  for (FaceIndex seed : mesh.faces()) {
    if (!(weight[seed.idx()] > 0.0) || region[seed.idx()] >= 0) continue;
    region[seed.idx()] = count;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const FaceIndex f = stack.back();
      stack.pop_back();
      for (HalfedgeIndex h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh)) {
        const FaceIndex g = mesh.face(mesh.opposite(h));
        if (g == Mesh::null_face() || !(weight[g.idx()] > 0.0) || region[g.idx()] >= 0) continue;
        region[g.idx()] = count;
        stack.push_back(g);
      }
    }
    ++count;
  }
  store_regions(mesh, region);
  auto [map, created] = mesh.add_property_map<FaceIndex, double>(REGION_WEIGHT_MAP, 0.0);
  (void)created;  // a map from an earlier marking is overwritten
  for (FaceIndex f : mesh.faces()) map[f] = weight[f.idx()];
  return static_cast<std::size_t>(count);
}

void store_region_strengths(Mesh& mesh, const std::vector<std::vector<int>>& regions,
                            const std::vector<double>& strength) {
  if (std::all_of(strength.begin(), strength.end(), [](double s) { return s == 1.0; })) return;
  auto [map, created] = mesh.add_property_map<FaceIndex, double>(REGION_WEIGHT_MAP, 0.0);
  (void)created;
  for (FaceIndex f : mesh.faces()) map[f] = 0.0;  // a map from an earlier marking is overwritten
  for (std::size_t r = 0; r < regions.size() && r < strength.size(); ++r)
    for (int f : regions[r])
      if (f >= 0 && static_cast<std::size_t>(f) < mesh.number_of_faces())
        map[FaceIndex(static_cast<Mesh::size_type>(f))] = strength[r];
}

std::vector<double> stored_region_weights(const Mesh& mesh) {
  const auto [map, found] = mesh.property_map<FaceIndex, double>(REGION_WEIGHT_MAP);
  if (!found) return {};
  std::vector<double> out(mesh.number_of_faces());
  for (FaceIndex f : mesh.faces()) out[f.idx()] = map[f];
  return out;
}

double mean_region_weight(const Positions& x, const Faces& faces, const std::vector<int>& region,
                          const std::vector<double>& weight) {
  if (weight.empty()) return 1.0;
  double sum = 0.0, area = 0.0;
  for (int f : region) {
    const Vec3 xc = x.row(faces(f, 2));
    const double a = (Vec3(x.row(faces(f, 0))) - xc).cross(Vec3(x.row(faces(f, 1))) - xc).norm();
    sum += a * weight[static_cast<std::size_t>(f)];
    area += a;
  }
  return area > 0.0 ? sum / area : 0.0;
}

}  // namespace shellcontract
