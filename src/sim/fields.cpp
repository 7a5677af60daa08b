#include "sim/fields.hpp"

#include <CGAL/IO/Color.h>

#include <algorithm>
#include <iomanip>
#include <sstream>
#include <utility>
#include <vector>

#include "core/classic_locale.hpp"
#include "geometry/curvature.hpp"
#include "mesh/properties.hpp"
#include "shellcontract/mesh_io.hpp"
#include "sim/pressure.hpp"
#include "sim/rest_state.hpp"

namespace shellcontract {
namespace {

/// One-ring area sums of a per-face quantity and of the face areas at positions x.
void ring_sums(const Faces& F, const Positions& x, const Eigen::VectorXd& per_face,
               Eigen::VectorXd& value, Eigen::VectorXd& area) {
  value = Eigen::VectorXd::Zero(x.rows());
  area = Eigen::VectorXd::Zero(x.rows());
  for (Eigen::Index j = 0; j < F.rows(); ++j) {
    const Vec3 xc = x.row(F(j, 2));
    const double A = 0.5 * (Vec3(x.row(F(j, 0))) - xc).cross(Vec3(x.row(F(j, 1))) - xc).norm();
    for (int k = 0; k < 3; ++k) {
      value(F(j, k)) += per_face.size() ? per_face(j) : 0.0;
      area(F(j, k)) += A;
    }
  }
}

}  // namespace

Eigen::VectorXd input_unit_mean_curvature(const Simulator& sim, const Positions& x) {
  // H is 1/length: a length s times the normalized one has s times smaller curvature.
  return compute_curvature(sim.rest_mesh(), x).mean / sim.normalization().scale;
}

VertexFields compute_vertex_fields(const Simulator& sim) {
  const Mesh& mesh = sim.rest_mesh();
  const Positions& x = sim.positions();
  const Faces F = faces_array(mesh);
  VertexFields out;
  // The curvatures in the file's units, as `regions -o` writes them under the same names: the
  // PLY's positions are the file's.
  const double scale = sim.normalization().scale;
  const CurvatureField c = compute_curvature(mesh, x);
  out.mean_curvature = c.mean / scale;
  out.gaussian_curvature = c.gaussian / (scale * scale);
  // The load that acts on this state (keyed pressure and air), as the next step applies it; its
  // force on each vertex along the vertex's area-weighted normal, per area share, signed as the
  // pressure (> 0 pushes inward). Normalized units, as -p is given.
  Positions f;
  pressure_forces(x, F, sim.net_pressure(), sim.options().pressure_model, f);
  Positions normal = Positions::Zero(x.rows(), 3);
  for (Eigen::Index j = 0; j < F.rows(); ++j) {
    const Vec3 xc = x.row(F(j, 2));
    const Vec3 N = (Vec3(x.row(F(j, 0))) - xc).cross(Vec3(x.row(F(j, 1))) - xc);
    for (int k = 0; k < 3; ++k) normal.row(F(j, k)) += N.transpose();
  }
  Eigen::VectorXd unused, area;
  ring_sums(F, x, Eigen::VectorXd(), unused, area);
  out.pressure = Eigen::VectorXd::Zero(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const double len = normal.row(i).norm();
    if (area(i) > 0.0 && len > 0.0)  // guard: isolated, or normals that cancel (no direction)
      out.pressure(i) = -f.row(i).dot(normal.row(i)) / len / (area(i) / 3.0);
  }
  // Energy density: one-ring energy over one-ring REST area (energies are per rest area).
  Eigen::VectorXd ring_energy, rest_area;
  ring_sums(F, sim.rest_positions(), sim.face_energies(), ring_energy, rest_area);
  out.energy_density = Eigen::VectorXd::Zero(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    if (rest_area(i) > 0.0) out.energy_density(i) = ring_energy(i) / rest_area(i);
  return out;
}

Eigen::Vector3i field_colour(double t) {
  t = std::clamp(t, 0.0, 1.0);
  if (t < 0.5) {
    const int w = static_cast<int>(255.0 * (t / 0.5) + 0.5);
    return Eigen::Vector3i(w, w, 255);
  }
  const int w = static_cast<int>(255.0 * ((1.0 - t) / 0.5) + 0.5);
  return Eigen::Vector3i(255, w, w);
}

FieldsPly fields_ply(const Simulator& sim, const Positions& x, const VertexFields& fields,
                     FieldColour colour) {
  const Eigen::VectorXd& c = colour == FieldColour::MeanCurvature       ? fields.mean_curvature
                             : colour == FieldColour::GaussianCurvature ? fields.gaussian_curvature
                             : colour == FieldColour::Pressure          ? fields.pressure
                                                                        : fields.energy_density;
  const std::vector<double> values(c.data(), c.data() + c.size());
  const double lo = field_percentile(values, 0.02), hi = field_percentile(values, 0.98);
  // Attached in the order of the file's columns. The fields stay float, as they always were:
  // they are for looking at, and half the size of doubles.
  // The input's vertices (a welded mesh's copies too, each with its vertex's values).
  Mesh out = mesh_for_output(sim.rest_mesh(), x);
  const std::vector<std::size_t> of = input_vertex_map(sim.rest_mesh());
  auto rgb = property::add_map<VertexIndex, CGAL::IO::Color>(out, property::VERTEX_COLOR);
  const std::pair<const char*, const Eigen::VectorXd*> columns[] = {
      {property::MEAN_CURVATURE, &fields.mean_curvature},
      {property::GAUSSIAN_CURVATURE, &fields.gaussian_curvature},
      {property::PRESSURE_LOAD, &fields.pressure},
      {property::ENERGY_DENSITY, &fields.energy_density}};
  for (const auto& [name, field] : columns) {
    auto map = property::add_map<VertexIndex, float>(out, name);
    for (VertexIndex v : out.vertices()) map[v] = static_cast<float>((*field)(static_cast<Eigen::Index>(of[v.idx()])));
  }
  for (VertexIndex v : out.vertices()) {
    const auto i = static_cast<Eigen::Index>(of[v.idx()]);
    const double t = hi > lo ? (c(i) - lo) / (hi - lo) : 0.5;  // constant field: white
    const Eigen::Vector3i c8 = field_colour(t);
    rgb[v] = CGAL::IO::Color(static_cast<unsigned char>(c8(0)), static_cast<unsigned char>(c8(1)),
                             static_cast<unsigned char>(c8(2)));
  }
  ClassicOStringStream comment;
  comment << std::setprecision(17) << "shellcontract fields; colour = field mapped from its 2nd to 98th percentile ["
          << lo << ", " << hi << "] onto blue-white-red";
  return FieldsPly{std::move(out), comment.str()};
}

void write_fields_ply(const std::string& path, const FieldsPly& ply) {
  write_ply_atomic(path, ply.mesh, ply.comment);
}

void write_fields_ply(const std::string& path, const Simulator& sim, const Positions& x,
                      const VertexFields& fields, FieldColour colour) {
  write_fields_ply(path, fields_ply(sim, x, fields, colour));
}

double field_percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const std::size_t k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace shellcontract
