// run_error_ladder on a small icosphere under the default pressure: the reference compared with
// itself is exactly 0 (runs are deterministic), XPBD with 50 sweeps is closer to its reference
// than with 1, the reference check runs the refined reference (half step for XPBD, twice the
// sweeps for PBD) and reports its change, every run has the masses of the base step, and bad
// ladders are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "shellcontract/error.hpp"
#include "sim/error_ladder.hpp"
#include "sim/option_ranges.hpp"
#include "sim/simulator.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

Mesh sphere() { return test::to_surface_mesh(test::icosphere(2)); }

/// The setting these tests were written for (the paper's constant pressure and flat-rest
/// bending); with the defaults' dihedral bending and air the coloured-rung test takes ~6 minutes
/// instead of seconds on 2 cores.
SimOptions ladder_physics() {
  SimOptions s;
  s.air_balance = 0.0;
  s.pressure = 2.0;
  s.bending = BendingModel::Isometric;
  return s;
}

ErrorLadderOptions small_ladder() {
  ErrorLadderOptions o;
  o.frames = 20;
  o.iterations = {1, 5, 50};
  o.substeps = {1, 2};
  o.xpbd_reference_iterations = 50;
  o.xpbd_reference_substeps = 8;
  o.pbd_reference_iterations = 100;  // smaller than the default, to keep the test short
  return o;
}

const ErrorLadderRow& find(const ErrorLadderResult& r, SolverKind k, int it, int sub) {
  for (const ErrorLadderRow& row : r.rows)
    if (row.solver == k && row.iterations == it && row.substeps == sub) return row;
  throw std::runtime_error("row not found");
}

TEST(ErrorLadder, ReferenceAgainstItselfIsZero) {
  ErrorLadderOptions o = small_ladder();
  o.solvers = {SolverKind::Xpbd};
  o.iterations = {o.xpbd_reference_iterations};
  o.substeps = {o.xpbd_reference_substeps};
  o.check_reference = false;
  const ErrorLadderResult r = run_error_ladder(sphere(), ladder_physics(), o);
  ASSERT_EQ(r.rows.size(), 1u);
  EXPECT_FALSE(r.rows[0].failed);
  EXPECT_EQ(r.rows[0].hausdorff, 0.0);
  EXPECT_EQ(r.rows[0].max_vertex_error, 0.0);
  EXPECT_EQ(r.rows[0].volume_error, 0.0);
  EXPECT_EQ(r.rows[0].energy_error, 0.0);
  // The run did something: the sphere contracted.
  EXPECT_LT(r.rows[0].volume_ratio, 0.99);
  EXPECT_TRUE(r.references.empty());
}

TEST(ErrorLadder, MoreSweepsBringXpbdCloserAndTheReferenceCheckIsReported) {
  const ErrorLadderResult r = run_error_ladder(sphere(), SimOptions(), small_ladder());
  EXPECT_EQ(r.frames, 20);
  EXPECT_DOUBLE_EQ(r.simulated_time, 20 * SimOptions().dt);
  // PBD rungs: substeps 1 only (pbd_substeps off); XPBD: every substep count.
  EXPECT_EQ(r.rows.size(), 3u + 6u);
  for (const ErrorLadderRow& row : r.rows) {
    EXPECT_FALSE(row.failed) << row.failure;
    EXPECT_TRUE(std::isfinite(row.hausdorff));
    if (row.solver == SolverKind::Pbd) {
      EXPECT_EQ(row.substeps, 1);
    }
  }
  for (int sub : {1, 2}) {
    const ErrorLadderRow& one = find(r, SolverKind::Xpbd, 1, sub);
    const ErrorLadderRow& fifty = find(r, SolverKind::Xpbd, 50, sub);
    EXPECT_GT(one.hausdorff, 0.0);
    EXPECT_LT(fifty.hausdorff, one.hausdorff) << "substeps " << sub;
    // Not asserted for V/V0: with 2 substeps 1 sweep happens to land closer in volume (0.0015)
    // than 50 sweeps (0.0053) on this sphere while its surface is farther.
  }
  EXPECT_LT(find(r, SolverKind::Pbd, 50, 1).hausdorff, find(r, SolverKind::Pbd, 1, 1).hausdorff);

  ASSERT_EQ(r.references.size(), 2u);
  ASSERT_EQ(r.reference_rows.size(), 2u);
  for (const ReferenceCheck& c : r.references) {
    EXPECT_FALSE(c.failed) << c.failure;
    if (c.solver == SolverKind::Xpbd) {
      EXPECT_EQ(c.refined_substeps, 2 * c.substeps);
      EXPECT_EQ(c.refined_iterations, c.iterations);
    } else {
      EXPECT_EQ(c.refined_substeps, 1);
      EXPECT_EQ(c.refined_iterations, 2 * c.iterations);
    }
    // A different run: its change is measured, not zero by construction.
    EXPECT_GT(c.hausdorff, 0.0);
    EXPECT_EQ(c.converged, c.hausdorff < c.smallest_rung_hausdorff);
  }
  // XPBD's reference on this sphere is converged in the sense of the report.
  EXPECT_TRUE(r.references[1].converged) << r.references[1].hausdorff << " vs "
                                         << r.references[1].smallest_rung_hausdorff;
}

