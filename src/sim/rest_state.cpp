#include "sim/rest_state.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "bending/dihedral_bending.hpp"
#include "bending/isometric_bending.hpp"
#include "core/constants.hpp"
#include "fem/triangle_element.hpp"
#include "mesh/properties.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract {
namespace {
Vec3 point(const Mesh& mesh, VertexIndex v) {
  const Point3& p = mesh.point(v);
  return Vec3(p.x(), p.y(), p.z());
}

/// The face's vertices in the order CGAL's vertices_around_face (and so its writers) lists
/// them: the order (j1, j2, j3) of the file that was read.
std::array<VertexIndex, 3> face_vertices(const Mesh& mesh, FaceIndex f) {
  const HalfedgeIndex h = mesh.halfedge(f);
  return {mesh.target(h), mesh.target(mesh.next(h)), mesh.target(mesh.next(mesh.next(h)))};
}
/// The triangle's smallest angle, from atan2 of each corner's |u x v| and u . v (exact near 0
/// and 180 degrees, where acos of a cosine is not).
double smallest_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const auto at = [](const Vec3& o, const Vec3& p, const Vec3& q) {
    const Vec3 u = p - o, v = q - o;
    return std::atan2(u.cross(v).norm(), u.dot(v));
  };
  return std::min({at(a, b, c), at(b, c, a), at(c, a, b)});
}
}  // namespace

RestStateReport build_rest_state(Mesh& mesh, MassModel mass, double density) {
  if (mesh.has_garbage()) throw UsageError("build_rest_state: mesh has garbage; collect it first");
  RestStateReport report;
  auto rest = property::add_map<FaceIndex, TriangleRest>(mesh, property::TRIANGLE_REST);
  auto inv_mass = property::add_map<VertexIndex, double>(mesh, property::INV_MASS, 0.0);
  auto hinge = property::add_map<EdgeIndex, HingeVertices>(mesh, property::HINGE,
                                                           HingeVertices{-1, -1, -1, -1});
  auto iso = property::add_map<EdgeIndex, IsometricBendingRest>(mesh, property::ISOMETRIC_BENDING);
  auto dih = property::add_map<EdgeIndex, DihedralBendingRest>(mesh, property::DIHEDRAL_BENDING);

  std::vector<double> vertex_mass(mesh.number_of_vertices(), 0.0);
  for (FaceIndex f : mesh.faces()) {
    const auto [a, b, c] = face_vertices(mesh, f);
    const TriangleRest r = triangle_rest(point(mesh, a), point(mesh, b), point(mesh, c));
    rest[f] = r;
    if (r.degenerate)
      ++report.degenerate_faces;
    else if (smallest_angle(point(mesh, a), point(mesh, b), point(mesh, c)) < PI / 180.0)
      ++report.sliver_faces;
    for (VertexIndex v : {a, b, c}) vertex_mass[v.idx()] += density * r.area / 3.0;
  }

  // Masses: area-lumped, or unit. A vertex whose faces all have zero area would get an infinite
  // inverse mass; it gets the mean mass instead (math-spec 11: degenerate faces are inactive).
  // A vertex surrounded by slivers is floored at MIN_MASS_FRACTION of the mean: with almost no
  // mass it takes nearly all of every projection's correction and runs away (camel.off of CGAL's
  // demo data, 26 vertices below 1 % of the mean, blew up at step 9).
  constexpr double MIN_MASS_FRACTION = 0.01;
  double mean_mass = 0.0;
  for (double m : vertex_mass) mean_mass += m;
  mean_mass /= std::max<std::size_t>(1, vertex_mass.size());
  // The lightest mass is the floor below: its inverse must be a number, or the first step's
  // positions are NaN with nothing to say why (a density far below MIN_DENSITY's reach).
  if (mass == MassModel::AreaLumped && !std::isfinite(1.0 / (MIN_MASS_FRACTION * mean_mass)))
    throw UsageError("`density` " + shortest_text(density) + " gives a mean vertex mass of " +
                     shortest_text(mean_mass) +
                     ", too small for its inverse to be a number: give a larger `density`");
  for (VertexIndex v : mesh.vertices()) {
    double m = mass == MassModel::Unit ? 1.0 : vertex_mass[v.idx()];
    if (!(m > 1e-12 * mean_mass)) m = mean_mass;
    m = std::max(m, MIN_MASS_FRACTION * mean_mass);
    inv_mass[v] = 1.0 / m;
  }

  for (EdgeIndex e : mesh.edges()) {
    const HalfedgeIndex h = mesh.halfedge(e, 0);
    const HalfedgeIndex o = mesh.opposite(h);
    if (mesh.is_border(h) || mesh.is_border(o)) continue;  // open mesh: no hinge (math-spec 1.1)
    // Face A = face(h) = (x0, x1, x2) with h: x0 -> x1; face B = face(o) = (x1, x0, x3).
    const HingeVertices s{static_cast<int>(mesh.source(h).idx()), static_cast<int>(mesh.target(h).idx()),
                          static_cast<int>(mesh.target(mesh.next(h)).idx()),
                          static_cast<int>(mesh.target(mesh.next(o)).idx())};
    const Vec3 x0 = point(mesh, mesh.source(h)), x1 = point(mesh, mesh.target(h)),
               x2 = point(mesh, mesh.target(mesh.next(h))), x3 = point(mesh, mesh.target(mesh.next(o)));
    if (rest[mesh.face(h)].degenerate || rest[mesh.face(o)].degenerate) {
      ++report.inactive_hinges;
      continue;  // hinge stays {-1,...}: inactive
    }
    hinge[e] = s;
    int clamped = 0;
    iso[e] = isometric_bending_rest(x0, x1, x2, x3, &clamped);
    report.clamped_cotangents += static_cast<std::size_t>(clamped);
    dih[e] = dihedral_bending_rest(x0, x1, x2, x3);
  }
  return report;
}

