// Replays the collision step's broad phase on the steps of a real run, dumped by
// lab/kernels/dump_steps.patch (x0, x1, the inflation and delta of each step), in an arena of
// the run's 2 threads, each step after the other on one CandidatePairs (the kept grid is
// patched as in the run).
//
//   default      find_candidates (Grid): median time per call and its parts, the pair counts
//   --alternate  per call, alternating: find_candidates (sorted by its counting sort), the grid
//                (grid_pairs) followed by main's parallel comparison sort of the packed pairs
//                (as main's find_candidates sorted them before this branch), the grid rebuilt
//                each call (no patch), and the grid unsorted
//   --face-pairs every 10th step: the overlapping face box pairs (FacePairs' box_overlaps),
//                the primitive box overlaps (PrimitiveBoxes'), the pairs emitted
//   --compare    every step: find_candidates against PrimitiveBoxes (CGAL, another method) and
//                against grid_pairs' pairs sorted here with their close flags; exit 1 if any
//                differs
// Usage: bench_broad_phase_steps MESH DUMP_DIR [--reps=N] [--threads=T] [options above]
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/broad_phase/grid.hpp"
#include "collision/broad_phase/scratch.hpp"
#include "shellcontract/mesh_io.hpp"
#include "sim/rest_state.hpp"

namespace {

using namespace shellcontract;

struct Step {
  Positions x0, x1;
  double inflation = 0.0, delta = 0.0;
};

bool load(const std::string& path, Step& s) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  long n = 0;
  bool ok = std::fread(&n, sizeof n, 1, f) == 1 && std::fread(&s.inflation, 8, 1, f) == 1 &&
            std::fread(&s.delta, 8, 1, f) == 1 && n > 0;
  if (ok) {
    const std::size_t count = 3 * static_cast<std::size_t>(n);
    s.x0.resize(n, 3);
    s.x1.resize(n, 3);
    ok = std::fread(s.x0.data(), 8, count, f) == count && std::fread(s.x1.data(), 8, count, f) == count;
  }
  std::fclose(f);
  return ok;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool same(const CandidatePairs& a, const CandidatePairs& b, bool flags) {
  auto eq = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::equal(x.begin(), x.end(), y.begin());
  };
  return eq(a.vertex_face, b.vertex_face) && eq(a.edge_edge, b.edge_edge) &&
         (!flags || (eq(a.vertex_face_close, b.vertex_face_close) &&
                     eq(a.edge_edge_close, b.edge_edge_close)));
}

/// grid_pairs' pairs (in its chunk order) on a step, into out.
void grid_unsorted(const Step& s, const CollisionTopology& topo, CandidatePairs& out) {
  detail::build_grid_vertex_boxes(s.x0, s.x1, s.inflation, out.scratch->grid_vertex_boxes);
  detail::grid_pairs(topo, far_gap_threshold(s.x0, s.x1, s.inflation, s.delta), out);
}

/// Sorts each list with its flags (the reference order: by pair).
void sort_with_flags(CandidatePairs& p) {
  for (auto [pairs, close] : {std::pair{&p.vertex_face, &p.vertex_face_close},
                              std::pair{&p.edge_edge, &p.edge_edge_close}}) {
    std::vector<std::pair<std::array<int, 2>, std::uint8_t>> z;
    for (std::size_t i = 0; i < pairs->size(); ++i) z.push_back({(*pairs)[i], (*close)[i]});
    std::sort(z.begin(), z.end());
    for (std::size_t i = 0; i < z.size(); ++i) {
      (*pairs)[i] = z[i].first;
      (*close)[i] = z[i].second;
    }
  }
}

