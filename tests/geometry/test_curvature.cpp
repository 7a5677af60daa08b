// Discrete curvature against closed forms: sphere H = 1/r, K = 1/r^2 at three scales, cylinder
// H = 1/(2r), K = 0, cube corners deficit pi/2, Gauss-Bonnet sum = 2 pi chi on every closed mesh
// we have, mixed areas tiling the surface.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/curvature.hpp"
#include "mesh/eigen_point_map.hpp"
#include "mesh/properties.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

constexpr double PI = 3.14159265358979323846;

long long euler_characteristic(const Mesh& mesh) {
  return static_cast<long long>(mesh.number_of_vertices()) - static_cast<long long>(mesh.number_of_edges()) +
         static_cast<long long>(mesh.number_of_faces());
}

double total_area(const Mesh& mesh, const Positions& x) {
  double A = 0.0;
  for (FaceIndex f : mesh.faces()) {
    std::vector<Vec3> p;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) p.emplace_back(x.row(v.idx()));
    A += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
  }
  return A;
}

/// Open tube of radius r along z: `rings` rings of `sectors` vertices, every other ring rotated
/// by half a sector (near-equilateral triangles), height step chosen for that.
test::TriMesh tube(int rings, int sectors, double r) {
  test::TriMesh m;
  m.x.resize(rings * sectors, 3);
  const double dphi = 2.0 * PI / sectors;
  const double dz = r * dphi * std::sqrt(3.0) / 2.0;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const double phi = (j + 0.5 * (i % 2)) * dphi;
      m.x.row(i * sectors + j) << r * std::cos(phi), r * std::sin(phi), i * dz;
    }
  std::vector<std::array<int, 3>> f;
  for (int i = 0; i + 1 < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const int a = i * sectors + j, b = i * sectors + (j + 1) % sectors;
      const int c = (i + 1) * sectors + j, d = (i + 1) * sectors + (j + 1) % sectors;
      if (i % 2 == 0) {  // ring i+1 is shifted forward by half a sector
        f.push_back({a, b, c});
        f.push_back({b, d, c});
      } else {  // ring i is the shifted one
        f.push_back({a, d, c});
        f.push_back({a, b, d});
      }
    }
  m.faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t k = 0; k < f.size(); ++k) m.faces.row(static_cast<Eigen::Index>(k)) << f[k][0], f[k][1], f[k][2];
  return m;
}

class SphereAtScale : public ::testing::TestWithParam<double> {};

TEST_P(SphereAtScale, MeanAndGaussianCurvatureMatchClosedFormAtEveryVertex) {
  const double r = GetParam();
  const test::TriMesh m = test::icosphere(3, r);  // 642 vertices, 1280 faces, all on the sphere
  const Mesh mesh = test::to_surface_mesh(m);
  const CurvatureField c = compute_curvature(mesh, m.x);
  ASSERT_EQ(c.mean.size(), m.x.rows());
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) {
    EXPECT_NEAR(c.mean(i) * r, 1.0, 0.02) << "vertex " << i << " r " << r << " H " << c.mean(i);
    EXPECT_NEAR(c.gaussian(i) * r * r, 1.0, 0.02) << "vertex " << i << " r " << r << " K " << c.gaussian(i);
    // Principal curvatures of an umbilic point: both 1/r.
    EXPECT_NEAR(c.k_min(i) * r, 1.0, 0.02) << "vertex " << i << " r " << r;
    EXPECT_NEAR(c.k_max(i) * r, 1.0, 0.02) << "vertex " << i << " r " << r;
    // The vertex normal is the outward radial direction.
    EXPECT_GT(Vec3(c.normal.row(i)).dot(Vec3(m.x.row(i)) / r), 0.999) << "vertex " << i;
  }
  // Mixed areas tile the surface (Meyer et al. 2003): sum = polyhedral area.
  EXPECT_NEAR(c.mixed_area.sum(), total_area(mesh, m.x), 1e-12 * r * r);
}

INSTANTIATE_TEST_SUITE_P(Scales, SphereAtScale, ::testing::Values(1e-3, 1.0, 1e3));

