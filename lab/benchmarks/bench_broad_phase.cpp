// Time per CCD broad-phase call (math-spec 10.2) for each BroadPhaseMethod, with the candidate
// counts of the paper's Table 2 (no culling, box overlaps, emitted VF / EE pairs).
// Scene: the mesh scaled to bounding-box diagonal 1 (math-spec 1.2), moved by one realistic
// contraction step: x1 = c + 0.99 (x0 - c) + noise (c = centroid, noise 1e-3 x mean edge length
// per coordinate), inflation 1e-4 x diagonal (the paper's delta in normalized units).
// Usage: bench_broad_phase [--mesh=PATH] [--end=PATH] [--inflation=I] [--far=D] [benchmark flags]
// (--end: end positions from a second mesh of the same connectivity, e.g. the next frame)
// (inflation and far distance x diagonal; defaults 1e-4 and none. The collision step's call is
// --inflation=5e-4 --far=1e-4; a mesh written by a long run gives its collapsed state.)
// Default mesh: data/meshes/bear.off (scripts/fetch_paper_meshes.sh); if it is missing, an
// icosphere with 5 subdivision levels (10242 vertices) is used instead.
#include <benchmark/benchmark.h>

#include <cstring>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "../tests/support/mesh_fixtures.hpp"
#include "collision/broad_phase.hpp"
#include "collision/broad_phase/grid.hpp"
#include "collision/broad_phase/scratch.hpp"
#include "collision/cull_batch.hpp"

namespace {

using namespace shellcontract;

std::string g_mesh = std::string(SHELLCONTRACT_PAPER_MESH_DIR) + "/bear.off";
/// Box inflation and the far distance of the close flags (negative: none), x diagonal. The
/// collision step calls the grid with 5e-4 (delta + the 4 delta region margin) and 1e-4 (delta).
double g_inflation = 1e-4;
double g_far = -1.0;
/// If set, the end positions are read from this mesh (same connectivity, e.g. the next frame of
/// a run) instead of the synthetic contraction step.
std::string g_end;

/// Minimal OFF reader (triangles only; polygons are fanned): enough for the paper meshes.
test::TriMesh read_off(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  // Tokens without comments.
  std::stringstream body;
  for (std::string line; std::getline(in, line);) body << line.substr(0, line.find('#')) << '\n';
  std::string magic;
  body >> magic;
  if (magic != "OFF") throw std::runtime_error(path + ": not an OFF file");
  long nv = 0, nf = 0, ne = 0;
  body >> nv >> nf >> ne;
  test::TriMesh m;
  m.x.resize(nv, 3);
  for (long i = 0; i < nv; ++i) body >> m.x(i, 0) >> m.x(i, 1) >> m.x(i, 2);
  std::vector<std::array<int, 3>> tris;
  for (long j = 0; j < nf; ++j) {
    int k = 0;
    body >> k;
    std::vector<int> ids(static_cast<std::size_t>(k));
    for (int& id : ids) body >> id;
    for (int t = 1; t + 1 < k; ++t)
      tris.push_back({ids[0], ids[static_cast<std::size_t>(t)], ids[static_cast<std::size_t>(t) + 1]});
  }
  if (!body) throw std::runtime_error(path + ": truncated OFF file");
  m.faces.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t j = 0; j < tris.size(); ++j)
    m.faces.row(static_cast<Eigen::Index>(j)) << tris[j][0], tris[j][1], tris[j][2];
  return m;
}

struct Scene {
  std::string name;
  CollisionTopology topo;
  Positions x0, x1;
  double inflation = 0.0;
};

