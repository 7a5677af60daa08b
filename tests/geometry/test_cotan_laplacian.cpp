// The finder's cotangent Laplacian (src/geometry/cotan_laplacian.hpp), built in parallel into
// compressed columns: the same structure and the same bits as Eigen's setFromTriplets on the
// finder's triplet list (built here, with the finder's formula), on a bumpy sphere whose faces
// are shuffled (so a vertex's contributions arrive out of neighbour order), with degenerate
// faces, exact right angles (zero weights, -0.0 entries) and an unused vertex. Checked to fail
// (both bit-for-bit tests) when a column walks its faces in decreasing index.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <Eigen/SparseCore>

#include "geometry/cotan_laplacian.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

using Tris = std::vector<std::array<int, 3>>;

/// The finder's original build: triplets per half-edge, then setFromTriplets.
Eigen::SparseMatrix<double> triplet_laplacian(const Tris& tri, const Positions& x) {
  std::vector<Eigen::Triplet<double>> lt;
  for (const auto& t : tri)
    for (int k = 0; k < 3; ++k) {
      const int i = t[static_cast<std::size_t>(k)], j = t[static_cast<std::size_t>((k + 1) % 3)],
                o = t[static_cast<std::size_t>((k + 2) % 3)];
      const Vec3 a = Vec3(x.row(i)) - Vec3(x.row(o)), b = Vec3(x.row(j)) - Vec3(x.row(o));
      const double cross = a.cross(b).norm();
      if (!(cross > 1e-14 * a.norm() * b.norm())) continue;
      const double w = 0.5 * a.dot(b) / cross;
      lt.emplace_back(i, j, -w);
      lt.emplace_back(j, i, -w);
      lt.emplace_back(i, i, w);
      lt.emplace_back(j, j, w);
    }
  Eigen::SparseMatrix<double> L(x.rows(), x.rows());
  L.setFromTriplets(lt.begin(), lt.end());
  return L;
}

/// Same outer and inner indices and the same value bits (so -0.0 differs from 0.0).
void expect_identical(const Eigen::SparseMatrix<double>& a, const Eigen::SparseMatrix<double>& b) {
  ASSERT_TRUE(a.isCompressed());
  ASSERT_TRUE(b.isCompressed());
  ASSERT_EQ(a.rows(), b.rows());
  ASSERT_EQ(a.cols(), b.cols());
  ASSERT_EQ(a.nonZeros(), b.nonZeros());
  const auto nnz = static_cast<std::size_t>(a.nonZeros());
  EXPECT_TRUE(std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1, b.outerIndexPtr()));
  EXPECT_TRUE(std::equal(a.innerIndexPtr(), a.innerIndexPtr() + nnz, b.innerIndexPtr()));
  std::size_t differing = 0;
  for (std::size_t k = 0; k < nnz; ++k)
    if (std::memcmp(a.valuePtr() + k, b.valuePtr() + k, sizeof(double)) != 0) ++differing;
  EXPECT_EQ(differing, 0u) << "of " << nnz << " entries";
}

/// A bumpy icosphere with shuffled faces, each face's corners rotated at random.
test::TriMesh bumpy_shuffled(int levels, unsigned seed) {
  test::TriMesh m = test::icosphere(levels);
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) {
    const Eigen::Vector3d p = m.x.row(i);
    m.x.row(i) *= 1.0 + 0.2 * std::sin(3.0 * p.x()) * std::sin(4.0 * p.y()) * std::sin(5.0 * p.z());
  }
  std::mt19937 rng(seed);
  std::vector<Eigen::Index> order(static_cast<std::size_t>(m.faces.rows()));
  for (std::size_t f = 0; f < order.size(); ++f) order[f] = static_cast<Eigen::Index>(f);
  std::shuffle(order.begin(), order.end(), rng);
  Faces g(m.faces.rows(), 3);
  for (std::size_t f = 0; f < order.size(); ++f) {
    const int r = static_cast<int>(rng() % 3);
    for (int k = 0; k < 3; ++k) g(static_cast<Eigen::Index>(f), k) = m.faces(order[f], (k + r) % 3);
  }
  m.faces = g;
  return m;
}

Tris tris_of(const Faces& faces) {
  Tris t(static_cast<std::size_t>(faces.rows()));
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) t[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)] = faces(f, k);
  return t;
}

TEST(CotanLaplacian, SameBitsAsSetFromTripletsOnAShuffledBumpySphere) {
  for (int levels : {2, 4}) {
    const test::TriMesh m = bumpy_shuffled(levels, 7u + static_cast<unsigned>(levels));
    const Tris t = tris_of(m.faces);
    expect_identical(detail::cotan_laplacian(t, m.x), triplet_laplacian(t, m.x));
  }
}

TEST(CotanLaplacian, SameBitsWithDegenerateFacesRightAnglesAndAnUnusedVertex) {
  // A unit square (two right triangles: zero weights across the diagonal's opposite corners),
  // a sliver with collinear corners, a face repeating a corner, and vertex 6 in no face.
  Positions x(8, 3);
  x << 0, 0, 0,  1, 0, 0,  1, 1, 0,  0, 1, 0,  2, 0, 0,  3, 0, 0,  5, 5, 5,  0.5, 0.5, 1;
  const Tris t = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 4, 4}, {2, 7, 3}, {0, 7, 1}, {3, 7, 0}, {1, 7, 2}};
  const Eigen::SparseMatrix<double> L = detail::cotan_laplacian(t, x);
  expect_identical(L, triplet_laplacian(t, x));
  EXPECT_EQ(L.col(6).nonZeros(), 0);
  // Both of the diagonal 0-2's opposite corners (1 and 3) are right angles: an entry stored
  // with the value -0.0 (two zero weights, negated).
  bool stored = false;
  for (Eigen::SparseMatrix<double>::InnerIterator it(L, 2); it; ++it)
    if (it.row() == 0) {
      stored = true;
      EXPECT_EQ(it.value(), 0.0);
      EXPECT_TRUE(std::signbit(it.value()));
    }
  EXPECT_TRUE(stored);
  // The sliver 1-4-5 and the face 1-4-4 give no weight: vertex 5 has no entry.
  EXPECT_EQ(L.col(5).nonZeros(), 0);
}

TEST(CotanLaplacian, ExactlySymmetricWithRowsSummingToZero) {
  const test::TriMesh m = bumpy_shuffled(4, 3u);
  const Eigen::SparseMatrix<double> L = detail::cotan_laplacian(tris_of(m.faces), m.x);
  const Eigen::SparseMatrix<double> Lt = L.transpose();
  expect_identical(L, Eigen::SparseMatrix<double>(Lt));
  const Eigen::VectorXd sums = L * Eigen::VectorXd::Ones(L.cols());
  for (Eigen::Index i = 0; i < L.rows(); ++i) {
    EXPECT_GT(L.coeff(i, i), 0.0) << i;
    EXPECT_LE(std::abs(sums(i)), 1e-12 * L.coeff(i, i)) << i;
  }
}

}  // namespace
}  // namespace shellcontract
