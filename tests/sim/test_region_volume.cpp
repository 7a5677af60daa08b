// The local contraction's cap-volume constraint (sim/region_volume.hpp): the cap volume against
// closed forms, its gradient against finite differences, and the projection's invariants.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sim/region_volume.hpp"
#include "sim/volume_constraint.hpp"
#include "support/icosphere_cap.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

/// A square pyramid: the rim (+-1, +-1, 0) counter-clockwise from above and the apex (0, 0, h);
/// its four faces face outward (up and away from the axis).
test::TriMesh pyramid(double h) {
  test::TriMesh m;
  m.x.resize(5, 3);
  m.x << 1, -1, 0, 1, 1, 0, -1, 1, 0, -1, -1, 0, 0, 0, h;
  m.faces.resize(4, 3);
  m.faces << 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4;
  return m;
}

std::vector<int> all_faces(const Faces& f) {
  std::vector<int> ids(static_cast<std::size_t>(f.rows()));
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<int>(i);
  return ids;
}

/// A perturbed open cap of the level-2 icosphere: its faces with a corner above z = z0.
test::CapScene cap_scene(double z0, unsigned seed) { return test::icosphere_cap(2, z0, 0.02, seed); }

/// meshes/cube.off: the unit cube, two triangles a side, counter-clockwise from outside (faces 0
/// and 1 the bottom, 2 and 3 the top, 4 and 5 the front at y = 0).
test::TriMesh unit_cube() {
  test::TriMesh m;
  m.x.resize(8, 3);
  m.x << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1;
  m.faces.resize(12, 3);
  m.faces << 0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7,
      6, 3, 0, 4, 3, 4, 7;
  return m;
}

TEST(RegionVolume, PiecesAreJoinedByEdgesOnly) {
  const test::TriMesh m = unit_cube();
  using Pieces = std::vector<std::vector<int>>;
  // A bottom and a top triangle of the cube: one fan over both rims closes a sixth of the cube,
  // a "cap" whose mirror drives the two triangles through each other (the blow-up at step 1 of
  // `run cube.off --regions` with the face list "0 3"). Each is a piece of its own, flat.
  const Pieces opposite = region_pieces(m.faces, {3, 0});
  EXPECT_EQ(opposite, (Pieces{{0}, {3}}));
  const RegionCap whole = make_region_cap(m.faces, {0, 3});
  EXPECT_NEAR(cap_volume(m.x, whole), 1.0 / 6.0, 1e-15);
  for (const std::vector<int>& piece : opposite)
    EXPECT_EQ(cap_volume(m.x, make_region_cap(m.faces, piece)), 0.0);
  EXPECT_EQ(region_pieces(m.faces, {0, 1, 2, 3}), (Pieces{{0, 1}, {2, 3}}));
  // Faces 4 (0, 1, 5) and 2 (4, 5, 6) share corner 5 only: separate pieces.
  EXPECT_EQ(region_pieces(m.faces, {0, 1, 2, 3, 4}), (Pieces{{0, 1, 4}, {2, 3}}));
  // Across the cube's edges: one piece, repeats and ids out of range dropped.
  EXPECT_EQ(region_pieces(m.faces, {5, 0, 4, 1, 5, -1, 12}), (Pieces{{0, 1, 4, 5}}));
  EXPECT_EQ(region_pieces(m.faces, {}), Pieces{});
}

