// --delta auto (sim/contact_distance.hpp): the paper's delta, or 1/80 of the mean edge length where
// that is smaller, or half the smallest rest gap where that is smaller still; the bound on a given
// delta and the warning for pairs held at rest. Checked against a regular tetrahedron's edge
// (closed form) and, through the Simulator and run_contraction, against the mean edge of an
// icosphere computed here from its arrays, not with CGAL.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/run.hpp"
#include "sim/contact_distance.hpp"
#include "sim/run_plan.hpp"
#include "sim/simulator.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/thin_card.hpp"
#include "test_paths.hpp"

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
  // A given delta is used as given (below an eighth of the mean edge: ADeltaAboveAnEighth...).
  o.auto_delta = false;
  o.collision.delta = 5.0 * share;
  EXPECT_EQ(Simulator(to_surface_mesh(sphere), o).options().collision.delta, 5.0 * share);
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

/// The unit cube with z scaled by `thickness`: its top and bottom faces `thickness` apart.
test::TriMesh thin_box(double thickness) {
  test::TriMesh m;
  m.x.resize(8, 3);
  m.x << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1;
  m.x.col(2) *= thickness;
  m.faces.resize(12, 3);
  m.faces << 0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7,
      6, 3, 0, 4, 3, 4, 7;
  return m;
}

TEST(ContactDistance, ADeltaAboveAnEighthOfTheMeanEdgeIsRefused) {
  // Before, a given delta was taken whatever the mesh: eight.off at --delta 0.1 swelled to 9.6
  // times its volume under a compressing pressure. Here ico2 with 0.05, above an eighth of its
  // mean edge; auto is never refused.
  const test::TriMesh sphere = test::icosphere(2, 3.0);
  const double bound = normalized_mean_edge(sphere) * MAX_DELTA_PER_MEAN_EDGE;
  SimOptions o;
  o.collision.delta = 0.05;
  ASSERT_GT(o.collision.delta, bound);
  try {
    Simulator(to_surface_mesh(sphere), o);
    ADD_FAILURE() << "0.05 was taken";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("above this mesh's bound"), std::string::npos) << e.what();
  }
  o.collision.delta = 0.99 * bound;
  EXPECT_EQ(Simulator(to_surface_mesh(sphere), o).options().collision.delta, 0.99 * bound);
  o.collision.delta = 0.05;
  o.auto_delta = true;
  EXPECT_LT(Simulator(to_surface_mesh(sphere), o).options().collision.delta, bound);
  o.collisions = false;  // no contact distance: nothing to refuse
  o.auto_delta = false;
  EXPECT_NO_THROW(Simulator(to_surface_mesh(sphere), o));
}

TEST(ContactDistance, AutoGoesBelowTheSmallestRestGap) {
  // A box 1e-4 thick (7.1e-5 of the diagonal): top and bottom were closer than the default delta
  // at rest, and the collision step held all eight vertices there for the whole run. Auto takes
  // half the gap; a given delta is kept, with a warning that names the pairs held.
  const test::TriMesh box = thin_box(1e-4);
  const double gap = 1e-4 / std::sqrt(2.0 + 1e-8);
  SimOptions o;
  o.auto_delta = true;
  SimPlan plan = plan_simulation(to_surface_mesh(box), o);
  EXPECT_NEAR(plan.options.collision.delta, 0.5 * gap, 1e-6 * gap);  // normalization rounds
  EXPECT_TRUE(plan.warnings.empty());
  o.auto_delta = false;
  plan = plan_simulation(to_surface_mesh(box), o);
  EXPECT_EQ(plan.options.collision.delta, 1e-4);
  ASSERT_EQ(plan.warnings.size(), 1u);
  EXPECT_NE(plan.warnings[0].find("holds their 8 vertices at their rest positions"),
            std::string::npos)
      << plan.warnings[0];
  // The cube itself has no gap below the default: nothing changes, nothing to say.
  o.auto_delta = true;
  plan = plan_simulation(to_surface_mesh(thin_box(1.0)), o);
  EXPECT_EQ(plan.options.collision.delta, 1e-4);
  EXPECT_TRUE(plan.warnings.empty());
}

TEST(ContactDistance, AutoStopsAtItsFloorAndSaysSo) {
  // A gap a million times below the default is a near-degenerate input: auto stops at
  // AUTO_DELTA_FLOOR_SHARE of the default and warns that the pairs closer than that are held.
  SimOptions o;
  o.auto_delta = true;
  const SimPlan plan = plan_simulation(to_surface_mesh(thin_box(1e-10)), o);
  EXPECT_EQ(plan.options.collision.delta, AUTO_DELTA_FLOOR_SHARE * 1e-4);
  // First the pairs the collision step's test at tolerance 0 takes for touching on a box this
  // thin (excluded, as named by PartsThatTouchAtRestAreNamedInAWarning), then the held ones.
  ASSERT_EQ(plan.warnings.size(), 2u);
  EXPECT_NE(plan.warnings[0].find("touch at rest"), std::string::npos) << plan.warnings[0];
  EXPECT_NE(plan.warnings[1].find("auto goes no lower"), std::string::npos) << plan.warnings[1];
}

