#include "mesh/reconstruction.hpp"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_with_circumcenter_3.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Random.h>
#include <CGAL/Robust_circumcenter_traits_3.h>
#include <CGAL/Surface_mesh_cell_base_3.h>
#include <CGAL/Surface_mesh_vertex_base_3.h>
#include <CGAL/Triangulation_data_structure_3.h>
#include <CGAL/assertions.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/poisson_surface_reconstruction.h>
#include <CGAL/property_map.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <new>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/decimal_text.hpp"
#include "core/memory_error.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/ply_reader.hpp"
#include "mesh/point_set_checks.hpp"
#include "mesh/read_polygon_soup.hpp"
#include "mesh/reconstruction_checks.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"  // shortest_text

namespace shellcontract {

namespace {

using Vector3 = Kernel::Vector_3;

/// The lines "x y z nx ny nz" of a text point set (blank lines and '#' comments skipped), each
/// checked here so that a bad line is named: CGAL's reader took three numbers as a point with no
/// normal (the solve then never ended) and printed its own message without the file.
void read_point_lines(const std::string& path, OrientedPoints& points) {
  std::istringstream in(read_regular_file(path));
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    std::vector<double> v;
    for (std::string token; fields >> token;) {
      double x = 0.0;
      if (!parse_c_number(token, x) || !std::isfinite(x))
        throw InputError(path + ": line " + std::to_string(number) + ": '" + printable(token) + "' is not a finite number");
      v.push_back(x);
    }
    if (v.size() != 6)
      throw InputError(path + ": line " + std::to_string(number) + ": " + std::to_string(v.size()) +
                       " numbers; an oriented point set has 6 per line (x y z nx ny nz)");
    if (v[3] == 0.0 && v[4] == 0.0 && v[5] == 0.0)
      throw InputError(path + ": line " + std::to_string(number) + ": the normal is zero");
    points.points.emplace_back(Point3(v[0], v[1], v[2]), Vector3(v[3], v[4], v[5]));
    points.lines.push_back(number);
  }
}

/// The oriented points of `path`: PLY through our reader (CGAL 5.5's crashes, see ply_reader),
/// anything else as text lines (read_point_lines), with allocation failures turned into an
/// InputError naming the file.
OrientedPoints read_oriented_points(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  OrientedPoints points;
  points.path = path;
  // A regular file or nothing: CGAL's reader would read /dev/zero or a FIFO until memory ends.
  regular_file_size(path);
  if (ext == ".ply") {
    const PlyData d = read_ply(path, read_file_bytes(path));
    if (d.normals.size() != d.points.size())
      throw InputError(path + ": no normals: the vertex element has no nx, ny, nz properties; need an oriented point set");
    points.points.reserve(d.points.size());
    for (std::size_t i = 0; i < d.points.size(); ++i)
      points.points.emplace_back(Point3(d.points[i][0], d.points[i][1], d.points[i][2]),
                                 Vector3(d.normals[i][0], d.normals[i][1], d.normals[i][2]));
  } else {
    try {
      read_point_lines(path, points);
    } catch (const std::bad_alloc&) {
      throw OutOfMemoryError(path + ": out of memory: reading its " +
                             std::to_string(points.points.size()) +
                             " points needs more memory than there is");
    }
  }
  // Poisson reconstruction needs finite points and normals: a NaN would poison the solve.
  for (std::size_t i = 0; i < points.points.size(); ++i) {
    const Point3& p = points.points[i].first;
    const Vector3& n = points.points[i].second;
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()) || !std::isfinite(n.x()) ||
        !std::isfinite(n.y()) || !std::isfinite(n.z()))
      throw InputError(path + ": " + points.where(i) + ": a non-finite coordinate or normal");
  }
  return points;
}

using PoissonFunction = CGAL::Poisson_reconstruction_function<Kernel>;

