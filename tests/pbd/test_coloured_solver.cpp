// Coloured (parallel) constraint order (math-spec 9.4; issue "parallel constraint projection"):
// the colouring is a valid grouping, the coloured solve is bit-identical for 1, 2 and 4 threads,
// and it is a valid Gauss-Seidel solver (energy decreases, momentum conserved, close to the
// sequential order's result).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "material/registry.hpp"
#include "material/stvk.hpp"
#include "pbd/colouring.hpp"
#include "pbd/constraint_kernels.hpp"
#include "pbd/solver.hpp"
#include "sim/rest_state.hpp"
#include "support/cgal_mesh.hpp"

namespace shellcontract {
namespace {

/// Icosphere with its rest state: membranes, isometric AND dihedral hinges (both bending kinds
/// in one set, so one solve exercises every kind the coloured sweep handles).
struct Scene {
  ConstraintSet set;
  Eigen::VectorXd w;
  Positions x;  ///< compressed and perturbed: every constraint has work to do
};

/// How the scene's vertex ids are ordered: as the icosphere makes them, by height (spatially
/// coherent, as meshes usually come), or shuffled.
enum class Ids { Icosphere, ByHeight, Shuffled };

test::TriMesh renumbered(const test::TriMesh& m, Ids ids) {
  std::vector<int> order(static_cast<std::size_t>(m.x.rows()));
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  if (ids == Ids::ByHeight)
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return m.x(a, 2) < m.x(b, 2); });
  if (ids == Ids::Shuffled) std::shuffle(order.begin(), order.end(), std::mt19937(11));
  test::TriMesh out = m;
  std::vector<int> new_id(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    new_id[static_cast<std::size_t>(order[k])] = static_cast<int>(k);
    out.x.row(static_cast<Eigen::Index>(k)) = m.x.row(order[k]);
  }
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f)
    for (int c = 0; c < 3; ++c) out.faces(f, c) = new_id[static_cast<std::size_t>(m.faces(f, c))];
  return out;
}

Scene make_scene(int level, double scale = 0.85, double noise = 0.02, Ids ids = Ids::Icosphere) {
  const test::TriMesh sphere = renumbered(test::icosphere(level), ids);
  Mesh mesh = test::to_surface_mesh(sphere);
  build_rest_state(mesh, MassModel::AreaLumped, 1.0);
  Scene s;
  s.set = pack_constraints(mesh, BendingModel::Isometric);
  s.set.dihedral_hinges = pack_constraints(mesh, BendingModel::Dihedral).dihedral_hinges;
  s.w = inverse_masses(mesh);
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, noise);
  s.x = scale * sphere.x;
  for (Eigen::Index i = 0; i < s.x.size(); ++i) s.x.data()[i] += n(rng);
  return s;
}

template <class Record>
void expect_valid_colouring(const std::vector<Record>& records, const Colouring& c) {
  ASSERT_EQ(c.order.size(), records.size());
  ASSERT_EQ(c.offsets.front(), 0u);
  ASSERT_EQ(c.offsets.back(), records.size());
  std::set<std::size_t> seen(c.order.begin(), c.order.end());
  EXPECT_EQ(seen.size(), records.size()) << "order is not a permutation";
  for (int k = 0; k < c.num_colours(); ++k) {
    ASSERT_LT(c.offsets[k], c.offsets[k + 1]) << "empty colour " << k;
    std::set<int> used;
    for (std::size_t p = c.offsets[k]; p < c.offsets[k + 1]; ++p) {
      if (p > c.offsets[k]) {
        EXPECT_LT(c.order[p - 1], c.order[p]) << "colour not in array order";
      }
      for (int v : records[c.order[p]].v)
        EXPECT_TRUE(used.insert(v).second) << "colour " << k << " shares vertex " << v;
    }
  }
}

TEST(Colouring, NoTwoConstraintsOfAColourShareAVertex) {
  const Scene s = make_scene(3);
  const Colouring m = colour_constraints(s.set.membranes);
  const Colouring h = colour_constraints(s.set.isometric_hinges);
  expect_valid_colouring(s.set.membranes, m);
  expect_valid_colouring(s.set.isometric_hinges, h);
  // Lower bounds: a valence-6 vertex lies in 6 faces and in 12 hinges (6 edges, 6 opposite).
  EXPECT_GE(m.num_colours(), 6);
  EXPECT_GE(h.num_colours(), 12);
  // Greedy first-fit stays near those bounds on a regular mesh (what makes colouring pay).
  EXPECT_LE(m.num_colours(), 12);
  EXPECT_LE(h.num_colours(), 24);
  RecordProperty("membrane_colours", m.num_colours());
  RecordProperty("hinge_colours", h.num_colours());
}