TEST(Curvature, InsideOutSphereHasNegativeMeanCurvature) {
  // Documented sign: H > 0 on a convex outward-oriented surface, so reversing every face flips
  // H (K does not depend on orientation).
  test::TriMesh m = test::icosphere(3, 2.0);
  m.faces.col(1).swap(m.faces.col(2));
  const CurvatureField c = compute_curvature(test::to_surface_mesh(m), m.x);
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) {
    EXPECT_NEAR(c.mean(i), -0.5, 0.01) << "vertex " << i;
    EXPECT_NEAR(c.gaussian(i), 0.25, 0.005) << "vertex " << i;
  }
}

TEST(Curvature, UsesTheGivenPositionsNotTheMeshPoints) {
  const test::TriMesh m = test::icosphere(3, 1.0);
  const Mesh mesh = test::to_surface_mesh(m);  // mesh points on the unit sphere
  const Positions deformed = 4.0 * m.x;        // sphere of radius 4
  const CurvatureField c = compute_curvature(mesh, deformed);
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) {
    EXPECT_NEAR(c.mean(i), 0.25, 0.25 * 0.02) << "vertex " << i;
    EXPECT_NEAR(c.gaussian(i), 1.0 / 16.0, 0.02 / 16.0) << "vertex " << i;
  }
}

TEST(Curvature, CylinderHasHalfInverseRadiusMeanAndZeroGaussianCurvature) {
  const double r = 0.7;
  const test::TriMesh m = tube(12, 64, r);
  const Mesh mesh = test::to_surface_mesh(m);
  const CurvatureField c = compute_curvature(mesh, m.x);
  int checked = 0;
  for (VertexIndex v : mesh.vertices()) {
    if (mesh.is_border(v)) continue;  // first and last ring: boundary, K meaningless there
    const auto i = static_cast<Eigen::Index>(v.idx());
    EXPECT_NEAR(c.mean(i) * r, 0.5, 0.02) << "vertex " << i;
    EXPECT_NEAR(c.gaussian(i) * r * r, 0.0, 0.02) << "vertex " << i;
    // k = H -+ sqrt(H^2 - K) with H r in [0.48, 0.52] and K r^2 in [-0.02, 0.02] lies within
    // 0.0613 of 0 and 1 (H^2 - K is near 1/4 r^2 here, where the root does not amplify errors).
    EXPECT_NEAR(c.k_min(i) * r, 0.0, 0.065) << "vertex " << i;
    EXPECT_NEAR(c.k_max(i) * r, 1.0, 0.065) << "vertex " << i;
    ++checked;
  }
  EXPECT_EQ(checked, 10 * 64);
}

TEST(Curvature, CubeCornersHaveDeficitHalfPi) {
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/cube.off");
  const CurvatureField c = compute_curvature(mesh, positions_from_mesh(mesh));
  ASSERT_EQ(c.angle_deficit.size(), 8);
  for (Eigen::Index i = 0; i < 8; ++i) {
    EXPECT_NEAR(c.angle_deficit(i), PI / 2, 1e-12) << "corner " << i;
    EXPECT_GT(c.gaussian(i), 0.0) << "corner " << i;
  }
}

TEST(Curvature, GaussBonnetOnIcospheres) {
  for (int level = 0; level <= 4; ++level) {
    const test::TriMesh m = test::icosphere(level, 1.0);
    const CurvatureField c = compute_curvature(test::to_surface_mesh(m), m.x);
    EXPECT_NEAR(c.angle_deficit.sum(), 4.0 * PI, 1e-9) << "level " << level;
  }
}

TEST(Curvature, GaussBonnetOnEveryClosedTestMesh) {
  int checked = 0;
  bool torus_seen = false;
  for (const auto& entry : std::filesystem::directory_iterator(test::MESH_DIR)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".off") continue;
    const Mesh mesh = read_input_mesh(entry.path().string());  // meshes/ top level: all closed
    const CurvatureField c = compute_curvature(mesh, positions_from_mesh(mesh));
    const long long chi = euler_characteristic(mesh);
    EXPECT_NEAR(c.angle_deficit.sum(), 2.0 * PI * static_cast<double>(chi), 1e-9) << entry.path();
    if (entry.path().filename() == "torus.off") {
      torus_seen = true;
      EXPECT_EQ(chi, 0);
      EXPECT_NEAR(c.angle_deficit.sum(), 0.0, 1e-9);
    }
    if (entry.path().filename() == "zero_area_face.off") {
      // The sliver face's angles are 0, 0, pi: still a pi per face, so Gauss-Bonnet holds.
      EXPECT_NEAR(c.angle_deficit.sum(), 4.0 * PI, 1e-9);
      for (Eigen::Index i = 0; i < c.mean.size(); ++i)
        EXPECT_TRUE(std::isfinite(c.mean(i)) && std::isfinite(c.gaussian(i))) << "vertex " << i;
    }
    ++checked;
  }
  EXPECT_TRUE(torus_seen) << "meshes/torus.off is part of the repository";
  EXPECT_GE(checked, 10);
}