/// A hint for a failed reconstruction whose points all lie on one sphere (the least-squares
/// sphere |p|^2 = 2 c.p + k through them, to 1e-9 of its radius; "" otherwise). Cospherical
/// points are the Delaunay triangulation's degenerate case: every tetrahedron has the same
/// circumsphere. The reconstruction failed (the mesher found an open surface) for evenly
/// spread points (a Fibonacci lattice) on a sphere with exact normals, while the same points
/// with a little noise went through (an icosphere's vertices, also on one sphere, go through as
/// they are).
std::string cospherical_hint(const std::vector<PointWithNormal>& points) {
  if (points.size() < 5) return "";
  Eigen::MatrixX4d a(static_cast<Eigen::Index>(points.size()), 4);
  Eigen::VectorXd b(a.rows());
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    const Point3& p = points[static_cast<std::size_t>(i)].first;
    a.row(i) << 2 * p.x(), 2 * p.y(), 2 * p.z(), 1.0;
    b(i) = p.x() * p.x() + p.y() * p.y() + p.z() * p.z();
  }
  const Eigen::Vector4d fit = a.colPivHouseholderQr().solve(b);
  const Eigen::Vector3d c = fit.head<3>();
  const double r_sq = fit(3) + c.squaredNorm();
  if (!(r_sq > 0.0) || !std::isfinite(r_sq)) return "";
  const double r = std::sqrt(r_sq);
  for (const PointWithNormal& pn : points) {
    const Eigen::Vector3d p(pn.first.x(), pn.first.y(), pn.first.z());
    if (!(std::abs((p - c).norm() - r) <= 1e-9 * r)) return "";
  }
  return ": the points all lie on one sphere, a degenerate case for the Delaunay triangulation "
         "the solve is built on; a little noise on the points may get through";
}

/// The value of a PoissonFunction at a point: CGAL 5.5's operator() repeated line for line (same
/// locate, same barycentric arithmetic, so the same values), because CGAL's own binds a reference
/// to a null pointer (Cell_hint::get, Poisson_reconstruction_function.h:265) on the first call of
/// every copy, which has no hint yet: undefined behaviour that UBSan reports (scripts/sanitize.sh).
/// Fixed in CGAL after 5.5 (CGAL/cgal commit 9cd4535b, issue 8260); this avoids it without a
/// sanitizer suppression. Like CGAL's, a copy starts without a hint (the surface mesher copies it).
class PoissonValue {
 public:
  using Cell_handle = PoissonFunction::Cell_handle;
  explicit PoissonValue(const PoissonFunction& function) : function_(&function) {}
  PoissonValue(const PoissonValue& other) : function_(other.function_) {}
  PoissonValue& operator=(const PoissonValue& other) {
    function_ = other.function_;
    hint_ = Cell_handle();
    return *this;
  }

  Kernel::FT operator()(const Point3& p) const {
    const PoissonFunction::Triangulation& tr = function_->tr();
    hint_ = tr.locate(p, hint_);  // a null handle means no hint, as in CGAL
    if (tr.is_infinite(hint_)) {
      const int i = hint_->index(tr.infinite_vertex());
      return hint_->vertex((i + 1) & 3)->f();
    }
    const Point3& pd = hint_->vertex(3)->point();
    const Vector3 va = hint_->vertex(0)->point() - pd;
    const Vector3 vb = hint_->vertex(1)->point() - pd;
    const Vector3 vc = hint_->vertex(2)->point() - pd;
    Kernel::FT m[9];
    CGAL::internal::invert(va.x(), va.y(), va.z(), vb.x(), vb.y(), vb.z(), vc.x(), vc.y(), vc.z(), m[0], m[1], m[2],
                           m[3], m[4], m[5], m[6], m[7], m[8]);
    const Vector3 vp = p - pd;
    const Kernel::FT a = m[0] * vp.x() + m[3] * vp.y() + m[6] * vp.z();
    const Kernel::FT b = m[1] * vp.x() + m[4] * vp.y() + m[7] * vp.z();
    const Kernel::FT c = m[2] * vp.x() + m[5] * vp.y() + m[8] * vp.z();
    const Kernel::FT d = 1 - (a + b + c);
    return a * hint_->vertex(0)->f() + b * hint_->vertex(1)->f() + c * hint_->vertex(2)->f() +
           d * hint_->vertex(3)->f();
  }

 private:
  const PoissonFunction* function_;
  mutable Cell_handle hint_;
};