TEST(RegionVolume, ACapWithEveryVertexOnItsRimMovesNoFartherThanMaxMove) {
  // Bottom, front and top of the cube: one piece, every vertex on its rim, whose cap (the fan
  // from the cube's centre) is half the cube. Mirroring it (target -V) shrinks it onto the
  // centre, where the gradient vanishes and the Newton steps throw the faces out of the mesh
  // (`run cube.off --regions` with "0 1 2 3 4 5" blew up at step 2).
  const test::TriMesh m = unit_cube();
  RegionCap cap = make_region_cap(m.faces, {0, 1, 2, 3, 4, 5});
  ASSERT_EQ(cap.rim.size(), cap.vertices.size());
  const double v0 = cap_volume(m.x, cap);
  EXPECT_NEAR(v0, 0.5, 1e-15);
  const double reach = cap_reach(m.x, cap);
  EXPECT_NEAR(reach, std::sqrt(3.0) / 2.0, 1e-15);  // the rim is all eight corners
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(8);
  auto farthest = [&](const Positions& x) { return (x - m.x).rowwise().norm().maxCoeff(); };

  Positions unbounded = m.x;
  project_cap_volume(unbounded, cap, w, -v0, 1e-12);
  EXPECT_GT(farthest(unbounded), std::sqrt(3.0));  // farther than the cube's diagonal

  Positions bounded = m.x;
  const int steps = project_cap_volume(bounded, cap, w, -v0, 1e-12, 4, reach);
  EXPECT_GE(steps, 1);
  EXPECT_LE(farthest(bounded), reach * (1.0 + 1e-12));
  EXPECT_TRUE(bounded.allFinite());
  EXPECT_LT(cap_volume(bounded, cap), v0);  // part of the way
  // Each call moves at most max_move, so later calls go on from there.
  Positions again = bounded;
  project_cap_volume(again, cap, w, -v0, 1e-12, 4, reach);
  EXPECT_LE((again - bounded).rowwise().norm().maxCoeff(), reach * (1.0 + 1e-12));

  // A bound the steps do not reach changes nothing, bit for bit.
  const test::CapScene s = cap_scene(0.4, 6);
  RegionCap c2 = make_region_cap(s.m.faces, s.region);
  const Eigen::VectorXd w2 = Eigen::VectorXd::Ones(s.m.x.rows());
  Positions a = s.m.x, b = s.m.x;
  const double t2 = -cap_volume(s.m.x, c2);
  project_cap_volume(a, c2, w2, t2, 1e-13);
  project_cap_volume(b, c2, w2, t2, 1e-13, 4, 100.0 * cap_reach(s.m.x, c2));
  EXPECT_EQ(a, b);
}

TEST(RegionVolume, PyramidCapIsTheConeOverItsRim) {
  for (double h : {0.7, 0.0, -0.7}) {
    const test::TriMesh m = pyramid(h);
    const RegionCap cap = make_region_cap(m.faces, all_faces(m.faces));
    EXPECT_EQ(cap.rim.size(), 4u);
    // Base area 4, height h: 4h/3 (> 0 bump, 0 flat, < 0 dent).
    EXPECT_NEAR(cap_volume(m.x, cap), 4.0 * h / 3.0, 1e-15) << "h " << h;
  }
}

TEST(RegionVolume, ARegionWithoutRimIsTheEnclosedVolume) {
  const test::TriMesh m = test::icosphere(2, 1.3);
  const RegionCap cap = make_region_cap(m.faces, all_faces(m.faces));
  EXPECT_TRUE(cap.rim.empty());
  EXPECT_NEAR(cap_volume(m.x, cap), signed_volume(m.x, m.faces), 1e-13);
}

TEST(RegionVolume, RimIsWhereRegionAndRestMeet) {
  const test::CapScene s = cap_scene(0.5, 1);
  const RegionCap cap = make_region_cap(s.m.faces, s.region);
  // On a closed manifold mesh a region vertex is on the rim iff it also has a face outside.
  std::vector<char> in(static_cast<std::size_t>(s.m.faces.rows()), 0);
  for (int f : s.region) in[static_cast<std::size_t>(f)] = 1;
  std::vector<char> touches_region(static_cast<std::size_t>(s.m.x.rows()), 0), touches_rest = touches_region;
  for (Eigen::Index j = 0; j < s.m.faces.rows(); ++j)
    for (int k = 0; k < 3; ++k)
      (in[static_cast<std::size_t>(j)] ? touches_region : touches_rest)[s.m.faces(j, k)] = 1;
  std::vector<int> want;
  for (std::size_t v = 0; v < touches_region.size(); ++v)
    if (touches_region[v] && touches_rest[v]) want.push_back(static_cast<int>(v));
  std::vector<int> got;
  for (int r : cap.rim) got.push_back(cap.vertices[static_cast<std::size_t>(r)]);
  EXPECT_FALSE(want.empty());
  EXPECT_EQ(got, want);
}

