// --delta auto (sim/contact_distance.hpp): the paper's delta, or 1/80 of the mean edge length where
// that is smaller. Checked against a regular tetrahedron's edge (closed form) and, through the
// Simulator and run_contraction, against the mean edge of an icosphere computed here from its
// arrays, not with CGAL.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "shellcontract/run.hpp"
#include "sim/contact_distance.hpp"
#include "sim/simulator.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

/// The regular tetrahedron with corners at alternate corners of the cube [-s, s]^3: every edge is
/// 2 sqrt(2) s and the bounding-box diagonal 2 sqrt(3) s.
test::TriMesh tetrahedron(double s) {
  test::TriMesh m;
  m.x.resize(4, 3);
  m.x << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  m.x *= s;
  m.faces.resize(4, 3);
  m.faces << 0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2;
  return m;
}

/// Mean edge length over the bounding-box diagonal, each edge once, from the arrays.
double normalized_mean_edge(const test::TriMesh& m) {
  std::set<std::pair<int, int>> edges;
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      edges.insert(std::minmax(m.faces(f, k), m.faces(f, (k + 1) % 3)));
  double sum = 0.0;
  for (const auto& [a, b] : edges) sum += (m.x.row(a) - m.x.row(b)).norm();
  const double diagonal = (m.x.colwise().maxCoeff() - m.x.colwise().minCoeff()).norm();
  return sum / static_cast<double>(edges.size()) / diagonal;
}

TEST(ContactDistance, MeanEdgeOfARegularTetrahedron) {
  EXPECT_NEAR(mean_edge_length(to_surface_mesh(tetrahedron(0.5))), std::sqrt(2.0), 1e-15);
  EXPECT_EQ(mean_edge_length(Mesh()), 0.0);
}

TEST(ContactDistance, TheCapOrTheEdgeShareWhicheverIsSmaller) {
  // Normalized (diagonal 1): s = 1 / (2 sqrt 3), edge sqrt(2/3).
  const Mesh m = to_surface_mesh(tetrahedron(0.5 / std::sqrt(3.0)));
  const double share = std::sqrt(2.0 / 3.0) / 80.0;  // 0.0102
  EXPECT_NEAR(auto_contact_distance(m, 0.05), share, 1e-15);
  EXPECT_EQ(auto_contact_distance(m, 1e-4), 1e-4);
  // No edge: the cap, never 0.
  EXPECT_EQ(auto_contact_distance(Mesh(), 1e-4), 1e-4);
}

TEST(ContactDistance, TheSimulatorResolvesAutoOnTheNormalizedMesh) {
  // A sphere of radius 3: the share is taken of the normalized edges, not the input's.
  const test::TriMesh sphere = test::icosphere(2, 3.0);
  const double share = normalized_mean_edge(sphere) / 80.0;
  ASSERT_GT(share, 1e-4);  // so a cap of 0.05 takes the share and 1e-4 stays
  SimOptions o;
  o.collision.delta = 0.05;
  o.auto_delta = true;
  EXPECT_NEAR(Simulator(to_surface_mesh(sphere), o).options().collision.delta, share, 1e-15);
  o.auto_delta = false;
  EXPECT_EQ(Simulator(to_surface_mesh(sphere), o).options().collision.delta, 0.05);
  o.auto_delta = true;
  o.collision.delta = 1e-4;
  EXPECT_EQ(Simulator(to_surface_mesh(sphere), o).options().collision.delta, 1e-4);
  // Without collisions there is no contact distance to resolve: the options stay as given.
  o.collision.delta = 0.05;
  o.collisions = false;
  EXPECT_EQ(Simulator(to_surface_mesh(sphere), o).options().collision.delta, 0.05);
}

TEST(ContactDistance, TheRunReportsTheDeltaItUsed) {
  const test::TriMesh sphere = test::icosphere(2, 3.0);
  RunOptions r;
  r.sim.frames = 1;
  r.sim.collision.delta = 0.05;
  r.sim.auto_delta = true;
  EXPECT_NEAR(run_contraction(to_surface_mesh(sphere), r).contact_distance,
              normalized_mean_edge(sphere) / 80.0, 1e-15);
  r.sim.collisions = false;
  EXPECT_EQ(run_contraction(to_surface_mesh(sphere), r).contact_distance, 0.0);
}

}  // namespace
}  // namespace shellcontract