/// A triangulation vertex or cell base `Base` with a creation stamp. CGAL's handles compare by
/// Compact_container's Time_stamper::less: by address unless the element declares Has_timestamp
/// (as Mesh_3's bases do). The surface mesher picks its next bad vertex, bad edge and bad facet from
/// containers ordered by handle (Surface_mesher_manifold.h's std::set<Vertex_handle>,
/// Surface_mesher_regular_edges.h's set of vertex pairs, Surface_mesher.h's Double_map of facets),
/// so with addresses the refinement order, and on degenerate input the outcome, followed wherever
/// malloc put the triangulation's blocks: a second call in one process, reusing the first call's
/// freed memory, ended otherwise than the first. With stamps the order is that of creation.
template <class Base>
class Stamped : public Base {
 public:
  using Has_timestamp = CGAL::Tag_true;
  template <class Tds2>
  struct Rebind_TDS {
    using Other = Stamped<typename Base::template Rebind_TDS<Tds2>::Other>;
  };
  using Base::Base;
  Stamped() = default;
  // A copy is another element: the container stamps it when it is inserted (stamp -1: none yet).
  Stamped(const Stamped& other) : Base(other) {}
  Stamped& operator=(const Stamped& other) {
    Base::operator=(other);
    return *this;
  }
  ~Stamped() = default;
  std::size_t time_stamp() const { return time_stamp_; }
  void set_time_stamp(const std::size_t& stamp) { time_stamp_ = stamp; }

 private:
  std::size_t time_stamp_ = std::size_t(-1);
};

/// CGAL's Surface_mesh_default_triangulation_3_generator (Surface_mesh_default_triangulation_3.h)
/// with stamped vertices and cells.
using MesherTraits = CGAL::Robust_circumcenter_traits_3<Kernel>;
using MesherTds = CGAL::Triangulation_data_structure_3<
    Stamped<CGAL::Surface_mesh_vertex_base_3<MesherTraits>>,
    Stamped<CGAL::Delaunay_triangulation_cell_base_with_circumcenter_3<
        MesherTraits, CGAL::Surface_mesh_cell_base_3<MesherTraits>>>>;
using MesherTriangulation = CGAL::Delaunay_triangulation_3<MesherTraits, MesherTds>;

/// CGAL::poisson_surface_reconstruction_delaunay (CGAL 5.5, poisson_surface_reconstruction.h)
/// with one more check: when the surface mesher finds vertices but no facet, CGAL's
/// facets_in_complex_2_to_triangle_mesh segfaults on the empty complex (400 points on a unit
/// sphere did it); here that is a failed reconstruction.
/// @throws InputError naming `path` when CGAL's mesher fails one of its own checks
bool poisson_delaunay(const std::string& path, const std::vector<PointWithNormal>& points, Mesh& mesh,
                      double spacing, const ReconstructionOptions& options) {
  using Tr = MesherTriangulation;
  using C2t3 = CGAL::Surface_mesh_complex_2_in_triangulation_3<Tr>;
  using Surface = CGAL::Implicit_surface_3<Kernel, PoissonValue>;
  // The mesher's initial points (Implicit_surface_oracle_3's Construct_initial_points) draw from
  // CGAL's default generator, which CGAL seeds with the clock and which keeps its state between
  // calls: seeded here. The mesher's refinement order, which followed the heap, is fixed by the
  // stamps of MesherTriangulation (Stamped).
  CGAL::get_default_random() = CGAL::Random(0);
  PoissonFunction function(points.begin(), points.end(), CGAL::First_of_pair_property_map<PointWithNormal>(),
                    CGAL::Second_of_pair_property_map<PointWithNormal>());
  if (!function.compute_implicit_function()) return false;
  const Point3 inner = function.get_inner_point();
  const double radius = 5.0 * CGAL::approximate_sqrt(function.bounding_sphere().squared_radius());
  const double dichotomy_error = options.distance * spacing / 1000.0;
  const Surface surface(PoissonValue(function), Kernel::Sphere_3(inner, radius * radius), dichotomy_error / radius);
  const CGAL::Surface_mesh_default_criteria_3<Tr> criteria(options.angle, options.radius * spacing,
                                                           options.distance * spacing);
  Tr tr;
  C2t3 c2t3(tr);
  try {
    CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Manifold_with_boundary_tag());
  } catch (const CGAL::Failure_exception& e) {
    // Fine criteria near a sharp fold can make the oracle return a point already inserted, which
    // CGAL's mesher asserts against ("is already inserted on surface"); that ended the process.
    std::string why = e.message().empty() ? e.expression() : e.message();
    while (!why.empty() && std::isspace(static_cast<unsigned char>(why.back()))) why.pop_back();
    throw InputError(path + ": Poisson surface reconstruction failed: CGAL's surface mesher stopped (" + why +
                     "); a larger distance or radius may get through");
  }
  if (tr.number_of_vertices() == 0 || c2t3.number_of_facets() == 0) return false;
  CGAL::facets_in_complex_2_to_triangle_mesh(c2t3, mesh);
  return true;
}

