// Nanoseconds per constraint projection (issue: end-to-end contraction, acceptance "benchmark";
// issue "parallel constraint projection").
// One Gauss-Seidel sweep over every membrane / bending constraint of a mesh in a compressed
// state, positions restored (untimed) before each sweep so every projection does real work.
//  - BM_<kind>Pbd: the kernel in the paper's array order, single thread.
//  - BM_<kind>PbdColouredOrder: the same kernel over the constraints grouped by colour, single
//    thread (consecutive projections share no vertex, so they overlap in the CPU pipeline).
//  - BM_<kind>SolverSweep/<order>/<threads>: one sweep of the real solver (ConstraintSolver with
//    iterations = 1 and only that kind), order 0 = Sequential, 1 = Coloured, wall-clock time;
//    the speed-up of 2 threads is the ratio of the Coloured /1 and /2 times.
// Usage: bench_projection [--mesh=PATH] [google-benchmark flags]
// Default mesh: data/meshes/bear.off (scripts/fetch_paper_meshes.sh).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstring>
#include <iostream>
#include <string>
#include <type_traits>
#include <vector>

#include "material/stvk.hpp"
#include "pbd/colouring.hpp"
#include "pbd/constraint_batches.hpp"
#include "pbd/constraint_kernels.hpp"
#include "pbd/solver.hpp"
#include "projection_scene.hpp"