TEST(ErrorLadder, ColouredRungsAreComparedWithTheSequentialReferenceAndThreadsChangeNoBit) {
  ErrorLadderOptions o = small_ladder();
  o.solvers = {SolverKind::Xpbd};
  o.iterations = {1, 50};
  o.substeps = {8};
  o.orders = {ConstraintOrder::Sequential, ConstraintOrder::Coloured};
  o.threads = {1, 2};
  o.check_reference = false;
  const ErrorLadderResult r = run_error_ladder(sphere(), ladder_physics(), o);
  // Sequential: one rung per iteration count; Coloured: one per thread count as well.
  ASSERT_EQ(r.rows.size(), 2u + 4u);
  auto row = [&](ConstraintOrder order, int threads, int it) -> const ErrorLadderRow& {
    for (const ErrorLadderRow& x : r.rows)
      if (x.order == order && x.threads == threads && x.iterations == it) return x;
    throw std::runtime_error("row not found");
  };
  // The sequential rung with the reference's own settings is the reference: error exactly 0.
  EXPECT_EQ(row(ConstraintOrder::Sequential, 1, 50).hausdorff, 0.0);
  for (int it : {1, 50}) {
    const ErrorLadderRow& one = row(ConstraintOrder::Coloured, 1, it);
    const ErrorLadderRow& two = row(ConstraintOrder::Coloured, 2, it);
    EXPECT_FALSE(one.failed) << one.failure;
    // Threads change the time only: the same bits, so the same errors.
    EXPECT_EQ(one.hausdorff, two.hausdorff) << it << " iterations";
    EXPECT_EQ(one.max_vertex_error, two.max_vertex_error);
    EXPECT_EQ(one.volume_ratio, two.volume_ratio);
  }
  // Another order of the same model: not the reference's bits, but closer to it with more sweeps.
  EXPECT_GT(row(ConstraintOrder::Coloured, 1, 50).hausdorff, 0.0);
  EXPECT_LT(row(ConstraintOrder::Coloured, 1, 50).hausdorff,
            row(ConstraintOrder::Coloured, 1, 1).hausdorff);
}