TEST(Colouring, NeedsMoreThan64ColoursWhenOneVertexIsInEveryConstraint) {
  // 70 constraints all sharing vertex 0: 70 colours, past the first 64-bit mask word.
  std::vector<int> ids;
  for (int k = 0; k < 70; ++k) ids.insert(ids.end(), {0, k + 1});
  const Colouring c = greedy_vertex_colouring(ids, 2);
  EXPECT_EQ(c.num_colours(), 70);
  for (int k = 0; k < 70; ++k) EXPECT_EQ(c.order[k], static_cast<std::size_t>(k));
  EXPECT_THROW(greedy_vertex_colouring({0, 1, 2}, 2), std::invalid_argument);
}

TEST(Colouring, ApplyOrderPermutes) {
  std::vector<int> a{10, 11, 12, 13};
  apply_order(a, {2, 0, 3, 1});
  EXPECT_EQ(a, (std::vector<int>{12, 10, 13, 11}));
}

Positions solve_steps(const Scene& s, SolverSettings settings, int steps) {
  const auto solver = make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, settings);
  Positions x = s.x;
  for (int k = 0; k < steps; ++k) solver->solve(x, s.w);
  return x;
}

TEST(ColouredSolver, BitIdenticalForOneTwoAndFourThreads) {
  const Scene s = make_scene(4);  // 5120 faces: the big colours are split over the threads
  for (SolverKind kind : {SolverKind::Pbd, SolverKind::Xpbd}) {
    SolverSettings settings;
    settings.kind = kind;
    settings.order = ConstraintOrder::Coloured;
    settings.threads = 1;
    const Positions one = solve_steps(s, settings, 3);
    ASSERT_TRUE(one.allFinite());
    ASSERT_GT((one - s.x).cwiseAbs().maxCoeff(), 1e-4) << "the solve must move the vertices";
    for (int threads : {2, 4}) {
      settings.threads = threads;
      const Positions many = solve_steps(s, settings, 3);
      // Exact comparison on purpose: the order inside a colour cannot change a bit.
      EXPECT_TRUE((many.array() == one.array()).all())
          << (kind == SolverKind::Pbd ? "pbd" : "xpbd") << ", " << threads
          << " threads, max diff " << (many - one).cwiseAbs().maxCoeff();
    }
  }
}

double total(const ConstraintEnergies& e) { return e.membrane + e.bending + e.anisotropic; }

TEST(ColouredSolver, IsAValidGaussSeidelSolver) {
  // From a mildly compressed, perturbed sphere. PBD: membranes only, whose energy each sweep
  // must lower (PBD does not minimize a sum over kinds: with k_B a mere correction multiplier
  // the membrane steps raise the bending energy, in either order). XPBD: membranes and
  // rest-aware dihedral hinges, whose total energy it lowers.
  for (SolverKind kind : {SolverKind::Pbd, SolverKind::Xpbd}) {
    Scene s = make_scene(3, 0.95, 0.005);
    s.set.isometric_hinges.clear();
    if (kind == SolverKind::Pbd) s.set.dihedral_hinges.clear();
    const Eigen::VectorXd mass = s.w.cwiseInverse();
    SolverSettings seq;
    seq.kind = kind;
    SolverSettings col = seq;
    col.order = ConstraintOrder::Coloured;
    col.threads = 2;
    const auto seq_solver = make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, seq);
    const auto col_solver = make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, col);
    const double e0 = total(col_solver->energies(s.x));
    Positions xs = s.x, xc = s.x;
    seq_solver->solve(xs, s.w);
    col_solver->solve(xc, s.w);
    const double es = total(seq_solver->energies(xs)), ec = total(col_solver->energies(xc));
    const char* name = kind == SolverKind::Pbd ? "pbd" : "xpbd";
    ASSERT_GT(e0, 0.0);
    EXPECT_LT(es, 0.9 * e0) << name;
    EXPECT_LT(ec, 0.9 * e0) << name << ": coloured sweeps must lower the energy";
    // Same physics as the sequential order, not the same bits: energies within 25 %.
    EXPECT_NEAR(ec, es, 0.25 * es) << name;
    // Every projection conserves momentum (sum g = 0), so the whole solve does.
    const Eigen::RowVector3d p0 = mass.transpose() * s.x, pc = mass.transpose() * xc;
    EXPECT_LE((pc - p0).cwiseAbs().maxCoeff(), 1e-12 * mass.sum() * s.x.cwiseAbs().maxCoeff()) << name;
    // The two orders end close together relative to how far the solve moved the vertices.
    const double moved = (xs - s.x).norm(), apart = (xc - xs).norm();
    RecordProperty(std::string(name) + "_order_difference", std::to_string(apart / moved));
    EXPECT_LE(apart, 0.25 * moved) << name;
  }
}