const Scene& scene() {
  static const Scene s = [] {
    Scene sc;
    test::TriMesh m;
    if (std::ifstream(g_mesh).good()) {
      m = read_off(g_mesh);
      sc.name = g_mesh;
    } else {
      std::cerr << "bench_broad_phase: " << g_mesh << " not found, using icosphere level 5\n";
      m = test::icosphere(5);
      sc.name = "icosphere(5)";
    }
    const Vec3 lo = m.x.colwise().minCoeff().transpose(), hi = m.x.colwise().maxCoeff().transpose();
    sc.x0 = m.x / (hi - lo).norm();  // diagonal 1 (math-spec 1.2)
    sc.topo = make_collision_topology(m.faces, static_cast<int>(m.x.rows()));
    double mean_edge = 0.0;
    for (Eigen::Index e = 0; e < sc.topo.edges.rows(); ++e)
      mean_edge += (sc.x0.row(sc.topo.edges(e, 0)) - sc.x0.row(sc.topo.edges(e, 1))).norm();
    mean_edge /= static_cast<double>(sc.topo.edges.rows());
    const Eigen::RowVector3d c = sc.x0.colwise().mean();
    std::mt19937 rng(1);
    std::normal_distribution<double> noise(0.0, 1e-3 * mean_edge);
    sc.x1 = (0.99 * (sc.x0.rowwise() - c)).rowwise() + c;
    for (Eigen::Index i = 0; i < sc.x1.size(); ++i) sc.x1.data()[i] += noise(rng);
    if (!g_end.empty()) {
      const test::TriMesh end = read_off(g_end);
      if (end.x.rows() != m.x.rows()) throw std::runtime_error(g_end + ": vertex count differs");
      sc.x1 = end.x / (hi - lo).norm();
    }
    sc.inflation = g_inflation;  // x diagonal (= 1)
    std::cerr << "bench_broad_phase: " << sc.name << ": " << sc.x0.rows() << " vertices, "
              << sc.topo.faces.rows() << " faces, " << sc.topo.edges.rows()
              << " edges, mean edge " << mean_edge << " (diagonal 1)\n";
    return sc;
  }();
  return s;
}

void BM_FindCandidates(benchmark::State& state, BroadPhaseMethod method) {
  const Scene& sc = scene();
  CandidatePairs out;
  // Every call on the same scene: a kept grid would be patched with nothing to change, which is
  // not a step's cost; each call builds its grid afresh (a step patches it: README).
  out.scratch->grid_patch = false;
  BroadPhaseStats stats;
  for (auto _ : state) {
    find_candidates(sc.x0, sc.x1, sc.topo, sc.inflation, out, &stats, method, g_far);
    benchmark::DoNotOptimize(out.vertex_face.data());
    benchmark::DoNotOptimize(out.edge_edge.data());
  }
  state.counters["no_culling_vf"] = static_cast<double>(stats.no_culling_vertex_face);
  state.counters["no_culling_ee"] = static_cast<double>(stats.no_culling_edge_edge);
  state.counters["box_overlaps"] = static_cast<double>(stats.box_overlaps);
  state.counters["vf"] = static_cast<double>(stats.vertex_face);
  state.counters["ee"] = static_cast<double>(stats.edge_edge);
  // 0 if the method fell back to another (Grid on a degenerate scene): the time is then not its.
  state.counters["own_path"] = stats.method_run == method ? 1.0 : 0.0;
}

/// The speculative task's call (SelfCollision::predict): the Grid on given vertex boxes (here the
/// swept boxes of the scene grown by the inflation), with the exact double cell loop or the
/// float superset one (BroadPhaseScratch::grid_float_superset).
void BM_GridOnVertexBoxes(benchmark::State& state, bool float_superset) {
  const Scene& sc = scene();
  std::vector<detail::GridVertexBox> boxes(static_cast<std::size_t>(sc.x0.rows()));
  for (Eigen::Index v = 0; v < sc.x0.rows(); ++v)
    for (Eigen::Index d = 0; d < 3; ++d) {
      detail::GridVertexBox& b = boxes[static_cast<std::size_t>(v)];
      b.lo[static_cast<std::size_t>(d)] = std::min(sc.x0(v, d), sc.x1(v, d)) - sc.inflation;
      b.hi[static_cast<std::size_t>(d)] = std::max(sc.x0(v, d), sc.x1(v, d)) + sc.inflation;
    }
  CandidatePairs out;
  out.scratch->grid_patch = false;  // as BM_FindCandidates
  out.scratch->grid_float_superset = float_superset;
  double cell_loop = 0.0;
  for (auto _ : state) {
    if (!find_candidates_in_vertex_boxes(boxes, sc.topo, out))
      state.SkipWithError("the grid degenerated");
    cell_loop += out.scratch->grid_cell_loop_seconds;
    benchmark::DoNotOptimize(out.vertex_face.data());
    benchmark::DoNotOptimize(out.edge_edge.data());
  }
  state.counters["vf"] = static_cast<double>(out.vertex_face.size());
  state.counters["ee"] = static_cast<double>(out.edge_edge.size());
  const auto calls = std::max<benchmark::IterationCount>(1, state.iterations());
  state.counters["cell_loop_ms"] = 1e3 * cell_loop / static_cast<double>(calls);
}

