// The readers' shared geometric steps on a checked soup (soup_geometry.hpp).
#include "mesh/soup_geometry.hpp"

#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/property_map.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "core/classic_locale.hpp"
#include "core/plural.hpp"
#include "mesh/eigen_point_map.hpp"
#include "mesh/normalization.hpp"
#include "mesh/seam_weld.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract::soup {

namespace PMP = CGAL::Polygon_mesh_processing;

bool UnitPoints::usable() const { return std::isfinite(diagonal) && diagonal > 0.0; }

UnitPoints unit_points(const std::vector<Point3>& points) {
  UnitPoints u;
  if (points.empty()) return u;
  Vec3 lo = to_vec(points[0]), hi = lo;
  for (const Point3& p : points) {
    lo = lo.cwiseMin(to_vec(p));
    hi = hi.cwiseMax(to_vec(p));
  }
  // compute_normalization's centre and diagonal, so that the readers and the simulator see the
  // same numbers.
  const Vec3 centre = 0.5 * lo + 0.5 * hi;
  u.diagonal = bounding_diagonal(lo, hi);
  u.scale = u.usable() ? u.diagonal : 1.0;
  u.unit.reserve(points.size());
  for (const Point3& p : points) {
    const Vec3 q = (to_vec(p) - centre) / u.scale;
    u.unit.emplace_back(q.x(), q.y(), q.z());
  }
  return u;
}

Mesh soup_mesh(const std::vector<Point3>& points, const std::vector<Polygon>& tris, const std::string& who) {
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, tris, mesh);
  if (mesh.number_of_faces() != tris.size())
    throw std::logic_error(who + ": polygon_soup_to_polygon_mesh dropped faces of a checked soup");
  for (const FaceIndex f : mesh.faces()) {
    const Polygon& t = tris[f.idx()];
    HalfedgeIndex h = mesh.halfedge(f);
    for (int k = 0; k < 3 && mesh.target(h).idx() != t[0]; ++k) h = mesh.next(h);
    if (mesh.target(h).idx() != t[0] || mesh.target(mesh.next(h)).idx() != t[1] ||
        mesh.target(mesh.next(mesh.next(h))).idx() != t[2])
      throw std::logic_error(who + ": face " + std::to_string(f.idx()) + " lost its input vertex order");
    mesh.set_halfedge(f, h);
  }
  return mesh;
}