TEST(ColouredSolver, ReportsColoursAndKeepsFacesForPerFaceOutput) {
  const Scene s = make_scene(3);
  SolverSettings settings;
  const auto seq = make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, settings);
  EXPECT_EQ(seq->colour_counts().membrane, 0);  // Sequential: no colouring
  settings.order = ConstraintOrder::Coloured;
  const auto col = make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, settings);
  const ColourCounts n = col->colour_counts();
  EXPECT_EQ(n.membrane, colour_constraints(s.set.membranes).num_colours());
  EXPECT_EQ(n.isometric, colour_constraints(s.set.isometric_hinges).num_colours());
  EXPECT_EQ(n.dihedral, colour_constraints(s.set.dihedral_hinges).num_colours());
  // Reordered constraints keep their face ids: per-face energies match the sequential solver's.
  const Eigen::VectorXd a = seq->face_energies(s.x, 1280), b = col->face_energies(s.x, 1280);
  EXPECT_GT(a.maxCoeff(), 0.0);
  EXPECT_TRUE(a.isApprox(b, 1e-14));
  EXPECT_NEAR(total(seq->energies(s.x)), total(col->energies(s.x)), 1e-12 * total(seq->energies(s.x)));
}

/// The scalar kernels over `set` in its array order (the coloured solver's sweep order, from
/// constraints()), `iterations` sweeps of membranes, isometric and dihedral hinges, and the
/// anisotropic faces with fibre energy `a` (if any) as the solver projects them: normals frozen
/// at the start, orientation +1, the paper's k_A projection in PBD.
template <class Material, class Aniso = NoAniso>
Positions reference_sweeps(const Material& m, const ConstraintSet& set, const Scene& s, bool xpbd,
                           int iterations, const Aniso& a = Aniso()) {
  Positions x = s.x;
  ProjectionContext ctx;
  ctx.x = x.data();
  ctx.w = s.w.data();
  ctx.energy_floor = 1e-16;   // 1e-16 x the largest modulus (1, MaterialParams{})
  ctx.alpha_tilde = 1e4;      // 1 / dt^2, dt = 0.01
  std::vector<double> lm(set.membranes.size()), li(3 * set.isometric_hinges.size()),
      ld(set.dihedral_hinges.size()), la(set.anisotropic.size());
  std::vector<Vec3> normal;
  for (const MembraneConstraint& c : set.anisotropic) {
    const Vec3 N = (Vec3(s.x.row(c.v[0])) - Vec3(s.x.row(c.v[2])))
                       .cross(Vec3(s.x.row(c.v[1])) - Vec3(s.x.row(c.v[2])));
    normal.push_back(N.normalized());
  }
  for (int it = 0; it < iterations; ++it) {
    for (std::size_t i = 0; i < set.membranes.size(); ++i)
      project_membrane(m, set.membranes[i], 1.0, ctx, xpbd ? &lm[i] : nullptr);
    for (std::size_t i = 0; i < set.isometric_hinges.size(); ++i)
      project_isometric_hinge(set.isometric_hinges[i], 0.01, ctx, xpbd ? &li[3 * i] : nullptr);
    for (std::size_t i = 0; i < set.dihedral_hinges.size(); ++i)
      project_dihedral_hinge(set.dihedral_hinges[i], 0.01, ctx, xpbd ? &ld[i] : nullptr);
    for (std::size_t i = 0; i < set.anisotropic.size(); ++i)
      if (xpbd)
        project_membrane(a, set.anisotropic[i], 1.0, ctx, &la[i]);
      else
        project_anisotropic_paper(a, set.anisotropic[i], set.anisotropic_k_a[i], normal[i], ctx);
  }
  return x;
}

/// Coloured-order settings of the tests below.
SolverSettings coloured(SolverKind kind, int iterations, int threads) {
  SolverSettings settings;
  settings.kind = kind;
  settings.order = ConstraintOrder::Coloured;
  settings.iterations = iterations;
  settings.threads = threads;
  return settings;
}