namespace {

using namespace shellcontract;

std::string g_mesh = std::string(SHELLCONTRACT_PAPER_MESH_DIR) + "/bear.off";

using Scene = lab::ProjectionScene;

const Scene& scene() {
  static const Scene s = lab::make_projection_scene(g_mesh);
  return s;
}

/// Times sweep(ctx, xw) with the state reset (untimed) before each sweep; xw holds the padded
/// rows of the batched kernels (x and w packed into it).
template <class Sweep>
void run_sweeps(benchmark::State& state, std::size_t count, Sweep sweep) {
  const Scene& sc = scene();
  Positions x = sc.x;
  std::vector<PaddedVertex> xw(static_cast<std::size_t>(x.rows()));
  ProjectionContext ctx;
  ctx.x = x.data();
  ctx.w = sc.w.data();
  ctx.energy_floor = 1e-16;
  for (auto _ : state) {
    state.PauseTiming();
    x = sc.x;
    pack_padded(x.data(), sc.w.data(), 0, xw.size(), xw.data());
    state.ResumeTiming();
    sweep(ctx, xw.data());
    benchmark::ClobberMemory();
  }
  state.counters["constraints"] = static_cast<double>(count);
  state.counters["per_projection"] = benchmark::Counter(
      static_cast<double>(count), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_MembraneStvkPbd(benchmark::State& state) {
  const auto& c = scene().membranes_and_isometric.membranes;
  const Stvk m(MaterialParams{});
  run_sweeps(state, c.size(), [&](const ProjectionContext& ctx, PaddedVertex*) {
    for (const MembraneConstraint& k : c) project_membrane(m, k, 1.0, ctx, nullptr);
  });
}

void BM_IsometricBendingPbd(benchmark::State& state) {
  const auto& c = scene().membranes_and_isometric.isometric_hinges;
  run_sweeps(state, c.size(), [&](const ProjectionContext& ctx, PaddedVertex*) {
    for (const IsometricHingeConstraint& k : c) project_isometric_hinge(k, 0.01, ctx, nullptr);
  });
}

void BM_DihedralBendingPbd(benchmark::State& state) {
  const auto& c = scene().dihedral.dihedral_hinges;
  run_sweeps(state, c.size(), [&](const ProjectionContext& ctx, PaddedVertex*) {
    for (const DihedralHingeConstraint& k : c) project_dihedral_hinge(k, 0.01, ctx, nullptr);
  });
}

/// Membranes grouped by colour and packed into SIMD batches, as the Coloured solver holds them.
ColouredBatches<MembraneBatch> coloured_membrane_batches() {
  std::vector<MembraneConstraint> c = scene().membranes_and_isometric.membranes;
  const Colouring col = colour_constraints(c);
  apply_order(c, col.order);
  std::vector<PackedMembrane> packed;
  for (const MembraneConstraint& k : c) packed.push_back(pack_membrane(k));
  return make_membrane_batches(packed, col.offsets);
}

ColouredBatches<IsometricBatch> coloured_isometric_batches() {
  std::vector<IsometricHingeConstraint> c = scene().membranes_and_isometric.isometric_hinges;
  const Colouring col = colour_constraints(c);
  apply_order(c, col.order);
  return make_isometric_batches(c, col.offsets);
}

ColouredBatches<DihedralBatch> coloured_dihedral_batches() {
  std::vector<DihedralHingeConstraint> c = scene().dihedral.dihedral_hinges;
  const Colouring col = colour_constraints(c);
  apply_order(c, col.order);
  return make_dihedral_batches(c, col.offsets);
}

/// state.range(0) = 0: the scalar kernels in colour order; 1: the batched path the solver runs
/// (AVX2 + FMA when the CPU has them, counter avx2 = 1).
void BM_MembraneStvkPbdColouredOrder(benchmark::State& state) {
  const ColouredBatches<MembraneBatch> b = coloured_membrane_batches();
  const Stvk m(MaterialParams{});
  const BatchIsa isa = state.range(0) == 0 ? BatchIsa::Scalar : BatchIsa::Auto;
  run_sweeps(state, scene().membranes_and_isometric.membranes.size(), [&](const ProjectionContext& ctx, PaddedVertex* xw) {
    project_stvk_membrane_batches(m, b.batches.data(), b.batches.size(), xw, ctx, nullptr, isa);
  });
  state.counters["colours"] = b.num_colours();
  state.counters["avx2"] = isa == BatchIsa::Auto && batch_avx2_available();
}

/// The other membrane materials: per-constraint kernel in array order, and the batched path of
/// the coloured order (range(0) as for BM_MembraneStvkPbdColouredOrder).
template <class M>
void membrane_pbd(benchmark::State& state) {
  const auto& c = scene().membranes_and_isometric.membranes;
  const M m(MaterialParams{});
  run_sweeps(state, c.size(), [&](const ProjectionContext& ctx, PaddedVertex*) {
    for (const MembraneConstraint& k : c) project_membrane(m, k, 1.0, ctx, nullptr);
  });
}

template <class M>
void membrane_coloured(benchmark::State& state) {
  const ColouredBatches<MembraneBatch> b = coloured_membrane_batches();
  const M m(MaterialParams{});
  const BatchIsa isa = state.range(0) == 0 ? BatchIsa::Scalar : BatchIsa::Auto;
  run_sweeps(state, scene().membranes_and_isometric.membranes.size(),
             [&](const ProjectionContext& ctx, PaddedVertex* xw) {
               if constexpr (std::is_same_v<M, Linear>)
                 project_linear_membrane_batches(m, b.batches.data(), b.batches.size(), xw, ctx, nullptr, isa);
               else if constexpr (std::is_same_v<M, Corotated>)
                 project_corotated_membrane_batches(m, b.batches.data(), b.batches.size(), xw, ctx, nullptr, isa);
               else
                 project_mooney_rivlin_membrane_batches(m, b.batches.data(), b.batches.size(), xw, ctx, nullptr, isa);
             });
  state.counters["avx2"] = isa == BatchIsa::Auto && batch_avx2_available();
}

void BM_MembraneCorotatedPbd(benchmark::State& state) { membrane_pbd<Corotated>(state); }
void BM_MembraneLinearPbd(benchmark::State& state) { membrane_pbd<Linear>(state); }
void BM_MembraneMooneyRivlinPbd(benchmark::State& state) { membrane_pbd<MooneyRivlin>(state); }
void BM_MembraneCorotatedPbdColouredOrder(benchmark::State& state) { membrane_coloured<Corotated>(state); }
void BM_MembraneLinearPbdColouredOrder(benchmark::State& state) { membrane_coloured<Linear>(state); }
void BM_MembraneMooneyRivlinPbdColouredOrder(benchmark::State& state) {
  membrane_coloured<MooneyRivlin>(state);
}

void BM_IsometricBendingPbdColouredOrder(benchmark::State& state) {
  const ColouredBatches<IsometricBatch> b = coloured_isometric_batches();
  const BatchIsa isa = state.range(0) == 0 ? BatchIsa::Scalar : BatchIsa::Auto;
  run_sweeps(state, scene().membranes_and_isometric.isometric_hinges.size(), [&](const ProjectionContext& ctx, PaddedVertex* xw) {
    project_isometric_hinge_batches(b.batches.data(), b.batches.size(), 0.01, xw, ctx, nullptr, isa);
  });
  state.counters["colours"] = b.num_colours();
  state.counters["avx2"] = isa == BatchIsa::Auto && batch_avx2_available();
}

void BM_DihedralBendingPbdColouredOrder(benchmark::State& state) {
  const ColouredBatches<DihedralBatch> b = coloured_dihedral_batches();
  const BatchIsa isa = state.range(0) == 0 ? BatchIsa::Scalar : BatchIsa::Auto;
  run_sweeps(state, scene().dihedral.dihedral_hinges.size(),
             [&](const ProjectionContext& ctx, PaddedVertex* xw) {
               project_dihedral_hinge_batches(b.batches.data(), b.batches.size(), 0.01, xw, ctx,
                                              nullptr, isa);
             });
  state.counters["colours"] = b.num_colours();
  state.counters["avx2"] = isa == BatchIsa::Auto && batch_avx2_available();
}

/// One sweep of the real solver over `set` (a single constraint kind), state.range(0) = order
/// (0 Sequential, 1 Coloured), state.range(1) = threads.
void solver_sweep(benchmark::State& state, const ConstraintSet& set, int iterations = 1) {
  const Scene& sc = scene();
  SolverSettings settings;
  settings.iterations = iterations;
  settings.order = state.range(0) == 0 ? ConstraintOrder::Sequential : ConstraintOrder::Coloured;
  settings.threads = static_cast<int>(state.range(1));
  const auto solver = make_constraint_solver(MaterialKind::Stvk, MaterialParams{}, set, settings);
  Positions x = sc.x;
  solver->solve(x, sc.w);  // warm-up: TBB starts its worker threads on first use
  for (auto _ : state) {
    state.PauseTiming();
    x = sc.x;
    state.ResumeTiming();
    solver->solve(x, sc.w);
    benchmark::ClobberMemory();
  }
  const std::size_t count =
      set.membranes.size() + set.isometric_hinges.size() + set.dihedral_hinges.size();
  const ColourCounts colours = solver->colour_counts();
  state.counters["colours"] = colours.membrane + colours.isometric + colours.dihedral;
  state.counters["per_projection"] = benchmark::Counter(
      static_cast<double>(count * iterations),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_MembraneStvkSolverSweep(benchmark::State& state) {
  ConstraintSet set;
  set.membranes = scene().membranes_and_isometric.membranes;
  solver_sweep(state, set);
}

void BM_IsometricBendingSolverSweep(benchmark::State& state) {
  ConstraintSet set;
  set.isometric_hinges = scene().membranes_and_isometric.isometric_hinges;
  solver_sweep(state, set);
}

/// Dihedral hinges (the default bending; in the coloured order in batches on the padded rows):
/// lab/pages/scale.md, "The whole run, and the solve in the coloured order".
void BM_DihedralBendingSolverSweep(benchmark::State& state) {
  ConstraintSet set;
  set.dihedral_hinges = scene().dihedral.dihedral_hinges;
  solver_sweep(state, set);
}

/// The solve of one time step: membranes and isometric hinges, 5 iterations (the defaults).
void BM_SolverStep(benchmark::State& state) {
  ConstraintSet set;
  set.membranes = scene().membranes_and_isometric.membranes;
  set.isometric_hinges = scene().membranes_and_isometric.isometric_hinges;
  solver_sweep(state, set, 5);
}

BENCHMARK(BM_MembraneStvkPbd)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IsometricBendingPbd)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DihedralBendingPbd)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MembraneStvkPbdColouredOrder)->Arg(0)->Arg(1)->ArgName("batched")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IsometricBendingPbdColouredOrder)->Arg(0)->Arg(1)->ArgName("batched")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DihedralBendingPbdColouredOrder)->Arg(0)->Arg(1)->ArgName("batched")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MembraneCorotatedPbd)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MembraneLinearPbd)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MembraneMooneyRivlinPbd)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MembraneCorotatedPbdColouredOrder)->Arg(0)->Arg(1)->ArgName("batched")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MembraneLinearPbdColouredOrder)->Arg(0)->Arg(1)->ArgName("batched")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MembraneMooneyRivlinPbdColouredOrder)->Arg(0)->Arg(1)->ArgName("batched")
    ->Unit(benchmark::kMicrosecond);
// {order, threads}: Sequential (threads unused), Coloured on 1 and 2 threads.
BENCHMARK(BM_MembraneStvkSolverSweep)->Args({0, 1})->Args({1, 1})->Args({1, 2})
    ->ArgNames({"order", "threads"})->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IsometricBendingSolverSweep)->Args({0, 1})->Args({1, 1})->Args({1, 2})
    ->ArgNames({"order", "threads"})->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DihedralBendingSolverSweep)->Args({0, 1})->Args({1, 1})->Args({1, 2})
    ->ArgNames({"order", "threads"})->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SolverStep)->Args({0, 1})->Args({1, 1})->Args({1, 2})
    ->ArgNames({"order", "threads"})->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  // Our own flag first, then Google Benchmark's.
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--mesh=", 7) == 0) {
      g_mesh = argv[i] + 7;
      for (int j = i; j + 1 < argc; ++j) argv[j] = argv[j + 1];
      --argc;
      --i;
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  try {
    scene();
  } catch (const std::exception& e) {
    std::cerr << "bench_projection: cannot load " << g_mesh << ": " << e.what()
              << "\n(run scripts/fetch_paper_meshes.sh, or pass --mesh=PATH)\n";
    return 2;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