TEST(ErrorLadder, EveryRunHasTheMassesOfTheBaseStep) {
  // Three light vertices that the pressure's mass floor raises at the base step and not at half
  // of it (sim/mass_scaling.hpp). Every run, at whatever fraction of the step, has the masses of
  // the base step, so the rungs and the reference are one model; before, the runs at dt / 2 and
  // the reference at dt / 4 had the lumped masses and the substeps-1 rungs the raised ones.
  const Mesh mesh = test::to_surface_mesh(test::icosphere_with_small_faces(2, 3));
  SimOptions base = ladder_physics();
  base.pressure = 4.0;
  base.collisions = false;
  const MassScaling at_base = Simulator(mesh, base).mass_scaling();
  ASSERT_GT(at_base.raised, 0u);
  SimOptions half = base;
  half.dt /= 2.0;
  ASSERT_EQ(Simulator(mesh, half).mass_scaled_vertices(), 0u);

  ErrorLadderOptions o = small_ladder();
  o.solvers = {SolverKind::Xpbd};
  o.iterations = {5};
  o.substeps = {1, 2, 4};
  o.xpbd_reference_substeps = 4;
  o.frames = 5;
  const ErrorLadderResult r = run_error_ladder(mesh, base, o);
  EXPECT_EQ(r.mass_scaled_vertices, at_base.raised);
  EXPECT_EQ(r.largest_mass_factor, at_base.largest_factor);
  ASSERT_EQ(r.rows.size(), 3u);
  ASSERT_EQ(r.reference_rows.size(), 1u);
  std::vector<ErrorLadderRow> runs = r.rows;
  runs.push_back(r.reference_rows[0]);
  for (const ErrorLadderRow& row : runs) {
    EXPECT_FALSE(row.failed) << row.failure;
    EXPECT_EQ(row.mass_scaled_vertices, at_base.raised) << "substeps " << row.substeps;
    EXPECT_EQ(row.largest_mass_factor, at_base.largest_factor) << "substeps " << row.substeps;
  }
}

TEST(ErrorLadder, RefusesEmptyOrNonPositiveLists) {
  ErrorLadderOptions o = small_ladder();
  o.iterations.clear();
  EXPECT_THROW(run_error_ladder(sphere(), ladder_physics(), o), UsageError);
  o = small_ladder();
  o.substeps = {0};
  EXPECT_THROW(run_error_ladder(sphere(), ladder_physics(), o), UsageError);
  o = small_ladder();
  o.frames = 0;
  EXPECT_THROW(run_error_ladder(sphere(), ladder_physics(), o), UsageError);
  o = small_ladder();
  o.threads = {0};
  EXPECT_THROW(run_error_ladder(sphere(), ladder_physics(), o), UsageError);
  o = small_ladder();
  o.orders.clear();
  EXPECT_THROW(run_error_ladder(sphere(), ladder_physics(), o), UsageError);
}

TEST(ErrorLadder, RefusesMoreStepsThanARunTakesBeforeRunningAny) {
  // A rung or reference of k substeps runs frames * k steps: 3 frames of 1431655766 reference
  // substeps are 2^32 + 2 steps, which an int product wrapped to 2 (a reference of two steps, and
  // every rung measured against nearly the rest state; review numguards L1); 2 frames of INT_MAX
  // wrapped to a negative count. Each is refused, naming the frames and substeps, before a run.
  for (const auto& [frames, ref_substeps, check] :
       {std::tuple{3, 1431655766, false}, std::tuple{2, 2147483647, false},
        std::tuple{1, option_ranges::MAX_FRAMES / 2 + 1, true},
        std::tuple{option_ranges::MAX_FRAMES / 8 + 1, 8, false}}) {
    ErrorLadderOptions o = small_ladder();
    o.solvers = {SolverKind::Xpbd};
    o.frames = frames;
    o.xpbd_reference_substeps = ref_substeps;
    o.check_reference = check;
    bool ran = false;
    o.progress = [&](const std::string&) { ran = true; };
    try {
      run_error_ladder(sphere(), ladder_physics(), o);
      ADD_FAILURE() << frames << " frames of " << ref_substeps << " reference substeps ran";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("(-n)"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(ran) << frames << " frames of " << ref_substeps << " reference substeps";
  }
  // PBD's rungs take one substep unless asked otherwise: their steps are the frames.
  ErrorLadderOptions o = small_ladder();
  o.solvers = {SolverKind::Pbd};
  o.frames = option_ranges::MAX_FRAMES / 2 + 1;
  o.substeps = {2};
  o.pbd_substeps = true;
  EXPECT_THROW(run_error_ladder(sphere(), ladder_physics(), o), UsageError);
}

}  // namespace
}  // namespace shellcontract