TEST(RegionVolume, GradientMatchesCentralDifferences) {
  const test::CapScene s = cap_scene(0.3, 2);
  const RegionCap cap = make_region_cap(s.m.faces, s.region);
  Positions g;
  cap_volume_gradient(s.m.x, cap, g);
  const double h = 1e-6;
  double worst = 0.0;
  for (std::size_t i = 0; i < cap.vertices.size(); ++i)
    for (int d = 0; d < 3; ++d) {
      Positions xp = s.m.x, xm = s.m.x;
      xp(cap.vertices[i], d) += h;
      xm(cap.vertices[i], d) -= h;
      const double fd = (cap_volume(xp, cap) - cap_volume(xm, cap)) / (2.0 * h);
      worst = std::max(worst, std::abs(fd - g(static_cast<Eigen::Index>(i), d)));
    }
  // V is cubic: the central difference's error is h^2 times third derivatives of order 1.
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(g.norm(), 0.1);
}

TEST(RegionVolume, RigidMotionKeepsTheVolumeAndTheGradientHasNoNetPart) {
  std::mt19937 rng(5);
  const test::CapScene s = cap_scene(0.4, 3);
  const RegionCap cap = make_region_cap(s.m.faces, s.region);
  const Mat3 R = test::random_rotation(rng);
  const Vec3 t = test::random_vec3(rng, 3.0);
  const Positions moved = (s.m.x * R.transpose()).rowwise() + t.transpose();
  EXPECT_NEAR(cap_volume(moved, cap), cap_volume(s.m.x, cap), 1e-13);
  Positions g;
  cap_volume_gradient(s.m.x, cap, g);
  EXPECT_LT(g.colwise().sum().norm(), 1e-14);
}

TEST(RegionVolume, ProjectionReachesTheTargetAndMovesNoCentreOfMass) {
  std::mt19937 rng(7);
  const test::CapScene s = cap_scene(0.4, 4);
  RegionCap cap = make_region_cap(s.m.faces, s.region);
  cap.rest_volume = cap_volume(s.m.x, cap);
  ASSERT_GT(cap.rest_volume, 0.0);
  Eigen::VectorXd w(s.m.x.rows());
  for (Eigen::Index i = 0; i < w.size(); ++i) w(i) = std::uniform_real_distribution<>(0.5, 2.0)(rng);
  Positions x = s.m.x;
  const double target = 0.4 * cap.rest_volume;
  project_cap_volume(x, cap, w, target, 1e-13);
  EXPECT_NEAR(cap_volume(x, cap), target, 1e-13);
  Vec3 moment = Vec3::Zero();  // sum of m_i dx_i: the centre of mass's displacement times M
  for (Eigen::Index i = 0; i < x.rows(); ++i) moment += Vec3(x.row(i) - s.m.x.row(i)) / w(i);
  EXPECT_LT(moment.norm(), 1e-14);
  EXPECT_GT((x - s.m.x).norm(), 1e-3);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    if (!std::binary_search(cap.vertices.begin(), cap.vertices.end(), static_cast<int>(i))) {
      EXPECT_EQ(x.row(i), s.m.x.row(i)) << "vertex " << i << " is not in the region";
    }
  }
  // A held vertex (w = 0, in contact) stays; the others still reach the target.
  w(cap.vertices[0]) = 0.0;
  x = s.m.x;
  project_cap_volume(x, cap, w, target, 1e-13);
  EXPECT_NEAR(cap_volume(x, cap), target, 1e-13);
  EXPECT_EQ(x.row(cap.vertices[0]), s.m.x.row(cap.vertices[0]));
}

