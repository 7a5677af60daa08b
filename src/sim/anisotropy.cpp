#include "sim/anisotropy.hpp"

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "core/power_of_two.hpp"
#include "fem/triangle_element.hpp"
#include "mesh/properties.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/regions.hpp"

namespace shellcontract {

Vec2 fiber_in_rest_frame(const Vec3& d, const Vec3& T1, const Vec3& T2, bool& fallback) {
  // d scaled by a power of two (exact) to a largest component in [0.5, 1): the norms below can
  // then neither overflow (--fiber 1e200,0,0 gave an infinite length and no fibre) nor underflow
  // (1e-200), and the direction keeps its bits.
  const Vec3 u = d.allFinite() ? Vec3(times_power_of_two(d, -binary_exponent(d.cwiseAbs().maxCoeff()))) : d;
  const Vec2 a(u.dot(T1), u.dot(T2));
  const double len = a.norm();
  fallback = !(len >= 1e-3 * u.norm()) || !(len > 0.0);
  return fallback ? Vec2(1.0, 0.0) : Vec2(a / len);
}

AnisotropyReport add_anisotropic_constraints(Mesh& mesh, const AnisotropyOptions& options,
                                             ConstraintSet& set) {
  AnisotropyReport report;
  const auto rest = property::get_map<FaceIndex, TriangleRest>(mesh, property::TRIANGLE_REST);
  // Rest data, attached once like f:triangle_rest (a second attach would be stale).
  auto fiber = property::add_map<FaceIndex, Vec2>(mesh, property::FIBER_DIR, Vec2(1.0, 0.0));
  auto corners = [&](int f) {
    std::array<int, 3> v;
    int k = 0;
    for (VertexIndex u : CGAL::vertices_around_face(mesh.halfedge(FaceIndex(f)), mesh))
      v[k++] = static_cast<int>(u.idx());
    return v;
  };
  auto point = [&](int v) {
    const Point3& p = mesh.point(VertexIndex(v));
    return Vec3(p.x(), p.y(), p.z());
  };
  const std::vector<std::vector<int>> regions = regions_from_face_ids(stored_regions(mesh));
  // The fibres first, into f:fiber_dir (the rest state's data, like f:triangle_rest) ...
  for (const std::vector<int>& region : regions) {
    // Area-weighted rest centroid of the region.
    Vec3 centre = Vec3::Zero();
    double area = 0.0;
    for (int f : region) {
      const auto v = corners(f);
      const double A = rest[FaceIndex(f)].area;
      centre += A * (point(v[0]) + point(v[1]) + point(v[2])) / 3.0;
      area += A;
    }
    if (area > 0.0) centre /= area;
    for (int f : region) {
      const TriangleRest& tr = rest[FaceIndex(f)];
      if (tr.degenerate) continue;
      const auto v = corners(f);
      const Vec3 d = options.fiber_mode == FiberMode::User
                         ? options.user_direction
                         : Vec3(centre - (point(v[0]) + point(v[1]) + point(v[2])) / 3.0);
      bool fallback = false;
      fiber[FaceIndex(f)] = fiber_in_rest_frame(d, tr.T1, tr.T2, fallback);
      if (fallback) ++report.fallback_fibers;
    }
  }
  // ... then the constraints read them from there.
  for (const std::vector<int>& region : regions)
    for (int f : region) {
      const TriangleRest& tr = rest[FaceIndex(f)];
      if (tr.degenerate) continue;
      MembraneConstraint c;
      c.v = corners(f);
      c.Dm_inv = tr.Dm_inv;
      c.rest_area = tr.area;
      c.max_step = STEP_CLAMP_FACTOR * tr.min_edge;
      c.face = f;
      c.data.fiber = fiber[FaceIndex(f)];
      set.anisotropic.push_back(c);
      set.anisotropic_k_a.push_back(options.kappa_a * options.mu_aniso * std::sqrt(tr.area));
      ++report.faces;
    }
  return report;
}

}  // namespace shellcontract
