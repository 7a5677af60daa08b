// The region finder's iterative heat solves run their systems two at a time in one thread
// (src/geometry/heat_smoothing.cpp): each system must get exactly the result it gets alone,
// bit for bit, whatever system it is paired with and however many there are, so the smoothed
// curvature (and the regions) cannot depend on the batching or the threads. The Laplacian and
// the masses are built here, not by the finder. Checked to fail when the paired kernel reads
// the first system's matrix values for both systems.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include <Eigen/SparseCore>

#include "geometry/heat_smoothing.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

struct HeatProblem {
  Eigen::SparseMatrix<double> L;
  Eigen::VectorXd mass, rhs;
  std::vector<double> times;
};

/// A bumpy icosphere, its cotangent Laplacian, a third of the incident areas as masses and a
/// rough field h = z + sin 7x to smooth, at five times (an odd count leaves one system alone).
HeatProblem bumpy_problem() {
  test::TriMesh m = test::icosphere(4);
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) {
    const Eigen::Vector3d p = m.x.row(i);
    m.x.row(i) *= 1.0 + 0.1 * std::sin(4 * p.x()) * std::sin(3 * p.y()) * std::sin(5 * p.z());
  }
  const Eigen::Index n = m.x.rows();
  HeatProblem h;
  h.mass = Eigen::VectorXd::Zero(n);
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
    const int c[3] = {m.faces(f, 0), m.faces(f, 1), m.faces(f, 2)};
    const Eigen::Vector3d p0 = m.x.row(c[0]), p1 = m.x.row(c[1]), p2 = m.x.row(c[2]);
    const double a = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    for (int k = 0; k < 3; ++k) {
      h.mass(c[k]) += a / 3.0;
      const int i = c[k], j = c[(k + 1) % 3], o = c[(k + 2) % 3];
      const Eigen::Vector3d u = m.x.row(i) - m.x.row(o), v = m.x.row(j) - m.x.row(o);
      const double w = 0.5 * u.dot(v) / u.cross(v).norm();
      t.emplace_back(i, j, -w);
      t.emplace_back(j, i, -w);
      t.emplace_back(i, i, w);
      t.emplace_back(j, j, w);
    }
  }
  h.L.resize(n, n);
  h.L.setFromTriplets(t.begin(), t.end());
  h.rhs.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) h.rhs(i) = h.mass(i) * (m.x(i, 2) + std::sin(7 * m.x(i, 0)));
  h.times = {1e-4, 4e-4, 2.5e-3, 1e-2, 4e-2};
  return h;
}

bool same_bits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

TEST(HeatBatch, EachSystemGetsTheBitsItGetsAlone) {
  const HeatProblem h = bumpy_problem();
  std::vector<int> together_its;
  const std::vector<Eigen::VectorXd> together = detail::heat_solves(h.L, h.mass, h.rhs, h.times, true, &together_its);
  ASSERT_EQ(together.size(), h.times.size());
  for (std::size_t k = 0; k < h.times.size(); ++k) {
    std::vector<int> alone_its;
    const std::vector<Eigen::VectorXd> alone = detail::heat_solves(h.L, h.mass, h.rhs, {h.times[k]}, true, &alone_its);
    EXPECT_GT(together_its[k], 0) << "time " << k << " fell back to the direct solver";
    EXPECT_EQ(together_its[k], alone_its[0]) << "time " << k;
    EXPECT_TRUE(same_bits(together[k], alone[0])) << "time " << k;
    // And it is the solution (the batching must not change which system is solved).
    const Eigen::VectorXd residual = h.rhs - (h.mass.asDiagonal() * together[k] + h.times[k] * (h.L * together[k]));
    EXPECT_LE(residual.norm(), 1e-10 * h.rhs.norm()) << "time " << k;
  }
}

TEST(HeatBatch, PartnersDoNotMatter) {
  // Rotated by one, the systems are paired with others (the first with the last: t0 with t4
  // and t1 with t3, then t1 with t0 and t2 with t4).
  const HeatProblem h = bumpy_problem();
  const std::size_t n = h.times.size();
  std::vector<double> rotated;
  for (std::size_t k = 0; k < n; ++k) rotated.push_back(h.times[(k + 1) % n]);
  const std::vector<Eigen::VectorXd> plain = detail::heat_solves(h.L, h.mass, h.rhs, h.times, true);
  const std::vector<Eigen::VectorXd> moved = detail::heat_solves(h.L, h.mass, h.rhs, rotated, true);
  for (std::size_t k = 0; k < n; ++k) EXPECT_TRUE(same_bits(plain[(k + 1) % n], moved[k])) << "time " << k;
}

}  // namespace
}  // namespace shellcontract
