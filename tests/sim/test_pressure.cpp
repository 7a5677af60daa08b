// Pressure load (math-spec 3, 13 "Pressure").
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>
#include <random>

#include "sim/pressure.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

constexpr double PI = 3.14159265358979323846;

TEST(Pressure, EnergyConsistentForceIsMinusPTimesVolumeGradient) {
  std::mt19937 rng(21);
  test::TriMesh m = test::icosphere(1, 0.7);
  for (Eigen::Index i = 0; i < m.x.rows(); ++i)
    m.x.row(i) += 0.05 * test::random_vec3(rng).transpose();
  const double P = 2.5;
  Positions f;
  pressure_forces(m.x, m.faces, P, PressureModel::EnergyConsistent, f);
  const double h = 1e-6;
  double err = 0, scale = 0;
  for (Eigen::Index i = 0; i < m.x.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      Positions xp = m.x, xm = m.x;
      xp(i, k) += h;
      xm(i, k) -= h;
      const double dV =
          (test::signed_volume(xp, m.faces) - test::signed_volume(xm, m.faces)) / (2 * h);
      err = std::max(err, std::abs(f(i, k) + P * dV));
      scale = std::max(scale, std::abs(f(i, k)));
    }
  ASSERT_GT(scale, 0.0);
  EXPECT_LE(err, 1e-8 * scale);
}

TEST(Pressure, NoNetForceOnClosedMeshAndInwardDirection) {
  const test::TriMesh m = test::icosphere(2, 1.0);
  for (PressureModel model : {PressureModel::EnergyConsistent, PressureModel::Paper}) {
    Positions f;
    pressure_forces(m.x, m.faces, 1.0, model, f);
    EXPECT_LE(f.colwise().sum().norm(), 1e-12 * f.rowwise().norm().sum());
    for (Eigen::Index i = 0; i < m.x.rows(); ++i)
      EXPECT_LT(f.row(i).dot(m.x.row(i)), 0.0) << "P > 0 must push vertex " << i << " inward";
  }
}

TEST(Pressure, TotalForceMagnitudeConvergesToPTimesArea) {
  // math-spec 13: on an icosphere of radius r, sum |f_i| -> P 4 pi r^2 under refinement, at
  // second order in the edge length (each level halves it, so the error drops ~4x).
  const double r = 0.8, P = 3.0;
  double previous_error = 0.0;
  for (int level : {1, 2, 3, 4}) {
    const test::TriMesh m = test::icosphere(level, r);
    Positions f;
    pressure_forces(m.x, m.faces, P, PressureModel::EnergyConsistent, f);
    const double error = std::abs(f.rowwise().norm().sum() / (P * 4 * PI * r * r) - 1.0);
    if (level > 1) {
      EXPECT_GT(previous_error / error, 3.5) << "level " << level;
    }
    previous_error = error;
  }
}

TEST(Pressure, PaperFormIsParallelAndAtLeastAsLarge) {
  // Both forms point along the area-weighted vertex normal; the paper's magnitude is larger by
  // sum A_j / |sum A_j n_j| >= 1 (math-spec 3); on an octahedron by about 73 %.
  test::TriMesh oct;
  oct.x.resize(6, 3);
  oct.x << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  oct.faces.resize(8, 3);
  oct.faces << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  ASSERT_GT(test::signed_volume(oct.x, oct.faces), 0.0);
  Positions fr, fp;
  pressure_forces(oct.x, oct.faces, 1.0, PressureModel::EnergyConsistent, fr);
  pressure_forces(oct.x, oct.faces, 1.0, PressureModel::Paper, fp);
  for (Eigen::Index i = 0; i < 6; ++i) {
    EXPECT_NEAR(Vec3(fr.row(i)).normalized().dot(Vec3(fp.row(i)).normalized()), 1.0, 1e-14);
    EXPECT_NEAR(fp.row(i).norm() / fr.row(i).norm(), std::sqrt(3.0), 1e-12);
  }
}

TEST(Pressure, ParallelGatherHasTheSerialFormsBits) {
  // The simulator's parallel form sums each vertex's face terms in face order; it must give
  // exactly the serial face loop's forces, in both models, for any number of threads (10k
  // vertices: three blocks), with an unreferenced vertex (no faces: zero force).
  std::mt19937 rng(29);
  test::TriMesh m = test::icosphere(5, 0.8);
  for (Eigen::Index i = 0; i < m.x.rows(); ++i)
    m.x.row(i) += 0.03 * test::random_vec3(rng).transpose();
  m.x.conservativeResize(m.x.rows() + 1, 3);
  m.x.row(m.x.rows() - 1) << 0.1, 0.2, 0.3;  // referenced by no face
  const VertexFaces around = vertex_faces(m.faces, m.x.rows());
  ASSERT_EQ(around.start.back(), 3 * m.faces.rows());
  EXPECT_EQ(around.start[static_cast<std::size_t>(m.x.rows())] -
                around.start[static_cast<std::size_t>(m.x.rows() - 1)],
            0);
  for (const PressureModel model : {PressureModel::EnergyConsistent, PressureModel::Paper}) {
    Positions serial, parallel1, parallel3;
    pressure_forces(m.x, m.faces, 1.7, model, serial);
    tbb::task_arena(1).execute(
        [&] { pressure_forces(m.x, m.faces, around, 1.7, model, parallel1); });
    tbb::task_arena(3).execute(
        [&] { pressure_forces(m.x, m.faces, around, 1.7, model, parallel3); });
    ASSERT_EQ(serial.rows(), parallel1.rows());
    EXPECT_EQ(std::memcmp(serial.data(), parallel1.data(), sizeof(double) * serial.size()), 0);
    EXPECT_EQ(std::memcmp(serial.data(), parallel3.data(), sizeof(double) * serial.size()), 0);
    EXPECT_TRUE(serial.row(serial.rows() - 1).isZero());
  }
}

}  // namespace
}  // namespace shellcontract
