#include "sim/pressure.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace shellcontract {

namespace {
/// Smallest task of the parallel form, in vertices (a vertex's sum does not depend on it).
constexpr Eigen::Index PRESSURE_VERTEX_BLOCK = 4096;
}  // namespace

void pressure_forces(const Positions& x, const Faces& faces, double P, PressureModel model,
                     Positions& f) {
  f.setZero(x.rows(), 3);
  // Sum of the unnormalized face normals N_j = (x1 - x3) x (x2 - x3) = 2 A_j nhat_j around
  // each vertex; both models use it.
  for (Eigen::Index j = 0; j < faces.rows(); ++j) {
    const int a = faces(j, 0), b = faces(j, 1), c = faces(j, 2);
    const Vec3 xc = x.row(c);
    const Vec3 N = (Vec3(x.row(a)) - xc).cross(Vec3(x.row(b)) - xc);
    f.row(a) += N.transpose();
    f.row(b) += N.transpose();
    f.row(c) += N.transpose();
  }
  if (model == PressureModel::EnergyConsistent) {
    f *= -P / 6.0;
    return;
  }
  // Paper form: |f_i| = P * (sum of one-ring areas) / 3 along the normalized area-weighted normal.
  Eigen::VectorXd ring_area = Eigen::VectorXd::Zero(x.rows());
  for (Eigen::Index j = 0; j < faces.rows(); ++j) {
    const int a = faces(j, 0), b = faces(j, 1), c = faces(j, 2);
    const Vec3 xc = x.row(c);
    const double A = 0.5 * (Vec3(x.row(a)) - xc).cross(Vec3(x.row(b)) - xc).norm();
    ring_area(a) += A;
    ring_area(b) += A;
    ring_area(c) += A;
  }
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const double len = f.row(i).norm();
    if (len > 0.0) {
      f.row(i) *= -P * ring_area(i) / (3.0 * len);
    }  // else: the normals cancel (e.g. a flat fold); no direction, so no force
  }
}

VertexFaces vertex_faces(const Faces& faces, Eigen::Index num_vertices) {
  VertexFaces out;
  const std::size_t nv = static_cast<std::size_t>(std::max<Eigen::Index>(num_vertices, 0));
  out.start.assign(nv + 1, 0);
  auto valid = [&](int v) { return v >= 0 && static_cast<std::size_t>(v) < nv; };
  for (Eigen::Index j = 0; j < faces.rows(); ++j)
    for (int k = 0; k < 3; ++k)
      if (valid(faces(j, k))) ++out.start[static_cast<std::size_t>(faces(j, k)) + 1];
  for (std::size_t v = 0; v < nv; ++v) out.start[v + 1] += out.start[v];
  out.faces.resize(static_cast<std::size_t>(out.start[nv]));
  std::vector<int> fill(out.start.begin(), out.start.end() - 1);
  for (Eigen::Index j = 0; j < faces.rows(); ++j)
    for (int k = 0; k < 3; ++k)
      if (valid(faces(j, k)))
        out.faces[static_cast<std::size_t>(fill[static_cast<std::size_t>(faces(j, k))]++)] =
            static_cast<int>(j);
  return out;
}

void pressure_forces(const Positions& x, const Faces& faces, const VertexFaces& around, double P,
                     PressureModel model, Positions& f) {
  const Eigen::Index nv = x.rows();
  f.resize(nv, 3);
  // A face's normal is computed again at each of its three corners instead of being stored: no
  // per-face buffer, and each vertex's terms are the serial loop's.
  auto normal = [&](int j) {
    const int a = faces(j, 0), b = faces(j, 1), c = faces(j, 2);
    const Vec3 xc = x.row(c);
    return Vec3((Vec3(x.row(a)) - xc).cross(Vec3(x.row(b)) - xc));
  };
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, nv, PRESSURE_VERTEX_BLOCK),
                    [&](const tbb::blocked_range<Eigen::Index>& r) {
                      for (Eigen::Index v = r.begin(); v < r.end(); ++v) {
                        // As the serial form: the sum from zero in face order, then the scale.
                        Vec3 sum = Vec3::Zero();
                        double ring_area = 0.0;
                        for (int k = around.start[static_cast<std::size_t>(v)];
                             k < around.start[static_cast<std::size_t>(v) + 1]; ++k) {
                          const Vec3 N = normal(around.faces[static_cast<std::size_t>(k)]);
                          sum += N;
                          if (model == PressureModel::Paper) ring_area += 0.5 * N.norm();
                        }
                        if (model == PressureModel::EnergyConsistent) {
                          f.row(v) = sum.transpose() * (-P / 6.0);
                          continue;
                        }
                        const double len = sum.norm();
                        f.row(v) = sum.transpose();
                        if (len > 0.0) f.row(v) *= -P * ring_area / (3.0 * len);
                      }
                    });
}

double air_net_pressure(double P, double R, double v) {
  if (!(R > 0.0)) return P;
  const double outside = P / (1.0 - R);
  return outside * (1.0 - R / std::max(v, 0.25 * R));
}

}  // namespace shellcontract