Orientation orient_components(Mesh& mesh, const std::vector<Point3>& points,
                              std::vector<Polygon>& tris, const std::vector<Point3>& unit,
                              double scale, bool reorient, const std::string& who,
                              std::vector<std::string>& warnings,
                              const std::vector<std::size_t>* number) {
  const std::size_t nf = tris.size();
  std::vector<std::size_t> component_face(nf);
  Orientation out;
  out.components = PMP::connected_components(mesh, CGAL::make_property_map(component_face));
  if (!reorient) return out;
  std::vector<double> six_volume(out.components, 0.0);
  std::vector<Vec3> origin_point(out.components);
  std::vector<char> has_origin(out.components, 0);
  std::vector<Eigen::AlignedBox3d> box(out.components);
  for (std::size_t f = 0; f < nf; ++f) {
    const std::size_t c = component_face[f];
    for (int k = 0; k < 3; ++k) box[c].extend(to_vec(unit[tris[f][k]]));
    // Measured from a point of the component: the closed-surface sum does not depend on the
    // origin, and a nearby one avoids cancellation for components far from the centre.
    if (!has_origin[c]) {
      origin_point[c] = to_vec(unit[tris[f][0]]);
      has_origin[c] = 1;
    }
    const Vec3 a = to_vec(unit[tris[f][0]]) - origin_point[c];
    const Vec3 b = to_vec(unit[tris[f][1]]) - origin_point[c];
    const Vec3 d = to_vec(unit[tris[f][2]]) - origin_point[c];
    six_volume[c] += a.dot(b.cross(d));
  }
  std::vector<char> flat(out.components, 0);
  for (std::size_t c = 0; c < out.components; ++c) {
    const double diagonal = box[c].diagonal().norm();
    flat[c] =
        !(std::abs(six_volume[c]) / 6.0 >= FLAT_COMPONENT_VOLUME * diagonal * diagonal * diagonal);
    if (!flat[c] || !out.flat.empty()) continue;
    for (std::size_t f = 0; f < nf; ++f)
      if (component_face[f] == c) out.flat_faces.push_back(f);
    ClassicOStringStream w;
    w << "component " << c << " (" << out.flat_faces.size() << " faces, starting at face "
      << out.flat_faces[0] << ") encloses no volume ("
      << six_volume[c] / 6.0 * scale * scale * scale
      << "): it is flat or collapsed, and the pressure would push its sides through each other";
    std::vector<char> in_component(points.size(), 0);
    std::vector<std::size_t> ids;
    for (const std::size_t f : out.flat_faces)
      for (int k = 0; k < 3; ++k)
        if (!in_component[tris[f][k]]) {
          in_component[tris[f][k]] = 1;
          ids.push_back(tris[f][k]);
        }
    out.flat = w.str() + stray_vertices_note(points, std::move(ids), number);
  }
  // One pass over the faces for every inside-out component (a pass per component was quadratic
  // in a file of many small inverted parts), and one warning line for more than MAX_LISTED.
  std::vector<std::size_t> first(out.components, nf), count(out.components, 0), flipped;
  for (std::size_t c = 0; c < out.components; ++c)
    if (six_volume[c] < 0.0 && !flat[c]) flipped.push_back(c);
  for (std::size_t f = 0; f < nf && !flipped.empty(); ++f) {
    const std::size_t c = component_face[f];
    if (six_volume[c] >= 0.0 || flat[c]) continue;
    std::swap(tris[f][1], tris[f][2]);
    first[c] = std::min(first[c], f);
    ++count[c];
  }
  out.reoriented = !flipped.empty();
  const auto volume = [&](std::size_t c) { return six_volume[c] / 6.0 * scale * scale * scale; };
  if (flipped.size() <= MAX_LISTED) {
    for (const std::size_t c : flipped) {
      ClassicOStringStream w;
      w << "component " << c << " (" << count[c] << " faces, starting at face " << first[c]
        << ") was inside-out (signed volume " << volume(c) << "); its faces were flipped";
      warnings.push_back(w.str());
    }
  } else {
    ClassicOStringStream w;
    w << flipped.size() << " components were inside-out; their faces were flipped: ";
    for (std::size_t i = 0; i < MAX_LISTED; ++i) {
      const std::size_t c = flipped[i];
      // The face numbers in the one-component form's words, "(N faces, starting at face F)",
      // which front ends rewrite in their own terms (the Blender add-on's polygons).
      w << "component " << c << " (" << count[c] << " faces, starting at face " << first[c]
        << ") of signed volume " << volume(c) << ", ";
    }
    w << "and " << flipped.size() - MAX_LISTED << " more";
    warnings.push_back(w.str());
  }
  // Rebuilt from the flipped soup (rare: only inside-out input pays for a second build).
  if (out.reoriented) mesh = soup_mesh(points, tris, who);
  return out;
}

namespace {

Eigen::AlignedBox3d box_of(const std::vector<Point3>& points, const std::vector<std::size_t>& ids,
                           std::size_t n) {
  Eigen::AlignedBox3d box;
  for (std::size_t i = 0; i < n; ++i) box.extend(to_vec(points[ids[i]]));
  return box;
}

}  // namespace