/// The coloured solve of `material` (and fibre energy `aniso`) against reference_sweeps.
template <class Material, class Aniso = NoAniso>
void expect_coloured_equals_scalar(const Scene& s, MaterialKind material, AnisoKind aniso,
                                   const MaterialParams& params, const std::string& name) {
  for (SolverKind kind : {SolverKind::Pbd, SolverKind::Xpbd}) {
    SolverSettings settings = coloured(kind, 3, 2);
    settings.aniso = aniso;
    const auto solver = make_constraint_solver(material, params, s.set, settings);
    Positions x = s.x;
    solver->solve(x, s.w);
    const bool xpbd = kind == SolverKind::Xpbd;
    const Positions ref = reference_sweeps(Material(params), solver->constraints(), s, xpbd, 3,
                                           Aniso(params));
    const double moved = (ref - s.x).cwiseAbs().maxCoeff();
    ASSERT_GT(moved, 1e-4);
    EXPECT_LE((x - ref).cwiseAbs().maxCoeff(), 1e-12 * moved) << name << (xpbd ? " xpbd" : " pbd");
  }
}

TEST(ColouredSolver, BatchedSolveEqualsTheScalarKernelsInColourOrder) {
  // The Coloured solver projects every material's membranes, the isometric and dihedral hinges
  // and the anisotropic faces in SIMD batches on padded rows. Its result must be what the
  // scalar kernels give in the same order, to rounding (FMA) relative to how far the vertices
  // moved.
  const Scene s = make_scene(3);
  MaterialParams p;
  p.c10 = 0.4;  // both Mooney-Rivlin terms, 2 (C10 + C01) = 1: the energy floor stays 1e-16
  p.c01 = 0.1;
  // Every registered material, walked from the registry (a new one is held to this unedited).
  for (const std::string& name : material_names()) {
    const MaterialKind kind = parse_material_kind(name);
    with_material(kind, p, [&](const auto& m) {
      expect_coloured_equals_scalar<std::decay_t<decltype(m)>>(s, kind, AnisoKind::None, p, name);
    });
  }
}

TEST(ColouredSolver, BatchedAnisotropicFacesEqualTheScalarKernelsInColourOrder) {
  // Every face also an E_A face with its own fibre and k_A (the paper's inward term in PBD).
  Scene s = make_scene(3);
  s.set.anisotropic = s.set.membranes;
  for (std::size_t i = 0; i < s.set.anisotropic.size(); ++i) {
    const double angle = 0.37 * static_cast<double>(i);
    s.set.anisotropic[i].data.fiber = Vec2(std::cos(angle), std::sin(angle));
    s.set.anisotropic_k_a.push_back(i % 3 == 0 ? 0.0 : 0.05);
  }
  MaterialParams p;
  p.fiber_target = 0.8;
  p.c10 = 0.4;  // as above, for Mooney-Rivlin
  p.c01 = 0.1;
  // Every registered fibre energy, each beside the next registered material in turn, so that
  // the fibre faces are seen with the C-form and the frame membranes.
  const std::vector<std::string> materials = material_names();
  std::size_t next = 0;
  for (const std::string& name : aniso_names()) {
    const AnisoKind aniso = parse_aniso_kind(name);
    if (aniso == AnisoKind::None) continue;
    const std::string& membrane = materials[next++ % materials.size()];
    const MaterialKind material = parse_material_kind(membrane);
    with_material(material, p, [&](const auto& m) {
      with_aniso(aniso, p, [&](const auto& a) {
        expect_coloured_equals_scalar<std::decay_t<decltype(m)>, std::decay_t<decltype(a)>>(
            s, material, aniso, p, membrane + " + fibre " + name);
      });
    });
  }
}

/// A closed bipyramid: `rim` vertices on a circle and two apexes; every face has an apex, so any
/// cut of the vertices leaves many faces on the interface.
Scene bipyramid_scene(int rim) {
  test::TriMesh m;
  m.x.resize(rim + 2, 3);
  for (int i = 0; i < rim; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * i / rim;
    m.x.row(i) << std::cos(a), std::sin(a), 0.0;
  }
  m.x.row(rim) << 0.0, 0.0, 1.0;
  m.x.row(rim + 1) << 0.0, 0.0, -1.0;
  m.faces.resize(2 * rim, 3);
  for (int i = 0; i < rim; ++i) {
    m.faces.row(2 * i) << i, (i + 1) % rim, rim;
    m.faces.row(2 * i + 1) << (i + 1) % rim, i, rim + 1;
  }
  Mesh mesh = test::to_surface_mesh(m);
  build_rest_state(mesh, MassModel::AreaLumped, 1.0);
  Scene s;
  s.set = pack_constraints(mesh, BendingModel::Isometric);
  s.w = inverse_masses(mesh);
  s.x = 0.9 * m.x;
  return s;
}