/// main's sort before this branch: pack pair and flag into keys, sort them in parallel, unpack.
void parallel_sort_pairs(NoZeroVector<std::array<int, 2>>& pairs,
                         NoZeroVector<std::uint8_t>& close, std::vector<std::uint64_t>& keys) {
  keys.resize(pairs.size());
  for (std::size_t i = 0; i < keys.size(); ++i)
    keys[i] = std::uint64_t(std::uint32_t(pairs[i][0])) << 33 |
              std::uint64_t(std::uint32_t(pairs[i][1])) << 1 | (close[i] ? 1u : 0u);
  tbb::parallel_sort(keys.begin(), keys.end());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    pairs[i] = {static_cast<int>(keys[i] >> 33), static_cast<int>((keys[i] >> 1) & 0xffffffffu)};
    close[i] = static_cast<std::uint8_t>(keys[i] & 1u);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: bench_broad_phase_steps MESH DUMP_DIR [--reps=N] [--threads=T] "
                 "[--alternate] [--face-pairs] [--compare]\n";
    return 2;
  }
  int reps = 5, threads = 2;
  bool compare = false, alternate = false, face_pairs = false;
  for (int i = 3; i < argc; ++i) {
    if (std::strncmp(argv[i], "--reps=", 7) == 0) reps = std::stoi(argv[i] + 7);
    if (std::strncmp(argv[i], "--threads=", 10) == 0) threads = std::stoi(argv[i] + 10);
    compare |= std::strcmp(argv[i], "--compare") == 0;
    alternate |= std::strcmp(argv[i], "--alternate") == 0;
    face_pairs |= std::strcmp(argv[i], "--face-pairs") == 0;
  }
  const Mesh mesh = read_input_mesh(argv[1]);
  const CollisionTopology topo =
      make_collision_topology(faces_array(mesh), static_cast<int>(mesh.number_of_vertices()));
  std::vector<Step> steps;
  for (int k = 0;; ++k) {
    Step s;
    if (!load(std::string(argv[2]) + "/step" + std::to_string(k) + ".bin", s)) break;
    if (s.x0.rows() != topo.num_vertices) {
      std::cerr << "step " << k << ": vertex count differs from the mesh\n";
      return 2;
    }
    steps.push_back(std::move(s));
  }
  std::printf("%zu steps, %d vertices, %ld faces, %ld edges, %d threads\n", steps.size(),
              topo.num_vertices, static_cast<long>(topo.faces.rows()),
              static_cast<long>(topo.edges.rows()), threads);
  if (steps.empty()) return 2;
  tbb::task_arena arena(threads);

  {
    CandidatePairs out;
    std::vector<double> total, build, loop, output;
    double pairs = 0.0;
    for (int r = 0; r < reps; ++r)
      for (const Step& s : steps) {
        BroadPhaseStats bs;
        arena.execute([&] {
          find_candidates(s.x0, s.x1, topo, s.inflation, out, &bs, BroadPhaseMethod::Grid,
                          s.delta);
        });
        const GridPartSeconds g = grid_part_seconds(out);
        total.push_back(1e3 * bs.seconds);
        build.push_back(1e3 * g.build);
        loop.push_back(1e3 * g.cell_loop);
        output.push_back(1e3 * g.output);
        pairs += static_cast<double>(bs.vertex_face + bs.edge_edge);
      }
    std::printf("find_candidates %.3f ms per call (grid %.3f, cell loop %.3f, output %.3f; "
                "medians), %.0f pairs per call\n",
                median(total), median(build), median(loop), median(output),
                pairs / static_cast<double>(total.size()));
  }

  if (alternate) {
    const char* names[] = {"find_candidates", "grid + parallel sort", "grid rebuilt + sort",
                           "grid unsorted"};
    CandidatePairs outs[4];
    outs[2].scratch->grid_patch = false;
    std::vector<double> times[4];
    std::vector<std::uint64_t> keys;
    for (int r = 0; r < reps; ++r)
      for (const Step& s : steps)
        for (int v = 0; v < 4; ++v) {
          CandidatePairs& out = outs[v];
          const auto t0 = std::chrono::steady_clock::now();
          arena.execute([&] {
            if (v == 0) {
              find_candidates(s.x0, s.x1, topo, s.inflation, out, nullptr, BroadPhaseMethod::Grid,
                              s.delta);
              return;
            }
            grid_unsorted(s, topo, out);
            if (v == 3) return;
            parallel_sort_pairs(out.vertex_face, out.vertex_face_close, keys);
            parallel_sort_pairs(out.edge_edge, out.edge_edge_close, keys);
          });
          times[v].push_back(ms_since(t0));
        }
    for (int v = 0; v < 4; ++v)
      std::printf("  %-22s %.3f ms per call (median)\n", names[v], median(times[v]));
  }

  if (face_pairs)
    for (std::size_t k = 0; k < steps.size(); k += 10) {
      const Step& s = steps[k];
      CandidatePairs o;
      BroadPhaseStats faces, prims;
      find_candidates(s.x0, s.x1, topo, s.inflation, o, &faces, BroadPhaseMethod::FacePairs);
      find_candidates(s.x0, s.x1, topo, s.inflation, o, &prims, BroadPhaseMethod::PrimitiveBoxes);
      std::printf("step %zu: face box pairs %lld, primitive box overlaps %lld, pairs %lld\n", k,
                  static_cast<long long>(faces.box_overlaps),
                  static_cast<long long>(prims.box_overlaps),
                  static_cast<long long>(prims.vertex_face + prims.edge_edge));
    }

  if (!compare) return 0;
  int failures = 0;
  CandidatePairs got;  // one object across the steps, as in the run
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const Step& s = steps[k];
    arena.execute([&] {
      find_candidates(s.x0, s.x1, topo, s.inflation, got, nullptr, BroadPhaseMethod::Grid,
                      s.delta);
    });
    CandidatePairs cgal, grid;
    find_candidates(s.x0, s.x1, topo, s.inflation, cgal, nullptr,
                    BroadPhaseMethod::PrimitiveBoxes, s.delta);
    arena.execute([&] { grid_unsorted(s, topo, grid); });
    sort_with_flags(grid);
    if (!same(got, cgal, false)) {
      std::printf("step %zu: pairs differ from PrimitiveBoxes\n", k);
      ++failures;
    }
    if (!same(got, grid, true)) {
      std::printf("step %zu: pairs or close flags differ from the sorted grid_pairs\n", k);
      ++failures;
    }
  }
  std::printf("compare: %d differences over %zu steps\n", failures, steps.size());
  return failures == 0 ? 0 : 1;
}