TEST(Curvature, GaussBonnetOnPaperMeshes) {
  int found = 0;
  for (const char* name : {"eight", "hand", "elk", "bear"}) {
    const std::string path = std::string(test::PAPER_MESH_DIR) + "/" + name + ".off";
    if (!std::filesystem::exists(path)) continue;
    ++found;
    const Mesh mesh = read_input_mesh(path);
    const CurvatureField c = compute_curvature(mesh, positions_from_mesh(mesh));
    const long long chi = euler_characteristic(mesh);
    if (std::string(name) == "eight") {
      EXPECT_EQ(chi, -2) << "eight.off is a genus-2 surface";
    }
    EXPECT_NEAR(c.angle_deficit.sum(), 2.0 * PI * static_cast<double>(chi), 1e-9) << path;
  }
  if (found == 0) GTEST_SKIP() << "no paper meshes in " << test::PAPER_MESH_DIR << "; run scripts/fetch_paper_meshes.sh";
}

TEST(Curvature, DegenerateTrianglesAreGuarded) {
  // A triangle with a repeated point and one with three coincident points: angles pi/2, pi/2, 0
  // and pi/3 each (documented), no area, no cotangent weight, no NaN.
  Mesh mesh;
  const VertexIndex a = mesh.add_vertex(Point3(0, 0, 0)), b = mesh.add_vertex(Point3(1, 0, 0)),
                    c = mesh.add_vertex(Point3(0, 1, 0));
  mesh.add_face(a, b, c);
  Positions x(3, 3);
  x << 0, 0, 0, 0, 0, 0, 0, 1, 0;  // vertices 0 and 1 coincide
  CurvatureField f = compute_curvature(mesh, x);
  EXPECT_NEAR(f.angle_deficit(0), 2 * PI - PI / 2, 1e-15);
  EXPECT_NEAR(f.angle_deficit(1), 2 * PI - PI / 2, 1e-15);
  EXPECT_NEAR(f.angle_deficit(2), 2 * PI, 1e-15);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(f.mixed_area(i), 0.0);
    EXPECT_EQ(f.mean(i), 0.0);
    EXPECT_EQ(f.gaussian(i), 0.0);
  }
  x.setZero();
  f = compute_curvature(mesh, x);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(f.angle_deficit(i), 2 * PI - PI / 3, 1e-15);
}

TEST(Curvature, StoreCreatesThenOverwritesTheVertexMaps) {
  const test::TriMesh m = test::icosphere(2, 1.0);
  Mesh mesh = test::to_surface_mesh(m);
  store_curvature(mesh, compute_curvature(mesh, m.x));
  const Positions bigger = 2.0 * m.x;
  store_curvature(mesh, compute_curvature(mesh, bigger));  // second store must not throw
  const auto H = property::get_map<VertexIndex, double>(mesh, property::MEAN_CURVATURE);
  const auto K = property::get_map<VertexIndex, double>(mesh, property::GAUSSIAN_CURVATURE);
  for (VertexIndex v : mesh.vertices()) {
    EXPECT_NEAR(H[v], 0.5, 0.01) << "vertex " << v.idx();  // radius-2 values, not radius-1
    EXPECT_NEAR(K[v], 0.25, 0.01) << "vertex " << v.idx();
  }
}

TEST(Curvature, SizeMismatchIsAUsageError) {
  const test::TriMesh m = test::icosphere(1, 1.0);
  Mesh mesh = test::to_surface_mesh(m);
  const Positions fewer = m.x.topRows(m.x.rows() - 1);
  EXPECT_THROW(compute_curvature(mesh, fewer), UsageError);
  CurvatureField wrong;
  wrong.mean = Eigen::VectorXd::Zero(3);
  wrong.gaussian = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(store_curvature(mesh, wrong), UsageError);
}

}  // namespace
}  // namespace shellcontract