TEST(ContactDistance, PairsWithinTwiceDeltaAtRestAreNamedAndAutoGoesBelowThem) {
  // A card 2e-4 thick (1.41e-4 of the diagonal): its sheets lie between delta (1e-4) and 2 delta
  // apart. They are not held, but a contact pushes them to 2 delta, beyond their rest gap, and
  // the card swelled to 3.7 times its volume under the default compressing run without a word.
  // A given delta now names them; auto surveys as far as the response pushes and takes half the
  // gap, as it does for a gap below delta.
  const Mesh card = to_surface_mesh(test::thin_card(2e-4));
  const double gap = 2e-4 / std::sqrt(2.0 + 4e-8);
  SimOptions o;
  SimPlan plan = plan_simulation(card, o);
  EXPECT_EQ(plan.options.collision.delta, 1e-4);
  ASSERT_EQ(plan.warnings.size(), 1u);
  EXPECT_NE(plan.warnings[0].find("between the contact distance 1e-04 and twice it at rest"),
            std::string::npos)
      << plan.warnings[0];
  EXPECT_NE(plan.warnings[0].find("beyond their rest gap"), std::string::npos) << plan.warnings[0];
  EXPECT_EQ(plan.warnings[0].find("holds their"), std::string::npos) << "no pair is held";
  o.auto_delta = true;
  plan = plan_simulation(card, o);
  EXPECT_NEAR(plan.options.collision.delta, 0.5 * gap, 1e-6 * gap);  // normalization rounds
  EXPECT_TRUE(plan.warnings.empty()) << plan.warnings[0];
  // A delta at most half the gap: the response pushes no pair beyond it.
  o.auto_delta = false;
  o.collision.delta = 0.49 * gap;
  EXPECT_TRUE(plan_simulation(card, o).warnings.empty());
  // Twice as thick (2.8e-4 apart, more than 2 delta): nothing to say.
  o.collision.delta = 1e-4;
  EXPECT_TRUE(plan_simulation(to_surface_mesh(test::thin_card(4e-4)), o).warnings.empty());
}

/// Two unit cubes (thin_box(1)), the second on top of the first with vertices of its own: the
/// lower cube's top face (vertices 4 to 7) and the upper one's bottom face (8 to 11) at z = 1,
/// `gap` apart.
test::TriMesh stacked_cubes(double gap) {
  const test::TriMesh cube = thin_box(1.0);
  test::TriMesh m;
  m.x.resize(16, 3);
  m.x << cube.x, cube.x;
  m.x.bottomRows(8).col(2).array() += 1.0 + gap;
  m.faces.resize(24, 3);
  m.faces << cube.faces, cube.faces.array() + 8;
  return m;
}

TEST(ContactDistance, PartsThatTouchAtRestAreNamedInAWarning) {
  // The collision step excludes the pairs that touch at rest for the whole run, so such parts
  // pressed together passed through each other (two balls pole to pole, stacked cubes under
  // inflation), and `check --against` saw nothing, without a word. The warning counts the pairs
  // the Simulator excludes and names the touching vertices (the lower cube's top corners).
  const Mesh touching = to_surface_mesh(stacked_cubes(0.0));
  SimOptions o;
  for (const bool automatic : {false, true}) {
    o.auto_delta = automatic;
    const SimPlan plan = plan_simulation(touching, o);
    ASSERT_EQ(plan.warnings.size(), 1u) << automatic;
    const std::string& w = plan.warnings[0];
    const std::size_t excluded = Simulator(touching, o).excluded_contact_pairs();
    ASSERT_GT(excluded, 0u);
    EXPECT_EQ(w.rfind(std::to_string(excluded) + " pairs of primitives (", 0), 0u) << w;
    EXPECT_NE(w.find("touch at rest, at or next to 8 vertices (4, 5, 6, 7, ...)"),
              std::string::npos)
        << w;
    EXPECT_NE(w.find("can pass through each other"), std::string::npos) << w;
    EXPECT_NE(w.find("Separate the parts by at least the contact distance 1e-04"),
              std::string::npos)
        << w;
  }
  // A gap of a hundredth of the diagonal: nothing touches, nothing is excluded, nothing to say.
  o.auto_delta = false;
  const Mesh apart = to_surface_mesh(stacked_cubes(0.02));
  EXPECT_TRUE(plan_simulation(apart, o).warnings.empty());
  EXPECT_EQ(Simulator(apart, o).excluded_contact_pairs(), 0u);
}

TEST(ContactDistance, TouchingAtAZeroAreaFaceIsNotCalledParts) {
  // zero_area_face.off is one closed cube whose face 13 (0, 2, 8) has its corners on one line:
  // vertex 8 lies on the edge from 0 to 2, so it touches the face on the other side of that
  // edge. The pairs are excluded as any touching pair, but there are no parts to separate or
  // join: the warning says where they are and what removes them.
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/zero_area_face.off");
  const SimPlan plan = plan_simulation(mesh, SimOptions{});
  ASSERT_EQ(plan.warnings.size(), 1u);
  const std::string& w = plan.warnings[0];
  EXPECT_NE(w.find("touch at rest, at or next to 1 vertex (8), each a corner of a zero-area face"),
            std::string::npos)
      << w;
  EXPECT_NE(w.find("removing the zero-area face"), std::string::npos) << w;
  EXPECT_EQ(w.find("Separate the parts"), std::string::npos) << w;
}

}  // namespace
}  // namespace shellcontract