TEST(ColouredSolver, RegionalLayoutIsExactAndBitIdenticalForAnyThreadsWhateverTheIds) {
  // StVK membranes and isometric hinges only: the solver cuts its breadth-first row order in two
  // and runs the two parts' interiors in parallel, then the interface (solver.cpp, REGIONS). Its
  // result must be the scalar kernels' in its array order (membranes, then hinges), and the same
  // bits on 1, 2 and 4 threads, whether the input's ids are coherent or shuffled (the rows are
  // in breadth-first order either way).
  for (Ids ids : {Ids::ByHeight, Ids::Shuffled}) {
    Scene s = make_scene(4, 0.85, 0.02, ids);
    s.set.dihedral_hinges.clear();
    const char* name = ids == Ids::ByHeight ? "ids by height, " : "shuffled ids, ";
    for (SolverKind kind : {SolverKind::Pbd, SolverKind::Xpbd}) {
      SolverSettings settings = coloured(kind, 3, 1);
      const auto one_solver =
          make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, settings);
      ASSERT_TRUE(one_solver->colour_counts().regional) << name;
      EXPECT_EQ(one_solver->colour_counts().membrane,
                colour_constraints(s.set.membranes).num_colours());
      Positions one = s.x;
      one_solver->solve(one, s.w);
      const bool xpbd = kind == SolverKind::Xpbd;
      const Positions ref =
          reference_sweeps(Stvk(MaterialParams{}), one_solver->constraints(), s, xpbd, 3);
      const double moved = (ref - s.x).cwiseAbs().maxCoeff();
      ASSERT_GT(moved, 1e-4);
      EXPECT_LE((one - ref).cwiseAbs().maxCoeff(), 1e-12 * moved)
          << name << (xpbd ? "xpbd" : "pbd");
      for (int threads : {2, 4}) {
        settings.threads = threads;
        const auto solver =
            make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, settings);
        Positions many = s.x;
        for (int step = 0; step < 2; ++step) solver->solve(many, s.w);  // the schedule is reused
        Positions again = one;
        one_solver->solve(again, s.w);
        EXPECT_TRUE((many.array() == again.array()).all())
            << name << (xpbd ? "xpbd, " : "pbd, ") << threads << " threads, max diff "
            << (many - again).cwiseAbs().maxCoeff();
      }
    }
  }
}

TEST(ColouredSolver, KeepsOnePhasePerColourWhenMostConstraintsSpanEveryCut) {
  // Every face of a bipyramid has an apex: at least a third of the faces span any cut, so the
  // regional layout would run them on one thread; the solver keeps one phase per colour, and its
  // result is still the scalar kernels' in its order, bit-identical on 1 and 2 threads.
  const Scene s = bipyramid_scene(64);
  SolverSettings settings = coloured(SolverKind::Pbd, 3, 1);
  const auto one_solver =
      make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, settings);
  EXPECT_FALSE(one_solver->colour_counts().regional);
  Positions one = s.x;
  one_solver->solve(one, s.w);
  const Positions ref =
      reference_sweeps(Stvk(MaterialParams{}), one_solver->constraints(), s, false, 3);
  const double moved = (ref - s.x).cwiseAbs().maxCoeff();
  ASSERT_GT(moved, 1e-6);
  EXPECT_LE((one - ref).cwiseAbs().maxCoeff(), 1e-12 * moved);
  settings.threads = 2;
  Positions two = s.x;
  make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, settings)->solve(two, s.w);
  EXPECT_TRUE((two.array() == one.array()).all());
}

TEST(ColouredSolver, DefaultBendingKeepsOnePhasePerColour) {
  // StVK membranes with dihedral hinges (the default shell): both kinds run in batches, but not
  // in the regional layout, whose two parts would keep a many-core machine's other threads idle
  // (solver.cpp). Bit-identical on 1, 2 and 3 threads all the same.
  Scene s = make_scene(4, 0.85, 0.02, Ids::ByHeight);
  s.set.isometric_hinges.clear();
  SolverSettings settings = coloured(SolverKind::Xpbd, 3, 1);
  const auto one_solver =
      make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, settings);
  EXPECT_FALSE(one_solver->colour_counts().regional);
  Positions one = s.x;
  one_solver->solve(one, s.w);
  ASSERT_GT((one - s.x).cwiseAbs().maxCoeff(), 1e-4);
  for (int threads : {2, 3}) {
    settings.threads = threads;
    Positions many = s.x;
    make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, s.set, settings)->solve(many, s.w);
    EXPECT_TRUE((many.array() == one.array()).all()) << threads << " threads";
  }
}

TEST(ColouredSolver, RejectsNegativeThreads) {
  SolverSettings settings;
  settings.threads = -1;
  EXPECT_THROW(make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, ConstraintSet{}, settings),
               std::invalid_argument);
}

}  // namespace
}  // namespace shellcontract
