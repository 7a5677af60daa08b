// Discrete curvature (Meyer et al. 2003 mixed area, cotangent mean-curvature normal, angle
// deficit). Conventions and sign are documented in the header.
#include "geometry/curvature.hpp"

#include <array>
#include <cmath>
#include <cstdlib>
#include <string>

#include "core/cancellation.hpp"
#include "core/constants.hpp"
#include "core/power_of_two.hpp"
#include "mesh/properties.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {
namespace {

/// A largest side in [2^-(FREE_SCALE_EXPONENT + 1), 2^FREE_SCALE_EXPONENT) is left as it is (see
/// detail::finder_exponent): squares and cubes of lengths are far from the double's range there,
/// and every mesh of a usual scale keeps its bits.
constexpr int FREE_SCALE_EXPONENT = 64;

/// A triangle counts as degenerate when |e1 x e2| is below this fraction of the squared
/// longest edge (sin of the largest corner angle ~ 1e-14). Its cotangents would be ~1e14 or
/// infinite and its area is zero to rounding, so it contributes no cotangent weight and no area.
constexpr double DEGENERATE_SIN = 1e-14;

/// Corner angles of triangle (p0, p1, p2), summing to pi to rounding in every case.
/// atan2(|a x b|, a . b) instead of acos: no domain error and full precision near 0 and pi.
std::array<double, 3> corner_angles(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  const std::array<Vec3, 3> p{p0, p1, p2};
  const std::array<double, 3> len{(p2 - p1).norm(), (p0 - p2).norm(), (p1 - p0).norm()};  // opposite i
  int zero_edges = 0;
  for (double l : len) zero_edges += (l == 0.0);
  if (zero_edges >= 2) return {PI / 3, PI / 3, PI / 3};  // all three points coincide
  if (zero_edges == 1) {
    // The limit of a triangle whose edge (a, b) shrinks to a point: angle 0 opposite that edge,
    // the two ends share pi. Any split keeps Gauss-Bonnet; pi/2 each is the symmetric limit.
    std::array<double, 3> a{PI / 2, PI / 2, PI / 2};
    for (int i = 0; i < 3; ++i)
      if (len[static_cast<std::size_t>(i)] == 0.0) a[static_cast<std::size_t>(i)] = 0.0;
    return a;
  }
  std::array<double, 3> angle{};
  for (std::size_t i = 0; i < 3; ++i) {
    const Vec3 u = p[(i + 1) % 3] - p[i];
    const Vec3 v = p[(i + 2) % 3] - p[i];
    angle[i] = std::atan2(u.cross(v).norm(), u.dot(v));
  }
  return angle;
}

/// Looks the map up and creates it when it is missing. properties.hpp's add_map refuses an
/// existing map on purpose (stale rest data); curvature of a new state must overwrite instead.
Mesh::Property_map<VertexIndex, double> attach_vertex_map(Mesh& mesh, const char* name) {
  try {
    return property::get_map<VertexIndex, double>(mesh, name);
  } catch (const UsageError&) {
    return property::add_map<VertexIndex, double>(mesh, name, 0.0);
  }
}

}  // namespace

namespace detail {

int finder_exponent(const Positions& x) {
  if (x.rows() == 0 || !x.allFinite()) return 0;
  // The largest side, not the diagonal, whose squares overflow sooner; a side beyond the largest
  // double (coordinates spanning more than it) is left alone.
  const double side = (x.colwise().maxCoeff() - x.colwise().minCoeff()).maxCoeff();
  if (!(side > 0.0) || !std::isfinite(side)) return 0;
  const int e = binary_exponent(side);
  return std::abs(e) <= FREE_SCALE_EXPONENT ? 0 : e;
}

void unscale_curvature(int k, CurvatureField& c) {
  c.mixed_area = times_power_of_two(c.mixed_area, 2 * k);
  c.gaussian = times_power_of_two(c.gaussian, -2 * k);
  c.mean = times_power_of_two(c.mean, -k);
  c.k_max = times_power_of_two(c.k_max, -k);
  c.k_min = times_power_of_two(c.k_min, -k);
}

}  // namespace detail