std::string stray_vertices_note(const std::vector<Point3>& points,
                                const std::vector<std::size_t>* number) {
  std::vector<std::size_t> all(points.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  return stray_vertices_note(points, std::move(all), number);
}

std::string stray_vertices_note(const std::vector<Point3>& points, std::vector<std::size_t> ids,
                                const std::vector<std::size_t>* number) {
  // The others are the vertices nearest the per-axis median (which strays do not move), so that
  // two strays at one place are found together, where taking one out at a time would not shrink
  // the box.
  if (ids.size() < STRAY_VERTICES_MAX + 4) return "";
  Vec3 median;
  for (int a = 0; a < 3; ++a) {
    std::vector<double> c(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) c[i] = to_vec(points[ids[i]])[a];
    std::nth_element(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(c.size() / 2), c.end());
    median[a] = c[c.size() / 2];
  }
  std::stable_sort(ids.begin(), ids.end(), [&](std::size_t a, std::size_t b) {
    return (to_vec(points[a]) - median).squaredNorm() < (to_vec(points[b]) - median).squaredNorm();
  });
  const double whole = box_of(points, ids, ids.size()).diagonal().norm();
  if (!(whole > 0.0) || !std::isfinite(whole)) return "";
  for (std::size_t k = 1; k <= STRAY_VERTICES_MAX; ++k) {
    const Eigen::AlignedBox3d rest = box_of(points, ids, ids.size() - k);
    const double extent = rest.diagonal().norm();
    if (!(extent < STRAY_VERTICES_EXTENT * whole)) continue;
    ClassicOStringStream s;
    s << std::setprecision(9) << "; " << (k == 1 ? "vertex " : "vertices ");
    for (std::size_t i = ids.size() - k; i < ids.size(); ++i) {
      const Vec3 p = to_vec(points[ids[i]]);
      s << (i + k == ids.size() ? "" : ", ") << (number ? (*number)[ids[i]] : ids[i]) << " at ("
        << p.x() << ", " << p.y() << ", " << p.z() << ")";
    }
    const Vec3 far = to_vec(points[ids.back()]);
    s << std::setprecision(3) << (k == 1 ? " lies " : " lie up to ") << rest.exteriorDistance(far)
      << " from the other vertices, whose bounding box has a diagonal of " << extent
      << ": the test is relative to the whole diagonal, which "
      << (k == 1 ? "this vertex holds" : "these hold") << "; remove " << (k == 1 ? "it" : "them")
      << " (a stray point) from the input";
    return s.str();
  }
  return "";
}

std::vector<std::size_t> zero_area_faces(const std::vector<Polygon>& tris, const std::vector<Point3>& unit) {
  const std::size_t nf = tris.size();
  std::vector<std::size_t> zero_area;
  if (nf == 0) return zero_area;
  double edge_sum = 0.0;
  for (const Polygon& t : tris)
    for (int k = 0; k < 3; ++k) edge_sum += (to_vec(unit[t[k]]) - to_vec(unit[t[(k + 1) % 3]])).norm();
  const double mean_edge = edge_sum / (3.0 * static_cast<double>(nf));
  const double threshold = ZERO_AREA_RELATIVE * mean_edge * mean_edge;
  for (std::size_t f = 0; f < nf; ++f) {
    const Vec3 a = to_vec(unit[tris[f][0]]);
    const double twice_area = (to_vec(unit[tris[f][1]]) - a).cross(to_vec(unit[tris[f][2]]) - a).norm();
    if (twice_area < threshold) zero_area.push_back(f);
  }
  return zero_area;
}

Mesh accept_triangles(const std::string& path, std::vector<Point3>& points,
                      std::vector<Polygon>& tris, UnitPoints& normalized, const Namer& name,
                      const AcceptOptions& options, InputReport* report) {
  // Connectivity, in the order of the problems' importance (each names what it finds). A soup
  // that is open only along split seams is simulated welded (seam_weld.hpp).
  const std::size_t nv = points.size();
  std::optional<SeamWeld> weld;
  try {
    check_no_duplicate_face(path, tris, name);
    check_edges(path, tris, nv, name);
    check_no_isolated_vertex(path, tris, nv, name);
    check_vertex_fans(path, tris, nv, name);
  } catch (const InputError& refusal) {
    // Or throws the refusal, with what is left after welding.
    weld = weld_seams(path, points, tris, refusal, name);
  }
  std::vector<Polygon> input_tris;
  if (weld) {
    input_tris = std::move(tris);
    tris = weld->tris;
    points = weld->points;
    normalized = unit_points(points);  // the same box: the copies are at its points
  }

  // The soup is now what polygon_soup_to_polygon_mesh requires (in release builds it only
  // asserts that): each condition of PMP::is_polygon_soup_a_polygon_mesh is one of the checks
  // above (tests/mesh/test_soup_checks_vs_cgal.cpp compares them on mutated soups). CGAL's test
  // itself is not run again: its std::set of directed edges is a large share of reading a large
  // mesh (lab/pages/scale.md, lab/history.md). A gap in our checks cannot become undefined
  // behaviour: Euler::add_face returns a null face for a face it cannot add, and soup_mesh
  // refuses a mesh that lost a face or a face's corner order.
  if (!normalized.usable())
    fail(path, "degenerate mesh",
         normalized.diagonal == 0.0
             ? "zero bounding-box diagonal: every vertex is at " + name.point(0)
             : "non-finite bounding-box diagonal: the coordinates span more than a double holds");
  Mesh mesh = soup_mesh(points, tris, options.who);
  std::vector<std::string> warnings;
  // A welded vertex is named by its first copy, as the connectivity refusals name it.
  std::vector<std::size_t> first_copy;
  if (weld) {
    first_copy.resize(weld->points.size());
    for (std::size_t i = weld->welded_of.size(); i-- > 0;) first_copy[weld->welded_of[i]] = i;
  }
  const std::vector<std::size_t>* number = weld ? &first_copy : nullptr;
  const Orientation oriented =
      orient_components(mesh, points, tris, normalized.unit, normalized.scale, options.reorient,
                        options.who, warnings, number);
  if (weld) store_input_corners(mesh, *weld, input_tris);
  if (!options.split_warning.empty()) warnings.push_back(options.split_warning);
  std::vector<std::size_t> zero_area = zero_area_faces(tris, normalized.unit);
  if (!zero_area.empty())
    warnings.push_back(counted(zero_area.size(), "face", "faces") +
                       one_or_many(zero_area.size(), " has", " have") +
                       " (nearly) zero area: " + list_indices(zero_area));

  // What the simulator needs beyond a closed manifold (one decision for `check`, `run` and the
  // arrays): a bounding box to normalize by (checked above, before building the mesh), and a
  // positive volume, measured exactly as the simulator does: validation's enclosed_volume is this
  // same PMP::volume call, made here directly so that mesh/ does not depend on validation/.
  const Positions x = positions_from_mesh(mesh);
  const Positions unit_x = normalize(x, compute_normalization(x));
  const double unit_volume =
      PMP::volume(mesh, CGAL::parameters::vertex_point_map(EigenPointMap(unit_x)));
  if (options.reorient && !(unit_volume > 0.0)) {
    ClassicOStringStream v;
    v << unit_volume;
    fail(path, "no positive volume",
         "the mesh encloses no positive volume (" + v.str() +
             " at a unit bounding-box diagonal): it is flat or degenerate" +
             stray_vertices_note(points, number));
  }
  // After the whole's volume, which names a single flat shell as before.
  if (!oriented.flat.empty())
    fail_faces(path, "component with no volume", oriented.flat, oriented.flat_faces);

  if (report) {
    report->vertices = mesh.number_of_vertices();
    report->faces = mesh.number_of_faces();
    report->triangulated_faces = options.triangulated;
    report->zero_area_faces = std::move(zero_area);
    report->reoriented = oriented.reoriented;
    report->components = oriented.components;
    // In input units; beyond about 1e102 per coordinate the cube of the scale overflows to inf.
    report->volume = unit_volume * normalized.scale * normalized.scale * normalized.scale;
    report->warnings = std::move(warnings);
    report->welded_vertices = weld ? weld->copies() : 0;
    report->notes.clear();
    if (weld) report->notes.push_back(weld_note(*weld, options.gltf));
  }
  return mesh;
}

}  // namespace shellcontract::soup
