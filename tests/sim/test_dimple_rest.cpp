// The mirrored dimple's rest state (sim/dimple_rest.hpp, docs/math/region-mirror.md section 6):
// once a dimple takes it, the dimple placed on its mirror image is stress-free (membranes and
// hinges, the rim's fold included), and a dimple that shrinks gives the solver back exactly the
// rest it was built with.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "pbd/solver.hpp"
#include "sim/dimple_rest.hpp"
#include "sim/region_dimple.hpp"
#include "sim/region_mirror.hpp"
#include "sim/rest_state.hpp"
#include "support/cgal_mesh.hpp"
#include "support/icosphere_cap.hpp"

namespace shellcontract {
namespace {

struct Fixture {
  test::CapScene s = test::icosphere_cap(3, 0.45, 0.02, 5);
  Mesh mesh;
  Eigen::VectorXd w;
  ConstraintSet set;
  RegionDimple d;
  Fixture() : mesh(test::to_surface_mesh(s.m)) {
    build_rest_state(mesh, MassModel::AreaLumped, 1.0);
    set = pack_constraints(mesh, BendingModel::Dihedral);
    w = inverse_masses(mesh);
    d = make_region_dimple(s.m.x, s.m.faces, s.region);
  }
  std::unique_ptr<ConstraintSolver> solver(ConstraintOrder order) const {
    SolverSettings settings;
    settings.order = order;
    return make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, set, settings);
  }
  /// The rest positions with the dimple's interior vertices on their mirror images.
  Positions dimpled() const {
    const RegionMirror mirror = make_region_mirror(s.m.x, d.dimple);
    EXPECT_EQ(mirror.fallback, MirrorFallback::None);
    Positions y = s.m.x;
    for (std::size_t i = 0; i < mirror.moved.size(); ++i)
      y.row(d.dimple.vertices[static_cast<std::size_t>(mirror.moved[i])]) =
          (mirror.image[i] + mirror.rest_centre).transpose();
    return y;
  }
};

class DimpleRest : public ::testing::TestWithParam<ConstraintOrder> {};

TEST_P(DimpleRest, TheDimpleOnItsMirrorImageIsStressFree) {
  Fixture f;
  set_dimple_size(f.d, f.s.m.faces, static_cast<int>(f.d.order.size() * 2 / 3));
  const Positions y = f.dimpled();
  const auto solver = f.solver(GetParam());
  const ConstraintEnergies before = solver->energies(y);
  ASSERT_GT(before.bending, 1e-6);  // the fold and the inverted cap
  ASSERT_GT(before.membrane, 0.0);  // the faces from the ragged rim to the images
  DimpleRestChange change;
  set_dimple_rest(*solver, HingeIndex(solver->constraints().dihedral_hinges, f.s.m.faces, {f.s.region}), f.s.m.x, f.s.m.faces,
                  f.d, change);
  EXPECT_EQ(change.faces.size(), static_cast<std::size_t>(f.d.size));
  EXPECT_FALSE(change.hinges.empty());
  const ConstraintEnergies after = solver->energies(y);
  EXPECT_LT(after.membrane, 1e-20 + 1e-12 * before.membrane);
  EXPECT_LT(after.bending, 1e-12 * before.bending);
  // The shell away from the dimple keeps its rest: at the rest positions only the dimple's own
  // faces and hinges are strained now.
  const ConstraintEnergies at_rest = solver->energies(f.s.m.x);
  EXPECT_GT(at_rest.bending, 0.0);
}

TEST_P(DimpleRest, ADimpleThatShrinksLeavesTheRestOfTheSmallerOneOnly) {
  Fixture f;
  const auto changed = f.solver(GetParam());
  const auto direct = f.solver(GetParam());
  const HingeIndex index(changed->constraints().dihedral_hinges, f.s.m.faces, {f.s.region});
  DimpleRestChange a, b;
  const int large = static_cast<int>(f.d.order.size() * 3 / 4), small = large / 3;
  set_dimple_size(f.d, f.s.m.faces, large);
  // A state that strains everything, the same for every solve below.
  Positions start = f.dimpled();
  start.array() *= 0.97;
  set_dimple_rest(*changed, index, f.s.m.x, f.s.m.faces, f.d, a);
  set_dimple_size(f.d, f.s.m.faces, small);
  set_dimple_rest(*changed, index, f.s.m.x, f.s.m.faces, f.d, a);
  set_dimple_rest(*direct, index, f.s.m.x, f.s.m.faces, f.d, b);
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.hinges, b.hinges);
  Positions x = start, y = start;
  changed->solve(x, f.w);
  direct->solve(y, f.w);
  EXPECT_EQ(x, y);
  // And size 0 gives back the built solver, bit for bit.
  set_dimple_size(f.d, f.s.m.faces, 0);
  set_dimple_rest(*changed, index, f.s.m.x, f.s.m.faces, f.d, a);
  EXPECT_TRUE(a.faces.empty() && a.hinges.empty());
  const auto built = f.solver(GetParam());
  Positions p = start, q = start;
  changed->solve(p, f.w);
  built->solve(q, f.w);
  EXPECT_EQ(p, q);
}