/// The Grid's cell loop per unit of its pair work (the entry pairs of every cell, which
/// GRID_WORK_PER_BOX limits), with the AVX-512 loop (Auto, where the CPU has it) or the portable
/// one: what a box costs the grid at a given work, against what PrimitiveBoxes costs per box.
void BM_GridCellLoop(benchmark::State& state, detail::GridIsa isa) {
  const Scene& sc = scene();
  CandidatePairs out;
  out.scratch->grid_patch = false;  // as BM_FindCandidates
  out.scratch->grid_isa = isa;
  BroadPhaseStats stats;
  double cell_loop = 0.0;
  for (auto _ : state) {
    find_candidates(sc.x0, sc.x1, sc.topo, sc.inflation, out, &stats, BroadPhaseMethod::Grid,
                    g_far);
    cell_loop += out.scratch->grid_cell_loop_seconds;
    benchmark::DoNotOptimize(out.vertex_face.data());
  }
  const std::vector<std::uint32_t>& start = out.scratch->cell_start;
  double work = 0.0;
  for (std::size_t c = 0; c + 1 < start.size(); ++c)
    work += static_cast<double>(detail::pairs_among(start[c + 1] - start[c]));
  const double boxes =
      static_cast<double>(sc.x0.rows() + sc.topo.faces.rows() + sc.topo.edges.rows());
  const double calls =
      static_cast<double>(std::max<benchmark::IterationCount>(1, state.iterations()));
  state.counters["cell_loop_ms"] = 1e3 * cell_loop / calls;
  state.counters["work_per_box"] = work / boxes;
  state.counters["ns_per_work"] = work > 0.0 ? 1e9 * cell_loop / calls / work : 0.0;
  state.counters["own_path"] = stats.method_run == BroadPhaseMethod::Grid ? 1.0 : 0.0;
}

/// A step's call as SelfCollision makes it: the kept grid patched. Alternates between the boxes
/// of the scene's step and those of the step after it, extrapolated (x1 -> 2 x1 - x0), so each
/// call moves the boxes by one step. Reports the grid's part (the patch) and the cell loop.
void BM_GridPatched(benchmark::State& state) {
  const Scene& sc = scene();
  const Positions x2 = 2.0 * sc.x1 - sc.x0;
  std::array<std::vector<detail::GridVertexBox>, 2> boxes;
  for (int k = 0; k < 2; ++k) {
    const Positions& a = k == 0 ? sc.x0 : sc.x1;
    const Positions& b = k == 0 ? sc.x1 : x2;
    boxes[static_cast<std::size_t>(k)].resize(static_cast<std::size_t>(a.rows()));
    for (Eigen::Index v = 0; v < a.rows(); ++v)
      for (Eigen::Index d = 0; d < 3; ++d) {
        detail::GridVertexBox& q = boxes[static_cast<std::size_t>(k)][static_cast<std::size_t>(v)];
        q.lo[static_cast<std::size_t>(d)] = std::min(a(v, d), b(v, d)) - sc.inflation;
        q.hi[static_cast<std::size_t>(d)] = std::max(a(v, d), b(v, d)) + sc.inflation;
      }
  }
  CandidatePairs out;
  double grid = 0.0, cell_loop = 0.0;
  std::int64_t patched = 0, calls = 0;
  for (auto _ : state) {
    if (!find_candidates_in_vertex_boxes(boxes[static_cast<std::size_t>(calls % 2)], sc.topo, out))
      state.SkipWithError("the grid degenerated");
    grid += out.scratch->grid_build_seconds;
    cell_loop += out.scratch->grid_cell_loop_seconds;
    patched += out.scratch->grid_patched_boxes > 0 ? out.scratch->grid_patched_boxes : 0;
    ++calls;
    benchmark::DoNotOptimize(out.edge_edge.data());
  }
  const double n = static_cast<double>(std::max<std::int64_t>(1, calls));
  state.counters["grid_ms"] = 1e3 * grid / n;
  state.counters["cell_loop_ms"] = 1e3 * cell_loop / n;
  state.counters["patched_boxes"] = static_cast<double>(patched) / n;
}