TEST(RegionVolume, HeldVerticesKeepTheirShareOfTheCorrection) {
  // A pyramid whose rim the contacts hold: the apex alone would have to carry the whole volume
  // change (project_cap_volume with w = 0 on the rim moves it from h to -h in one step). Sharing,
  // the apex moves only as far as it would with nothing held, and V is linear in the apex height,
  // so one step leaves exactly the held vertices' share (1 - f) of the error.
  const double h = 0.5;
  const test::TriMesh m = pyramid(h);
  const RegionCap cap = make_region_cap(m.faces, all_faces(m.faces));
  const Eigen::VectorXd w = Eigen::VectorXd::Constant(5, 1.0);
  std::vector<char> held = {1, 1, 1, 1, 0};
  const double v0 = cap_volume(m.x, cap), target = -v0;
  Positions g;
  cap_volume_gradient(m.x, cap, g);
  const double f = g.row(4).squaredNorm() / g.rowwise().squaredNorm().sum();
  ASSERT_GT(f, 0.0);
  ASSERT_LT(f, 1.0);

  Positions free = m.x, shared = m.x;
  project_cap_volume(free, cap, w, target, 1e-14, 1);  // nothing held: every vertex moves
  EXPECT_EQ(project_cap_volume_sharing(shared, cap, w, held, target, 1e-14, 1), 1);
  EXPECT_EQ(shared.topRows(4), m.x.topRows(4));
  EXPECT_NEAR((shared.row(4) - m.x.row(4)).norm(), (free.row(4) - m.x.row(4)).norm(), 1e-15);
  EXPECT_NEAR(cap_volume(shared, cap) - target, (1.0 - f) * (v0 - target), 1e-14);

  // Every step leaves the held share (1 - f_k) of its error, f_k from that step's gradient (the
  // rim's rows change with the apex), so the apex never goes past its mirror height; four single
  // steps are the four-step call.
  Positions stepped = m.x;
  for (int k = 0; k < 4; ++k) {
    cap_volume_gradient(stepped, cap, g);
    const double fk = g.row(4).squaredNorm() / g.rowwise().squaredNorm().sum();
    const double before = cap_volume(stepped, cap) - target;
    project_cap_volume_sharing(stepped, cap, w, held, target, 1e-14, 1);
    EXPECT_NEAR(cap_volume(stepped, cap) - target, (1.0 - fk) * before, 1e-14) << "step " << k;
    EXPECT_GT(stepped(4, 2), -h);
  }
  shared = m.x;
  EXPECT_EQ(project_cap_volume_sharing(shared, cap, w, held, target, 1e-14, 4), 4);
  EXPECT_EQ(shared, stepped);

  // An all-zero held list is no held list, bit for bit (a perturbed cap, unequal masses;
  // project_cap_volume is the call with none).
  const test::CapScene s = cap_scene(0.4, 5);
  RegionCap c2 = make_region_cap(s.m.faces, s.region);
  Eigen::VectorXd w2(s.m.x.rows());
  std::mt19937 rng(3);
  for (Eigen::Index i = 0; i < w2.size(); ++i)
    w2(i) = std::uniform_real_distribution<>(0.5, 2.0)(rng);
  Positions a = s.m.x, b = s.m.x;
  const double t2 = 0.3 * cap_volume(s.m.x, c2);
  project_cap_volume(a, c2, w2, t2, 1e-13);
  project_cap_volume_sharing(b, c2, w2, std::vector<char>(static_cast<std::size_t>(w2.size()), 0),
                             t2, 1e-13);
  EXPECT_EQ(a, b);
}

}  // namespace
}  // namespace shellcontract