/// The mesh with its faces in a canonical order: each face rotated to start at its smallest
/// vertex index (orientation kept), the faces sorted by their three indices. CGAL's export
/// (facets_in_complex_2_to_triangle_mesh) lists the facets of a std::set ordered by cell
/// address, so the same surface came out in another face order whenever the allocator placed
/// the triangulation's cells differently (another malloc setting, another process history).
/// The vertices come in the triangulation's container order, which follows its insertions, not
/// addresses: they are kept as they are.
Mesh with_canonical_face_order(const Mesh& mesh) {
  using Corners = std::array<Mesh::size_type, 3>;
  std::vector<Corners> faces;
  faces.reserve(mesh.number_of_faces());
  for (const FaceIndex f : mesh.faces()) {
    Corners c{};
    std::size_t k = 0;
    for (const VertexIndex v : vertices_around_face(mesh.halfedge(f), mesh)) c[k++] = v.idx();
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    faces.push_back(c);
  }
  std::sort(faces.begin(), faces.end());
  Mesh out;
  out.reserve(mesh.number_of_vertices(), mesh.number_of_edges(), mesh.number_of_faces());
  for (const VertexIndex v : mesh.vertices()) out.add_vertex(mesh.point(v));
  for (const Corners& c : faces)
    if (out.add_face(VertexIndex(c[0]), VertexIndex(c[1]), VertexIndex(c[2])) == Mesh::null_face())
      throw std::logic_error("with_canonical_face_order: a face of a closed manifold mesh was refused");
  return out;
}

/// "NAME VALUE is not WHAT" as a UsageError.
[[noreturn]] void refuse(const std::string& name, double value, const std::string& what) {
  throw UsageError(name + " " + shortest_text(value) + ": " + what);
}

}  // namespace

void check_reconstruction_options(const ReconstructionOptions& o, const std::string& prefix) {
  // CGAL's surface mesher (Boissonnat and Oudot's Delaunay refinement) is guaranteed to end only
  // for an angular bound of at most 30 degrees (CGAL manual, 3D Surface Mesh Generation,
  // "Meshing Criteria"). 0 switches the angle criterion off. A negative bound is not refused by
  // CGAL: its criterion squares the sine, so -40 would act as 40.
  if (!(o.angle >= 0.0 && o.angle <= RECONSTRUCTION_MAX_ANGLE))
    refuse(prefix + "angle", o.angle,
           "the smallest triangle angle must be a number in [0, 30] degrees (CGAL's surface mesher "
           "is guaranteed to end only up to 30; 0: no angle bound)");
  // The radius bound is the largest surface Delaunay ball, x the average point spacing (the
  // spacing this file computes from the points). The vertices grow as 1 / radius^2 and
  // triangles much smaller than the spacing show nothing of the points that larger ones do not,
  // so half the spacing is the floor: a smaller one only makes the refinement run away.
  // CGAL reads 0 as "no bound"; here the option is a size and 0 is refused with the rest.
  // The upper bound keeps radius x spacing finite (coordinates are at most 1e30: checked_points).
  if (!(o.radius >= RECONSTRUCTION_MIN_RADIUS && o.radius <= RECONSTRUCTION_MAX_SPACINGS))
    refuse(prefix + "radius", o.radius,
           "the largest triangle size is a multiple of the average point spacing and must be a "
           "number in [0.5, 1e6] (below half the spacing the refinement runs away)");
  // The distance bound is the largest distance between a facet's circumcentre and its surface
  // Delaunay ball's centre, x the average spacing; it also sets the implicit surface oracle's
  // bisection error (distance x spacing / 1000, poisson_delaunay), so 0 makes that bisection
  // never reach its error and the mesher never end. Where the surface bends, the vertices grow
  // as 1 / distance, and bounds far below the spacing make the oracle return points already
  // inserted (a CGAL assertion): a tenth of the spacing is the floor.
  if (!(o.distance >= RECONSTRUCTION_MIN_DISTANCE && o.distance <= RECONSTRUCTION_MAX_SPACINGS))
    refuse(prefix + "distance", o.distance,
           "the approximation error is a multiple of the average point spacing and must be a "
           "number in [0.1, 1e6] (0 never ends; below a tenth of the spacing the refinement "
           "runs away)");
  if (o.spacing_neighbours < 1)
    throw UsageError(prefix + "spacing_neighbours " + std::to_string(o.spacing_neighbours) +
                     ": the neighbours of the average spacing estimate must be at least 1");
}