/// The early-exit check on the same step (it finds a pair, so this is its "true" time).
void BM_HasAnyCandidate(benchmark::State& state) {
  const Scene& sc = scene();
  CandidatePairs scratch;
  bool any = false;
  for (auto _ : state) {
    any = has_any_candidate(sc.x0, sc.x1, sc.topo, sc.inflation, scratch);
    benchmark::DoNotOptimize(any);
  }
  state.counters["any"] = any ? 1.0 : 0.0;
}

/// The collision step's filter stage (cull_batch: box cull and non-penetration filter) on every
/// pair the grid finds, four stencils of one kind at a time, as SelfCollision::detect runs it;
/// tolerance = the far distance if given (the collision step's delta), else 0. The stencils are
/// gathered in pair order beforehand, so the time is the cull's (and its position loads).
void BM_CullBatch(benchmark::State& state, CullIsa isa) {
  const Scene& sc = scene();
  CandidatePairs pairs;
  find_candidates(sc.x0, sc.x1, sc.topo, sc.inflation, pairs, nullptr, BroadPhaseMethod::Grid,
                  g_far);
  std::vector<std::array<int, 4>> vf, ee;
  for (const auto& p : pairs.vertex_face)
    vf.push_back({p[0], sc.topo.faces(p[1], 0), sc.topo.faces(p[1], 1), sc.topo.faces(p[1], 2)});
  for (const auto& p : pairs.edge_edge)
    ee.push_back({sc.topo.edges(p[0], 0), sc.topo.edges(p[0], 1), sc.topo.edges(p[1], 0),
                  sc.topo.edges(p[1], 1)});
  const double tol = g_far > 0.0 ? g_far : 0.0;
  std::vector<std::uint8_t> culled(vf.size() + ee.size() + CULL_LANES);
  for (auto _ : state) {
    std::size_t at = 0;
    for (const auto* list : {&vf, &ee}) {
      const CcdPrimitive kind = list == &vf ? CcdPrimitive::VertexFace : CcdPrimitive::EdgeEdge;
      for (std::size_t i = 0; i < list->size(); i += CULL_LANES) {
        const int count = static_cast<int>(std::min<std::size_t>(CULL_LANES, list->size() - i));
        cull_batch(kind, sc.x0.data(), sc.x1.data(), list->data() + i, count, tol,
                   culled.data() + at, isa);
        at += static_cast<std::size_t>(count);
      }
    }
    benchmark::DoNotOptimize(culled.data());
  }
  std::size_t n_culled = 0;
  for (std::size_t i = 0; i < vf.size() + ee.size(); ++i) n_culled += culled[i];
  state.counters["tests"] = static_cast<double>(vf.size() + ee.size());
  state.counters["culled"] = static_cast<double>(n_culled);
}

BENCHMARK_CAPTURE(BM_CullBatch, Auto, CullIsa::Auto)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CullBatch, Scalar, CullIsa::Scalar)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FindCandidates, PrimitiveBoxes, BroadPhaseMethod::PrimitiveBoxes)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FindCandidates, FacePairs, BroadPhaseMethod::FacePairs)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FindCandidates, Bvh, BroadPhaseMethod::Bvh)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FindCandidates, Grid, BroadPhaseMethod::Grid)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GridCellLoop, Auto, detail::GridIsa::Auto)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GridCellLoop, Portable, detail::GridIsa::Portable)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GridOnVertexBoxes, Exact, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GridOnVertexBoxes, FloatSuperset, true)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GridPatched)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HasAnyCandidate)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  // Our own flag first, then Google Benchmark's.
  for (int i = 1; i < argc; ++i) {
    const bool mesh = std::strncmp(argv[i], "--mesh=", 7) == 0;
    const bool inflation = std::strncmp(argv[i], "--inflation=", 12) == 0;
    const bool far = std::strncmp(argv[i], "--far=", 6) == 0;
    const bool end = std::strncmp(argv[i], "--end=", 6) == 0;
    if (mesh || inflation || far || end) {
      if (end) g_end = argv[i] + 6;
      if (mesh) g_mesh = argv[i] + 7;
      if (inflation) g_inflation = std::stod(argv[i] + 12);
      if (far) g_far = std::stod(argv[i] + 6);
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
    std::cerr << "bench_broad_phase: cannot load " << g_mesh << ": " << e.what() << "\n";
    return 2;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
