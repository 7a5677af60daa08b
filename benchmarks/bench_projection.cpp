// Nanoseconds per constraint projection (issue: end-to-end contraction, acceptance "benchmark").
// Single thread, one Gauss-Seidel sweep over every membrane / bending constraint of a mesh in a
// compressed state, positions restored (untimed) before each sweep so every projection does
// real work. Usage: bench_projection [--mesh=PATH] [google-benchmark flags]
// Default mesh: data/meshes/bear.off (scripts/fetch_paper_meshes.sh).
#include <benchmark/benchmark.h>

#include <cstring>
#include <iostream>
#include <random>
#include <string>

#include "shellcontract/material/stvk.hpp"
#include "shellcontract/mesh/io.hpp"
#include "shellcontract/pbd/constraint_kernels.hpp"
#include "shellcontract/sim/simulator.hpp"

namespace {

using namespace shellcontract;

std::string g_mesh = std::string(SHELLCONTRACT_PAPER_MESH_DIR) + "/bear.off";

/// The scene: constraints of the normalized mesh and a compressed, perturbed state.
struct Scene {
  ConstraintSet membranes_and_isometric;
  ConstraintSet dihedral;
  Eigen::VectorXd w;
  Positions x;
};

const Scene& scene() {
  static const Scene s = [] {
    Scene sc;
    const Mesh mesh = read_input_mesh(g_mesh);
    SimOptions opt;
    opt.frames = 0;
    Simulator sim(mesh, opt);
    sc.membranes_and_isometric = pack_constraints(sim.rest_mesh(), BendingModel::Isometric);
    sc.dihedral = pack_constraints(sim.rest_mesh(), BendingModel::Dihedral);
    sc.w = inverse_masses(sim.rest_mesh());
    std::mt19937 rng(1);
    std::normal_distribution<double> n(0.0, 1e-3);
    sc.x = 0.9 * sim.positions();
    for (Eigen::Index i = 0; i < sc.x.size(); ++i) sc.x.data()[i] += n(rng);
    return sc;
  }();
  return s;
}

template <class Sweep>
void run_sweeps(benchmark::State& state, std::size_t count, Sweep sweep) {
  const Scene& sc = scene();
  Positions x = sc.x;
  ProjectionContext ctx;
  ctx.x = x.data();
  ctx.w = sc.w.data();
  ctx.energy_floor = 1e-16;
  for (auto _ : state) {
    state.PauseTiming();
    x = sc.x;
    state.ResumeTiming();
    sweep(ctx);
    benchmark::ClobberMemory();
  }
  state.counters["constraints"] = static_cast<double>(count);
  state.counters["per_projection"] = benchmark::Counter(
      static_cast<double>(count), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_MembraneStvkPbd(benchmark::State& state) {
  const auto& c = scene().membranes_and_isometric.membranes;
  const Stvk m(MaterialParams{});
  run_sweeps(state, c.size(), [&](const ProjectionContext& ctx) {
    for (const MembraneConstraint& k : c) project_membrane(m, k, 1.0, ctx, nullptr);
  });
}

void BM_IsometricBendingPbd(benchmark::State& state) {
  const auto& c = scene().membranes_and_isometric.isometric_hinges;
  run_sweeps(state, c.size(), [&](const ProjectionContext& ctx) {
    for (const IsometricHingeConstraint& k : c) project_isometric_hinge(k, 0.01, ctx, nullptr);
  });
}

void BM_DihedralBendingPbd(benchmark::State& state) {
  const auto& c = scene().dihedral.dihedral_hinges;
  run_sweeps(state, c.size(), [&](const ProjectionContext& ctx) {
    for (const DihedralHingeConstraint& k : c) project_dihedral_hinge(k, 0.01, ctx, nullptr);
  });
}

BENCHMARK(BM_MembraneStvkPbd)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IsometricBendingPbd)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DihedralBendingPbd)->Unit(benchmark::kMicrosecond);

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
