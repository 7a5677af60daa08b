// A/B of the batched dihedral kernel in one binary: an older dihedral_batches.cpp (OLD_KERNEL, its
// public functions renamed old_*) against the tree's, on bench_projection's scene of bear
// (lab/benchmarks/projection_scene.hpp), one thread, PBD (/0) and XPBD (/1),
// the repetitions interleaved at random; first it prints how many vertices differ after three
// sweeps of each from the same state. Build and run: lab/kernels/README.md, "The dihedral kernel
// in three phases".
#include <benchmark/benchmark.h>
#include "pbd/constraint_batches.hpp"
#define make_dihedral_batches old_make_dihedral_batches
#define batch_atan2 old_batch_atan2
#define project_dihedral_hinge_batches old_project_dihedral_hinge_batches
#include OLD_KERNEL
#undef make_dihedral_batches
#undef batch_atan2
#undef project_dihedral_hinge_batches
#include <string>
#include <vector>
#include "../benchmarks/projection_scene.hpp"
#include "pbd/colouring.hpp"
#include "pbd/constraint_kernels.hpp"
#include "pbd/solver.hpp"

namespace {
using namespace shellcontract;
// bench_projection's scene (its dihedral hinges, masses and state), with the hinges in
// colour order and packed into batches as the Coloured solver holds them.
struct Scene : lab::ProjectionScene {
  ColouredBatches<DihedralBatch> b;
};
const Scene& scene() {
  static const Scene s = [] {
    Scene sc{lab::make_projection_scene(BEAR_OFF), {}};
    std::vector<DihedralHingeConstraint> c = sc.dihedral.dihedral_hinges;
    const Colouring col = colour_constraints(c);
    apply_order(c, col.order);
    sc.b = make_dihedral_batches(c, col.offsets);
    return sc;
  }();
  return s;
}
template <bool Old>
void run(benchmark::State& state) {
  const Scene& sc = scene();
  Positions x = sc.x;
  std::vector<PaddedVertex> xw(static_cast<std::size_t>(x.rows()));
  ProjectionContext ctx;
  ctx.x = x.data();
  ctx.w = sc.w.data();
  ctx.energy_floor = 1e-16;
  double* lam = nullptr;
  std::vector<double> lv;
  if (state.range(0)) { lv.assign(sc.b.batches.size() * 4, 0.0); lam = lv.data(); ctx.alpha_tilde = 1e-3; }
  for (auto _ : state) {
    state.PauseTiming();
    pack_padded(x.data(), sc.w.data(), 0, xw.size(), xw.data());
    if (lam) std::fill(lv.begin(), lv.end(), 0.0);
    state.ResumeTiming();
    if (Old) old_project_dihedral_hinge_batches(sc.b.batches.data(), sc.b.batches.size(), 0.01, xw.data(), ctx, lam, BatchIsa::Auto);
    else project_dihedral_hinge_batches(sc.b.batches.data(), sc.b.batches.size(), 0.01, xw.data(), ctx, lam, BatchIsa::Auto);
    benchmark::ClobberMemory();
  }
  state.counters["per_projection"] = benchmark::Counter(
      static_cast<double>(sc.dihedral.dihedral_hinges.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
void BM_Old(benchmark::State& s) { run<true>(s); }
void BM_New(benchmark::State& s) { run<false>(s); }
BENCHMARK(BM_Old)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_New)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
}  // namespace

// Bits: one PBD and one XPBD sweep of each from the same state, compared.
int main(int argc, char** argv) {
  const Scene& sc = scene();
  for (int xp = 0; xp < 2; ++xp) {
    std::vector<PaddedVertex> a(sc.x.rows()), b(sc.x.rows());
    Positions x = sc.x;
    pack_padded(x.data(), sc.w.data(), 0, a.size(), a.data());
    pack_padded(x.data(), sc.w.data(), 0, b.size(), b.data());
    ProjectionContext ctx; ctx.x = x.data(); ctx.w = sc.w.data(); ctx.energy_floor = 1e-16; ctx.alpha_tilde = 1e-3;
    std::vector<double> la(sc.b.batches.size() * 4, 0.0), lb = la;
    for (int it = 0; it < 3; ++it) {
      old_project_dihedral_hinge_batches(sc.b.batches.data(), sc.b.batches.size(), 0.01, a.data(), ctx, xp ? la.data() : nullptr, BatchIsa::Auto);
      project_dihedral_hinge_batches(sc.b.batches.data(), sc.b.batches.size(), 0.01, b.data(), ctx, xp ? lb.data() : nullptr, BatchIsa::Auto);
    }
    std::size_t diff = 0; double md = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      double d = std::abs(a[i].x - b[i].x) + std::abs(a[i].y - b[i].y) + std::abs(a[i].z - b[i].z);
      if (d != 0) ++diff; md = std::max(md, d);
    }
    std::printf("%s: %zu of %zu vertices differ, max |diff| %.3g\n", xp ? "xpbd" : "pbd", diff, a.size(), md);
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
}
