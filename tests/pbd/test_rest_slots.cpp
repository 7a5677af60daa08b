// A solver's rest data changed after it is built (ConstraintSolver::set_membrane_rest,
// set_dihedral_rest_angle; pbd/rest_slots.hpp): the rest shape taken from a deformed state makes
// that state stress-free in every order (the records, the packed copy and the batches all read
// it), and putting the built rest back gives the built solver's results bit for bit.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "bending/dihedral_bending.hpp"
#include "fem/triangle_element.hpp"
#include "pbd/solver.hpp"
#include "sim/rest_state.hpp"
#include "support/cgal_mesh.hpp"

namespace shellcontract {
namespace {

struct Scene {
  ConstraintSet set;
  Eigen::VectorXd w;
  Positions x;  ///< compressed and perturbed: every membrane and hinge is strained
};

Scene make_scene() {
  const test::TriMesh sphere = test::icosphere(2);
  Mesh mesh = test::to_surface_mesh(sphere);
  build_rest_state(mesh, MassModel::AreaLumped, 1.0);
  Scene s;
  s.set = pack_constraints(mesh, BendingModel::Dihedral);
  s.w = inverse_masses(mesh);
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 0.03);
  s.x = 0.85 * sphere.x;
  for (Eigen::Index i = 0; i < s.x.size(); ++i) s.x.data()[i] += n(rng);
  return s;
}

Vec3 at(const Positions& x, int v) { return Vec3(x.row(v)); }

/// Every membrane and hinge of the solver given its shape at x as its rest.
void rest_at(ConstraintSolver& solver, const Positions& x) {
  const std::vector<MembraneConstraint> membranes = solver.constraints().membranes;
  for (const MembraneConstraint& c : membranes) {
    const TriangleRest r = triangle_rest(at(x, c.v[0]), at(x, c.v[1]), at(x, c.v[2]));
    ASSERT_FALSE(r.degenerate);
    EXPECT_TRUE(solver.set_membrane_rest(c.face, r.Dm_inv, r.area));
  }
  const std::vector<DihedralHingeConstraint> hinges = solver.constraints().dihedral_hinges;
  for (std::size_t i = 0; i < hinges.size(); ++i) {
    const auto& v = hinges[i].v;
    double theta = 0.0;
    ASSERT_TRUE(dihedral_angle(at(x, v[0]), at(x, v[1]), at(x, v[2]), at(x, v[3]), theta));
    solver.set_dihedral_rest_angle(i, theta);
  }
}

struct Setting {
  ConstraintOrder order;
  int threads;
  SolverKind kind;
};

class RestSlots : public ::testing::TestWithParam<Setting> {};

SolverSettings settings_of(const Setting& p) {
  SolverSettings s;
  s.order = p.order;
  s.threads = p.threads;
  s.kind = p.kind;
  s.iterations = 3;
  return s;
}

TEST_P(RestSlots, TheStateTheRestWasTakenFromIsStressFree) {
  const Scene s = make_scene();
  const auto solver = make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, settings_of(GetParam()));
  const ConstraintEnergies before = solver->energies(s.x);
  ASSERT_GT(before.membrane, 1e-6);
  ASSERT_GT(before.bending, 1e-8);
  rest_at(*solver, s.x);
  const ConstraintEnergies after = solver->energies(s.x);
  EXPECT_LT(after.membrane, 1e-20 * before.membrane);
  EXPECT_LT(after.bending, 1e-20 * before.bending);
  // The sweeps (the batches in the coloured order, the packed records in the sequential one)
  // find nothing to do: had a copy kept the built rest, they would pull x back towards it.
  Positions x = s.x;
  solver->solve(x, s.w);
  EXPECT_LT((x - s.x).cwiseAbs().maxCoeff(), 1e-12);
}

TEST_P(RestSlots, TheBuiltRestPutBackGivesTheBuiltSolversResultsBitForBit) {
  const Scene s = make_scene();
  const SolverSettings settings = settings_of(GetParam());
  const auto built = make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, settings);
  const auto changed = make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, settings);
  const ConstraintSet original = changed->constraints();
  rest_at(*changed, s.x);
  for (const MembraneConstraint& c : original.membranes)
    EXPECT_TRUE(changed->set_membrane_rest(c.face, c.Dm_inv, c.rest_area));
  for (std::size_t i = 0; i < original.dihedral_hinges.size(); ++i)
    changed->set_dihedral_rest_angle(i, original.dihedral_hinges[i].rest.rest_angle);
  Positions a = s.x, b = s.x;
  built->solve(a, s.w);
  changed->solve(b, s.w);
  EXPECT_EQ(a, b);
  EXPECT_EQ(built->energies(a).membrane, changed->energies(a).membrane);
  EXPECT_EQ(built->energies(a).bending, changed->energies(a).bending);
}

INSTANTIATE_TEST_SUITE_P(Orders, RestSlots,
                         ::testing::Values(Setting{ConstraintOrder::Sequential, 1, SolverKind::Pbd},
                                           Setting{ConstraintOrder::Sequential, 1, SolverKind::Xpbd},
                                           Setting{ConstraintOrder::Coloured, 1, SolverKind::Pbd},
                                           Setting{ConstraintOrder::Coloured, 2, SolverKind::Xpbd}));

TEST(RestSlots, AFaceWithoutAMembraneIsRefused) {
  const Scene s = make_scene();
  const auto solver = make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, SolverSettings{});
  const Mat2 I = Mat2::Identity();
  EXPECT_FALSE(solver->set_membrane_rest(-1, I, 1.0));
  EXPECT_FALSE(solver->set_membrane_rest(static_cast<int>(s.set.membranes.size()) + 5, I, 1.0));
}

}  // namespace
}  // namespace shellcontract
