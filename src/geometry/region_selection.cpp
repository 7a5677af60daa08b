// Spherical-region selection by curvature and the region face-list file format (header has the
// algorithm and the meaning of every threshold).
#include "shellcontract/geometry/region_selection.hpp"

#include <CGAL/IO/Color.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <boost/property_map/property_map.hpp>

#include <Eigen/QR>

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

#include "shellcontract/core/error.hpp"
#include "shellcontract/geometry/curvature.hpp"
#include "shellcontract/mesh/file_safety.hpp"
#include "shellcontract/mesh/io.hpp"
#include "shellcontract/mesh/properties.hpp"

namespace shellcontract {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

constexpr double PI = 3.14159265358979323846;

/// Read-write property map over a std::vector indexed by the descriptor's idx(), so PMP can
/// work on a const mesh without attaching (and later removing) temporary maps on it.
template <class Key, class T>
struct VectorPropertyMap {
  using key_type = Key;
  using value_type = T;
  using reference = T&;
  using category = boost::read_write_property_map_tag;
  std::vector<T>* values;
  friend T get(const VectorPropertyMap& m, Key k) { return (*m.values)[k.idx()]; }
  friend void put(const VectorPropertyMap& m, Key k, const T& v) { (*m.values)[k.idx()] = v; }
};

/// Vertices within `rings` edge hops of v (v included), by breadth-first search.
/// `mark` is scratch space of size #V holding a stamp per vertex, so no per-call allocation.
void ring_neighbourhood(const Mesh& mesh, VertexIndex v, int rings, std::vector<std::size_t>& mark,
                        std::size_t stamp, std::vector<VertexIndex>& out) {
  out.clear();
  out.push_back(v);
  mark[v.idx()] = stamp;
  std::size_t begin = 0;
  for (int r = 0; r < rings; ++r) {
    const std::size_t end = out.size();
    for (std::size_t i = begin; i < end; ++i)
      for (VertexIndex w : CGAL::vertices_around_target(mesh.halfedge(out[i]), mesh))
        if (mark[w.idx()] != stamp) {
          mark[w.idx()] = stamp;
          out.push_back(w);
        }
    begin = end;
  }
}

/// Area-weighted median of |values| (weights = mixed areas): the smallest |value| such that
/// at least half of the total weight has |value| <= it. 0 when the total weight is 0.
double weighted_median_abs(const Eigen::VectorXd& values, const Eigen::VectorXd& weights) {
  std::vector<Eigen::Index> order(static_cast<std::size_t>(values.size()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::sort(order.begin(), order.end(),
            [&](Eigen::Index a, Eigen::Index b) { return std::abs(values(a)) < std::abs(values(b)); });
  const double total = weights.sum();
  if (!(total > 0.0)) return 0.0;
  double acc = 0.0;
  for (Eigen::Index i : order) {
    acc += weights(i);
    if (acc >= 0.5 * total) return std::abs(values(i));
  }
  return std::abs(values(order.back()));
}

/// A fitted sphere (same length unit as the positions).
struct Sphere {
  Vec3 centre;
  double radius;
};

/// Weighted algebraic least-squares sphere through the points of `group`:
/// minimise sum w_i (|p_i|^2 - 2 c . p_i - d)^2 over (c, d), radius^2 = d + |c|^2 (Pratt's
/// linearisation; exact for points on a sphere). The points are centred and scaled to unit RMS
/// first so the 4x4 system has the same conditioning at every scale.
/// @return nothing when fewer than 4 non-coplanar points (rank < 4) or radius^2 <= 0.
std::optional<Sphere> fit_sphere(const std::vector<VertexIndex>& group, const Positions& x,
                                 const Eigen::VectorXd& weight) {
  if (group.size() < 4) return std::nullopt;
  Vec3 mean = Vec3::Zero();
  for (VertexIndex v : group) mean += Vec3(x.row(static_cast<Eigen::Index>(v.idx())));
  mean /= static_cast<double>(group.size());
  double rms = 0.0;
  for (VertexIndex v : group) rms += (Vec3(x.row(static_cast<Eigen::Index>(v.idx()))) - mean).squaredNorm();
  rms = std::sqrt(rms / static_cast<double>(group.size()));
  if (!(rms > 0.0)) return std::nullopt;  // all points coincide
  Eigen::MatrixXd A(static_cast<Eigen::Index>(group.size()), 4);
  Eigen::VectorXd b(static_cast<Eigen::Index>(group.size()));
  for (std::size_t i = 0; i < group.size(); ++i) {
    const auto j = static_cast<Eigen::Index>(group[i].idx());
    const Vec3 q = (Vec3(x.row(j)) - mean) / rms;
    const double w = std::sqrt(std::max(weight(j), 0.0));
    A.row(static_cast<Eigen::Index>(i)) << 2.0 * w * q.transpose(), w;
    b(static_cast<Eigen::Index>(i)) = w * q.squaredNorm();
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  qr.setThreshold(1e-10);  // relative to the largest pivot: coplanar seeds give rank 3
  if (qr.rank() < 4) return std::nullopt;
  const Eigen::Vector4d sol = qr.solve(b);
  const Vec3 centre = sol.head<3>();
  const double r2 = sol(3) + centre.squaredNorm();
  if (!(r2 > 0.0)) return std::nullopt;
  return Sphere{mean + rms * centre, rms * std::sqrt(r2)};
}

/// What a region file may hold beyond its face ids: comment lines, blank lines, wide spacing.
constexpr std::uint64_t REGION_FILE_SLACK_BYTES = 1 << 20;

std::string line_error(const std::string& path, std::size_t line, const std::string& what) {
  return path + ":" + std::to_string(line) + ": " + what;
}


void check_region_options(const RegionOptions& options) {
  if (options.smoothing_rings < 0) throw UsageError("select_spherical_regions: smoothing_rings must be >= 0");
  if (!(options.fit_distance_tolerance >= 0.0) || !(options.fit_normal_tolerance_deg >= 0.0))
    throw UsageError("select_spherical_regions: fit tolerances must be >= 0");
}

/// Steps 1-4 (header) from the per-vertex H and K (mean_raw, gaussian_raw) and the mixed areas
/// and angle deficits of c, all computed at x.
std::vector<int> select_from_curvature(const Mesh& mesh, const Positions& x, const CurvatureField& c,
                                       const Eigen::VectorXd& mean_raw, const Eigen::VectorXd& gaussian_raw,
                                       const RegionOptions& options, RegionReport* report) {
  const auto nv = static_cast<Eigen::Index>(mesh.number_of_vertices());

  // Step 1: ring averages. H: area-weighted mean; K: total deficit / total mixed area.
  Eigen::VectorXd H = mean_raw, K = gaussian_raw;
  if (options.smoothing_rings > 0) {
    std::vector<std::size_t> mark(static_cast<std::size_t>(nv), 0);
    std::vector<VertexIndex> ring;
    for (VertexIndex v : mesh.vertices()) {
      ring_neighbourhood(mesh, v, options.smoothing_rings, mark, v.idx() + 1, ring);
      double area = 0.0, h_area = 0.0, deficit = 0.0;
      for (VertexIndex w : ring) {
        const auto j = static_cast<Eigen::Index>(w.idx());
        area += c.mixed_area(j);
        h_area += c.mixed_area(j) * mean_raw(j);
        deficit += c.angle_deficit(j);
      }
      const auto i = static_cast<Eigen::Index>(v.idx());
      // Zero area only around degenerate faces: keep the (already zero) raw values there.
      if (area > 0.0) {
        H(i) = h_area / area;
        K(i) = deficit / area;
      }
    }
  }

  // Step 2: seeds. The reference is floored relative to the bounding-box diagonal (scale-free).
  const double diagonal = nv > 0 ? (x.colwise().maxCoeff() - x.colwise().minCoeff()).norm() : 0.0;
  const double floor = diagonal > 0.0 ? RegionOptions::REFERENCE_FLOOR / diagonal : 0.0;
  const double h_ref = std::max(weighted_median_abs(H, c.mixed_area), floor);
  std::vector<char> seed(static_cast<std::size_t>(nv), 0);
  std::size_t seeds = 0;
  for (Eigen::Index i = 0; i < nv; ++i) {
    if (!(H(i) > 0.0 && K(i) > 0.0)) continue;  // convex only (also rejects NaN)
    const double root = std::sqrt(std::max(H(i) * H(i) - K(i), 0.0));
    const double k_max = H(i) + root, k_min = H(i) - root;  // k_max >= H > 0: ratio is defined
    if (k_min < options.min_principal_ratio * k_max) continue;
    if (!(H(i) >= options.min_curvature_contrast * h_ref)) continue;
    seed[static_cast<std::size_t>(i)] = 1;
    ++seeds;
  }

  // Face areas, unit normals and area-weighted H (the patch summaries and the growth need them).
  const std::size_t nf = mesh.number_of_faces();
  std::vector<double> face_area(nf, 0.0), face_h(nf, 0.0);
  std::vector<Vec3> face_normal(nf, Vec3::Zero()), face_centroid(nf, Vec3::Zero());
  std::vector<std::array<Eigen::Index, 3>> corners(nf);
  double total_area = 0.0;
  for (FaceIndex f : mesh.faces()) {
    int k = 0;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      if (k < 3) corners[f.idx()][static_cast<std::size_t>(k++)] = static_cast<Eigen::Index>(v.idx());
    const auto& id = corners[f.idx()];
    const Vec3 p0(x.row(id[0])), p1(x.row(id[1])), p2(x.row(id[2]));
    const Vec3 n = (p1 - p0).cross(p2 - p0);
    const double n_norm = n.norm();
    face_area[f.idx()] = 0.5 * n_norm;
    if (n_norm > 0.0) face_normal[f.idx()] = n / n_norm;  // degenerate faces keep 0 and never grow
    face_centroid[f.idx()] = (p0 + p1 + p2) / 3.0;
    face_h[f.idx()] = (H(id[0]) + H(id[1]) + H(id[2])) / 3.0;
    total_area += face_area[f.idx()];
  }

  // Step 3: each edge-connected group of seed vertices gets a sphere fitted to it; faces that
  // lie on that sphere (corners within the distance tolerance, face normal within the angle
  // tolerance of the outward radial direction at the centroid) grow from the group's one-ring
  // across edges. The seeds alone lose a patch's outer ring (the discrete curvature there mixes
  // in the crease); the one-ring of the seeds spills over the crease; the fitted sphere tells
  // the two apart. The face normal is used, not the vertex normal: a face inscribed in a sphere
  // has its normal through the centre whatever its shape, while a vertex normal at the patch
  // border averages in the faces beyond the crease.
  std::vector<char> selected(nf, 0);
  std::vector<char> visited(static_cast<std::size_t>(nv), 0);
  const double cos_normal = std::cos(options.fit_normal_tolerance_deg * PI / 180.0);
  for (VertexIndex s0 : mesh.vertices()) {
    if (!seed[s0.idx()] || visited[s0.idx()]) continue;
    std::vector<VertexIndex> group{s0};
    visited[s0.idx()] = 1;
    for (std::size_t i = 0; i < group.size(); ++i)
      for (VertexIndex w : CGAL::vertices_around_target(mesh.halfedge(group[i]), mesh))
        if (seed[w.idx()] && !visited[w.idx()]) {
          visited[w.idx()] = 1;
          group.push_back(w);
        }
    const std::optional<Sphere> sphere = fit_sphere(group, x, c.mixed_area);
    if (!sphere) continue;  // fewer than 4 or coplanar seeds: no shape to grow, only noise
    const auto on_sphere = [&](FaceIndex f) {
      for (Eigen::Index i : corners[f.idx()]) {
        const double dist = (Vec3(x.row(i)) - sphere->centre).norm();
        if (!(std::abs(dist - sphere->radius) <= options.fit_distance_tolerance * sphere->radius)) return false;
      }
      const Vec3 radial = face_centroid[f.idx()] - sphere->centre;  // outward: convex side only
      return face_normal[f.idx()].dot(radial) >= cos_normal * radial.norm() && radial.norm() > 0.0;
    };
    std::vector<FaceIndex> front;
    for (VertexIndex v : group)
      for (FaceIndex f : CGAL::faces_around_target(mesh.halfedge(v), mesh))
        if (f != Mesh::null_face() && !selected[f.idx()] && on_sphere(f)) {
          selected[f.idx()] = 1;
          front.push_back(f);
        }
    for (std::size_t i = 0; i < front.size(); ++i)
      for (FaceIndex g : CGAL::faces_around_face(mesh.halfedge(front[i]), mesh))
        if (g != Mesh::null_face() && !selected[g.idx()] && on_sphere(g)) {
          selected[g.idx()] = 1;
          front.push_back(g);
        }
  }

  // Step 4: edge-connected patches of selected faces. An edge is constrained where exactly one
  // side is selected, so every component is all-selected or all-unselected.
  std::vector<char> constrained(mesh.number_of_edges(), 0);
  for (EdgeIndex e : mesh.edges()) {
    const FaceIndex a = mesh.face(mesh.halfedge(e, 0)), b = mesh.face(mesh.halfedge(e, 1));
    const bool sa = a != Mesh::null_face() && selected[a.idx()];
    const bool sb = b != Mesh::null_face() && selected[b.idx()];
    constrained[e.idx()] = sa != sb;
  }
  std::vector<std::size_t> comp_of_face(nf, 0);
  const std::size_t n_components =
      PMP::connected_components(mesh, VectorPropertyMap<FaceIndex, std::size_t>{&comp_of_face},
                                CGAL::parameters::edge_is_constrained_map(VectorPropertyMap<EdgeIndex, char>{&constrained}));

  struct Patch {
    std::vector<int> faces;
    double area = 0.0, h_area = 0.0;
  };
  std::vector<Patch> patches(n_components);
  for (std::size_t f = 0; f < nf; ++f) {
    if (!selected[f]) continue;
    Patch& p = patches[comp_of_face[f]];
    p.faces.push_back(static_cast<int>(f));  // ascending: f runs upward
    p.area += face_area[f];
    p.h_area += face_area[f] * face_h[f];
  }
  RegionReport r;
  r.total_area = total_area;
  r.reference_mean_curvature = h_ref;
  r.seed_vertices = seeds;
  std::vector<Patch> kept;
  for (Patch& p : patches) {
    if (p.faces.empty()) continue;  // an unselected component
    const double fraction = total_area > 0.0 ? p.area / total_area : 0.0;
    if (fraction < options.min_area_fraction) {
      ++r.dropped_small;
    } else if (fraction > options.max_area_fraction) {
      ++r.dropped_large;
    } else {
      kept.push_back(std::move(p));
    }
  }
  std::sort(kept.begin(), kept.end(), [](const Patch& a, const Patch& b) {
    if (a.area != b.area) return a.area > b.area;
    return a.faces.front() < b.faces.front();
  });

  std::vector<int> region(nf, -1);
  for (std::size_t id = 0; id < kept.size(); ++id) {
    const Patch& p = kept[id];
    for (int f : p.faces) region[static_cast<std::size_t>(f)] = static_cast<int>(id);
    RegionSummary s;
    s.faces = p.faces.size();
    s.area = p.area;
    s.area_fraction = total_area > 0.0 ? p.area / total_area : 0.0;
    s.mean_curvature = p.area > 0.0 ? p.h_area / p.area : 0.0;
    s.contrast = h_ref > 0.0 ? s.mean_curvature / h_ref : 0.0;
    r.regions.push_back(s);
  }
  if (report) *report = std::move(r);
  return region;
}

}  // namespace

std::vector<int> select_spherical_regions(const Mesh& mesh, const Positions& x, const RegionOptions& options,
                                          RegionReport* report) {
  check_region_options(options);
  const CurvatureField c = compute_curvature(mesh, x);  // checks garbage and sizes
  return select_from_curvature(mesh, x, c, c.mean, c.gaussian, options, report);
}

std::size_t mark_spherical_regions(Mesh& mesh, const Positions& x, const RegionOptions& options,
                                   RegionReport* report) {
  check_region_options(options);
  const CurvatureField c = compute_curvature(mesh, x);
  store_curvature(mesh, c);
  // H and K as every later reader sees them: from the maps (the mixed areas and deficits that
  // the ring averages weight them with have no map; nothing else uses them).
  const auto H_map = property::get_map<VertexIndex, double>(mesh, property::MEAN_CURVATURE);
  const auto K_map = property::get_map<VertexIndex, double>(mesh, property::GAUSSIAN_CURVATURE);
  Eigen::VectorXd H(static_cast<Eigen::Index>(mesh.number_of_vertices())), K(H.size());
  for (VertexIndex v : mesh.vertices()) {
    H(static_cast<Eigen::Index>(v.idx())) = H_map[v];
    K(static_cast<Eigen::Index>(v.idx())) = K_map[v];
  }
  const std::vector<int> region = select_from_curvature(mesh, x, c, H, K, options, report);
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
  // A face is listed once at most, in at most 20 characters with its separator: a real file is
  // bounded by the mesh. Larger files (a huge sparse file; /dev/zero is refused as a device)
  // are refused before they are read; so are longer lines.
  const std::uint64_t max_line = REGION_FILE_SLACK_BYTES + 21 * static_cast<std::uint64_t>(num_faces);
  const std::uint64_t max_bytes = REGION_FILE_SLACK_BYTES + 64 * static_cast<std::uint64_t>(num_faces);
  const std::string bytes = read_regular_file(path, max_bytes);
  std::vector<std::vector<int>> regions;
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
    while (tokens >> token) {
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
    regions.push_back(std::move(region));
  }
  return regions;
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