Mesh reconstruct_from_oriented_points(const std::string& path, const ReconstructionOptions& options) {
  check_reconstruction_options(options);
  // Each position once, with its first line's normal: the solve's triangulation keeps one vertex
  // per position anyway (whichever it meets first), and repeated positions made the average
  // spacing, hence the triangles, smaller, down to zero.
  const OrientedPoints input = read_oriented_points(path);
  std::vector<std::size_t> kept;
  const std::vector<PointWithNormal> points =
      checked_points(input, options.spacing_neighbours, &kept);
  const double spacing = CGAL::compute_average_spacing<CGAL::Sequential_tag>(
      points, options.spacing_neighbours,
      CGAL::parameters::point_map(CGAL::First_of_pair_property_map<PointWithNormal>()));
  // Normals at odds with their neighbours' on a large share of the points make no surface: the
  // solve and the mesher ran for minutes on a dense set before the checks after them refused it.
  const std::string at_odds = inconsistent_normals_hint(
      input, kept, points, options.spacing_neighbours, REFUSED_AGAINST_NEIGHBOURS_SHARE);
  if (!at_odds.empty()) throw InputError(path + ": no surface reconstructed" + at_odds);
  // A failure on inconsistently oriented normals is blamed on them, not on the criteria or on the
  // points' layout (random normals on points of one sphere got the cospherical hint).
  const auto failure_hint = [&] {
    const std::string normals =
        inconsistent_normals_hint(input, kept, points, options.spacing_neighbours);
    return normals.empty() ? cospherical_hint(points) : normals;
  };
  Mesh mesh;
  bool found = false;
  try {
    found = spacing > 0.0 && poisson_delaunay(path, points, mesh, spacing, options);
  } catch (const InputError& e) {
    const std::string normals =
        inconsistent_normals_hint(input, kept, points, options.spacing_neighbours);
    if (normals.empty()) throw;
    throw InputError(path + ": Poisson surface reconstruction failed" + normals);
  }
  if (!found)
    throw InputError(path + ": Poisson surface reconstruction failed (no surface found)" +
                     failure_hint());
  if (!CGAL::is_closed(mesh) || !CGAL::is_triangle_mesh(mesh))
    throw InputError(path + ": the reconstructed surface is not a closed triangle mesh" +
                     failure_hint());
  // Outward orientation, as the simulator expects (math-spec 1.1).
  if (!CGAL::Polygon_mesh_processing::is_outward_oriented(mesh))
    CGAL::Polygon_mesh_processing::reverse_face_orientations(mesh);
  mesh.collect_garbage();
  Mesh result = with_canonical_face_order(mesh);
  // The mesher meshes the surface around one inner point: a separate object is left out, and
  // inconsistent normals give a surface of folds and tunnels, both closed and both accepted so far.
  check_surface_fits_points(input, kept, points, result, spacing, options.distance);
  return result;
}

}  // namespace shellcontract