TEST_P(DimpleRest, TwoTouchingDimplesGiveTheSameRestInEitherOrder) {
  // The cap split into two regions along x = 0: their dimples share rim edges, whose hinges
  // neither sets, so the solver's rest does not depend on which dimple changed size last (as it
  // must not: a resumed run sets them in region order).
  Fixture f;
  std::vector<int> east, west;
  for (int face : f.s.region) {
    const double cx = f.s.m.x(f.s.m.faces(face, 0), 0) + f.s.m.x(f.s.m.faces(face, 1), 0) +
                      f.s.m.x(f.s.m.faces(face, 2), 0);
    (cx > 0.0 ? east : west).push_back(face);
  }
  RegionDimple a = make_region_dimple(f.s.m.x, f.s.m.faces, east);
  RegionDimple b = make_region_dimple(f.s.m.x, f.s.m.faces, west);
  set_dimple_size(a, f.s.m.faces, static_cast<int>(a.order.size()));
  set_dimple_size(b, f.s.m.faces, static_cast<int>(b.order.size()));
  const auto one = f.solver(GetParam());
  const auto two = f.solver(GetParam());
  const HingeIndex index(one->constraints().dihedral_hinges, f.s.m.faces, {east, west});
  DimpleRestChange ca1, cb1, ca2, cb2;
  set_dimple_rest(*one, index, f.s.m.x, f.s.m.faces, a, ca1);
  set_dimple_rest(*one, index, f.s.m.x, f.s.m.faces, b, cb1);
  set_dimple_rest(*two, index, f.s.m.x, f.s.m.faces, b, cb2);
  set_dimple_rest(*two, index, f.s.m.x, f.s.m.faces, a, ca2);
  ASSERT_FALSE(ca1.hinges.empty());
  for (std::size_t h : ca1.hinges)
    EXPECT_EQ(std::count(cb1.hinges.begin(), cb1.hinges.end(), h), 0) << "hinge " << h << " set by both";
  Positions x = f.s.m.x * 0.97, y = x;
  one->solve(x, f.w);
  two->solve(y, f.w);
  EXPECT_EQ(x, y);
}

TEST_P(DimpleRest, ARunOfSizesEndsAsItsLastSizeAlone) {
  // A run resizes a dimple nearly every step, and each call puts back only what it does not set
  // again: after growing, shrinking past a size, to 0 and growing again, the solver and the
  // record of what was set are those of one call at the last size.
  Fixture f;
  const auto changed = f.solver(GetParam());
  const HingeIndex index(changed->constraints().dihedral_hinges, f.s.m.faces, {f.s.region});
  DimpleRestChange a;
  const int n = static_cast<int>(f.d.order.size());
  for (int size : {1, 3, n / 4, n / 2, n / 2 + 1, n / 3, 0, n / 5, 3 * n / 4, n * 2 / 3}) {
    set_dimple_size(f.d, f.s.m.faces, size);
    set_dimple_rest(*changed, index, f.s.m.x, f.s.m.faces, f.d, a);
  }
  const auto direct = f.solver(GetParam());
  DimpleRestChange b;
  set_dimple_rest(*direct, index, f.s.m.x, f.s.m.faces, f.d, make_region_mirror(f.s.m.x, f.d.dimple),
                  b);
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.hinges, b.hinges);
  EXPECT_EQ(changed->constraints().dihedral_hinges.size(), direct->constraints().dihedral_hinges.size());
  for (std::size_t h = 0; h < direct->constraints().dihedral_hinges.size(); ++h)
    EXPECT_EQ(changed->constraints().dihedral_hinges[h].rest.rest_angle,
              direct->constraints().dihedral_hinges[h].rest.rest_angle) << "hinge " << h;
  Positions start = f.dimpled();
  start.array() *= 0.97;
  Positions x = start, y = start;
  changed->solve(x, f.w);
  direct->solve(y, f.w);
  EXPECT_EQ(x, y);
}

TEST(HingeIndex, EachFaceEdgeKnowsItsHingeAndTheFaceAcross) {
  Fixture f;
  const auto solver = f.solver(ConstraintOrder::Sequential);
  const std::vector<DihedralHingeConstraint>& hinges = solver->constraints().dihedral_hinges;
  const Faces& faces = f.s.m.faces;
  const HingeIndex index(hinges, faces, {f.s.region});
  ASSERT_EQ(index.record_of_face_edge.size(), static_cast<std::size_t>(3 * faces.rows()));
  const auto has_edge = [&](Eigen::Index g, int a, int b) {
    for (int e = 0; e < 3; ++e)
      if (std::minmax(faces(g, e), faces(g, (e + 1) % 3)) == std::minmax(a, b)) return true;
    return false;
  };
  int with_hinge = 0;
  for (Eigen::Index g = 0; g < faces.rows(); ++g)
    for (int e = 0; e < 3; ++e) {
      const int a = faces(g, e), b = faces(g, (e + 1) % 3);
      const auto slot = static_cast<std::size_t>(3 * g + e);
      const int across = index.face_across[slot];
      ASSERT_GE(across, 0);  // a closed mesh
      EXPECT_NE(across, g);
      EXPECT_TRUE(has_edge(across, a, b));
      const int record = index.record_of_face_edge[slot];
      if (record < 0) continue;
      ++with_hinge;
      const DihedralHingeConstraint& c = hinges[static_cast<std::size_t>(record)];
      EXPECT_EQ(std::minmax(c.v[0], c.v[1]), std::minmax(a, b));
    }
  EXPECT_EQ(with_hinge, static_cast<int>(2 * hinges.size()));  // every hinge from both its faces
}

INSTANTIATE_TEST_SUITE_P(Orders, DimpleRest,
                         ::testing::Values(ConstraintOrder::Sequential, ConstraintOrder::Coloured));

}  // namespace
}  // namespace shellcontract