CurvatureField compute_curvature(const Mesh& mesh, const Positions& x) {
  if (mesh.has_garbage())
    throw UsageError("compute_curvature: the mesh has removed elements; call collect_garbage() first");
  const auto nv = static_cast<Eigen::Index>(mesh.number_of_vertices());
  if (x.rows() != nv)
    throw UsageError("compute_curvature: positions have " + std::to_string(x.rows()) + " rows, mesh has " +
                     std::to_string(nv) + " vertices");

  if (const int k = detail::finder_exponent(x); k != 0) {
    CurvatureField c = compute_curvature(mesh, times_power_of_two(x, -k));
    detail::unscale_curvature(k, c);
    return c;
  }
  CurvatureField c;
  c.mixed_area = Eigen::VectorXd::Zero(nv);
  Eigen::VectorXd angle_sum = Eigen::VectorXd::Zero(nv);
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> laplacian =
      Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>::Zero(nv, 3);  // sum (cot+cot)(xi-xj)
  c.normal = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>::Zero(nv, 3);

  for (FaceIndex f : mesh.faces()) {
    // A run's cancel (cancellation.hpp): on a large mesh this loop is a long single call.
    if (f.idx() % CANCELLATION_CHUNK == 0) cancellation_point();
    std::array<Eigen::Index, 3> id{};
    int k = 0;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (k == 3) throw UsageError("compute_curvature: face " + std::to_string(f.idx()) + " is not a triangle");
      id[static_cast<std::size_t>(k++)] = static_cast<Eigen::Index>(v.idx());
    }
    if (k != 3) throw UsageError("compute_curvature: face " + std::to_string(f.idx()) + " is not a triangle");
    const std::array<Vec3, 3> p{Vec3(x.row(id[0])), Vec3(x.row(id[1])), Vec3(x.row(id[2]))};

    const std::array<double, 3> angle = corner_angles(p[0], p[1], p[2]);
    for (std::size_t i = 0; i < 3; ++i) angle_sum(id[i]) += angle[i];

    const Vec3 cross = (p[1] - p[0]).cross(p[2] - p[0]);  // |cross| = 2 area, direction = normal
    const double cross_norm = cross.norm();
    double max_edge2 = 0.0;
    for (std::size_t i = 0; i < 3; ++i) max_edge2 = std::max(max_edge2, (p[(i + 1) % 3] - p[i]).squaredNorm());
    if (!(cross_norm > DEGENERATE_SIN * max_edge2)) continue;  // also catches NaN
    for (std::size_t i = 0; i < 3; ++i) c.normal.row(id[i]) += cross.transpose();  // area weighted

    const double area = 0.5 * cross_norm;
    // cot of the corner angle at i = (u . v) / |u x v| with |u x v| = 2 area for every corner.
    std::array<double, 3> cot{};
    for (std::size_t i = 0; i < 3; ++i)
      cot[i] = (p[(i + 1) % 3] - p[i]).dot(p[(i + 2) % 3] - p[i]) / cross_norm;

    // Edge (i, j) opposite corner o gets weight cot(o): L_i += cot(o) (x_i - x_j).
    for (std::size_t o = 0; o < 3; ++o) {
      const std::size_t i = (o + 1) % 3, j = (o + 2) % 3;
      const Vec3 e = p[i] - p[j];
      laplacian.row(id[i]) += cot[o] * e.transpose();
      laplacian.row(id[j]) -= cot[o] * e.transpose();
    }

    // Mixed area (Meyer et al. 2003, Fig. 4). A corner is obtuse when its cosine (dot) < 0.
    int obtuse = -1;
    for (std::size_t i = 0; i < 3; ++i)
      if (cot[i] < 0.0) obtuse = static_cast<int>(i);
    if (obtuse < 0) {
      // Voronoi: corner i gets (|x_i - x_j|^2 cot(k) + |x_i - x_k|^2 cot(j)) / 8.
      for (std::size_t i = 0; i < 3; ++i) {
        const std::size_t j = (i + 1) % 3, kk = (i + 2) % 3;
        c.mixed_area(id[i]) += ((p[i] - p[j]).squaredNorm() * cot[kk] + (p[i] - p[kk]).squaredNorm() * cot[j]) / 8.0;
      }
    } else {
      for (std::size_t i = 0; i < 3; ++i)
        c.mixed_area(id[i]) += (static_cast<int>(i) == obtuse) ? area / 2.0 : area / 4.0;
    }
  }

  c.angle_deficit.resize(nv);
  c.gaussian.resize(nv);
  c.mean.resize(nv);
  c.k_max.resize(nv);
  c.k_min.resize(nv);
  for (Eigen::Index i = 0; i < nv; ++i) {
    c.angle_deficit(i) = 2.0 * PI - angle_sum(i);
    const double n_norm = c.normal.row(i).norm();
    if (n_norm > 0.0) c.normal.row(i) /= n_norm;
    const double A = c.mixed_area(i);
    if (!(A > 0.0)) {  // isolated vertex or only degenerate faces around it: no measure to divide by
      c.gaussian(i) = c.mean(i) = c.k_max(i) = c.k_min(i) = 0.0;
      continue;
    }
    c.gaussian(i) = c.angle_deficit(i) / A;
    c.mean(i) = laplacian.row(i).dot(c.normal.row(i)) / (4.0 * A);
    const double H = c.mean(i), K = c.gaussian(i);
    const double root = std::sqrt(std::max(H * H - K, 0.0));
    c.k_max(i) = H + root;
    c.k_min(i) = H - root;
  }
  return c;
}

void store_curvature(Mesh& mesh, const CurvatureField& field) {
  const auto nv = static_cast<Eigen::Index>(mesh.number_of_vertices());
  if (field.mean.size() != nv || field.gaussian.size() != nv || mesh.has_garbage())
    throw UsageError("store_curvature: the field was not computed on this mesh (" + std::to_string(field.mean.size()) +
                     " values, " + std::to_string(nv) + " vertices)");
  auto mean_map = attach_vertex_map(mesh, property::MEAN_CURVATURE);
  auto gauss_map = attach_vertex_map(mesh, property::GAUSSIAN_CURVATURE);
  for (VertexIndex v : mesh.vertices()) {
    const auto i = static_cast<Eigen::Index>(v.idx());
    mean_map[v] = field.mean(i);
    gauss_map[v] = field.gaussian(i);
  }
}

}  // namespace shellcontract