ConstraintSet pack_constraints(const Mesh& mesh, BendingModel bending) {
  ConstraintSet set;
  const auto rest = property::get_map<FaceIndex, TriangleRest>(mesh, property::TRIANGLE_REST);
  for (FaceIndex f : mesh.faces()) {
    const TriangleRest& r = rest[f];
    if (r.degenerate) continue;
    const auto fv = face_vertices(mesh, f);
    MembraneConstraint c;
    c.v = {static_cast<int>(fv[0].idx()), static_cast<int>(fv[1].idx()), static_cast<int>(fv[2].idx())};
    c.Dm_inv = r.Dm_inv;
    c.rest_area = r.area;
    c.max_step = STEP_CLAMP_FACTOR * r.min_edge;
    c.face = static_cast<int>(f.idx());
    set.membranes.push_back(c);
  }
  if (bending == BendingModel::None) return set;
  const auto hinge = property::get_map<EdgeIndex, HingeVertices>(mesh, property::HINGE);
  const auto iso = property::get_map<EdgeIndex, IsometricBendingRest>(mesh, property::ISOMETRIC_BENDING);
  const auto dih = property::get_map<EdgeIndex, DihedralBendingRest>(mesh, property::DIHEDRAL_BENDING);
  for (EdgeIndex e : mesh.edges()) {
    const HingeVertices& s = hinge[e];
    if (s[0] < 0) continue;
    // Shortest of the five stencil edges, for the step clamp.
    auto len = [&](int a, int b) {
      const Point3& p = mesh.point(VertexIndex(a));
      const Point3& q = mesh.point(VertexIndex(b));
      return std::sqrt(CGAL::squared_distance(p, q));
    };
    const double shortest = std::min({len(s[0], s[1]), len(s[1], s[2]), len(s[2], s[0]),
                                      len(s[0], s[3]), len(s[3], s[1])});
    // Every model named, no default: a model added to BendingModel without its hinges here is a
    // compiler warning (-Wswitch), not a run that silently bends as another model.
    switch (bending) {
      case BendingModel::Isometric: {
        const IsometricBendingRest& r = iso[e];
        set.isometric_hinges.push_back({s, r.K, 3.0 / r.area_sum, STEP_CLAMP_FACTOR * shortest});
        break;
      }
      case BendingModel::Dihedral:
        set.dihedral_hinges.push_back({s, dih[e], STEP_CLAMP_FACTOR * shortest});
        break;
      case BendingModel::None:
        break;  // returned above
    }
  }
  return set;
}

Eigen::VectorXd inverse_masses(const Mesh& mesh) {
  const auto inv_mass = property::get_map<VertexIndex, double>(mesh, property::INV_MASS);
  Eigen::VectorXd w(mesh.number_of_vertices());
  for (VertexIndex v : mesh.vertices()) w(v.idx()) = inv_mass[v];
  return w;
}

Faces faces_array(const Mesh& mesh) {
  Faces F(mesh.number_of_faces(), 3);
  for (FaceIndex f : mesh.faces()) {
    const auto fv = face_vertices(mesh, f);
    F.row(f.idx()) << static_cast<int>(fv[0].idx()), static_cast<int>(fv[1].idx()),
        static_cast<int>(fv[2].idx());
  }
  return F;
}

}  // namespace shellcontract
