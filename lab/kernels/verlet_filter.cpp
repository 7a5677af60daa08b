// What the per-step filter of a Verlet list would cost on bear's default run (issue 58, point 4;
// collision_coherence.md, section 13). Standalone: reads the frames of
//   shellcontract run data/meshes/bear.off -o D/out.off -q --export-dir D/fr --export-every 1
// builds, at step T0, the list of vertex-face and edge-edge pairs (not sharing a vertex) whose
// swept boxes, grown by a margin G on each side, overlap (brute force, not timed), and then
// times the filter a list step would run: each listed pair's two primitive boxes gathered from
// the current swept vertex boxes (min and max over their corners) and tested for overlap, the
// survivors written out in list order. Two ways: the step's face and edge boxes computed first
// (their pass is timed too) and two boxes gathered per pair, or each pair's boxes gathered from
// its corners. Timed over the steps T0 .. T0 + 4, REPS times each, on 1 and on 2 threads (two
// halves of the list; std::thread started each time, as a TBB arena would not be); prints the
// medians.
//
// Build: g++ -O3 -DNDEBUG -std=c++17 -pthread lab/kernels/verlet_filter.cpp -o /tmp/verlet_filter
// Usage: /tmp/verlet_filter D/fr T0 G_IN_MEAN_EDGES [REPS=20]
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

struct Box {
  double lo[3], hi[3];
};

static void read_off(const std::string& path, std::vector<std::array<double, 3>>& v, std::vector<std::array<int, 3>>* f) {
  std::ifstream in(path);
  std::string tag;
  std::size_t nv = 0, nf = 0, ne = 0;
  in >> tag >> nv >> nf >> ne;
  v.resize(nv);
  for (auto& p : v) in >> p[0] >> p[1] >> p[2];
  if (f) {
    f->resize(nf);
    for (auto& t : *f) {
      int k;
      in >> k >> t[0] >> t[1] >> t[2];
    }
  }
  if (!in) {
    std::fprintf(stderr, "cannot read %s\n", path.c_str());
    std::exit(2);
  }
}

static bool overlap(const Box& a, const Box& b) {
  for (int d = 0; d < 3; ++d)
    if (a.hi[d] < b.lo[d] || b.hi[d] < a.lo[d]) return false;
  return true;
}

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: verlet_filter D/fr T0 G_IN_MEAN_EDGES [REPS]\n");
    return 2;
  }
  const std::string dir = argv[1];
  const int t0 = std::atoi(argv[2]);
  const double g_edges = std::atof(argv[3]);
  const int reps = argc > 4 ? std::atoi(argv[4]) : 20;
  auto frame = [&](int i) {
    char name[64];
    std::snprintf(name, sizeof name, "/out_%03d.off", i);
    return dir + name;
  };
  std::vector<std::array<int, 3>> faces;
  std::vector<std::vector<std::array<double, 3>>> x(7);
  read_off(frame(t0), x[0], &faces);
  for (int k = 1; k < 7; ++k) read_off(frame(t0 + k), x[k], nullptr);
  const std::size_t nv = x[0].size(), nf = faces.size();
  // Normalized units as the run's (centre and diagonal of frame t0: only scale matters here).
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (const auto& p : x[0])
    for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], p[d]), hi[d] = std::max(hi[d], p[d]);
  const double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
  for (auto& fr : x)
    for (auto& p : fr)
      for (int d = 0; d < 3; ++d) p[d] /= diag;
  std::set<std::pair<int, int>> edge_set;
  for (const auto& t : faces)
    for (int k = 0; k < 3; ++k) edge_set.insert({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  const std::vector<std::pair<int, int>> edges(edge_set.begin(), edge_set.end());
  double mean_edge = 0.0;
  for (const auto& e : edges) {
    double s = 0.0;
    for (int d = 0; d < 3; ++d) s += (x[0][e.first][d] - x[0][e.second][d]) * (x[0][e.first][d] - x[0][e.second][d]);
    mean_edge += std::sqrt(s);
  }
  mean_edge /= static_cast<double>(edges.size());
  // The run's inflation: (delta + 4 delta) / 2 with delta = 1e-4 (normalized units).
  const double inflation = 2.5e-4, grow = g_edges * mean_edge;
  auto vertex_boxes = [&](int step, double extra, std::vector<Box>& out) {
    out.resize(nv);
    for (std::size_t i = 0; i < nv; ++i)
      for (int d = 0; d < 3; ++d) {
        out[i].lo[d] = std::min(x[step][i][d], x[step + 1][i][d]) - inflation - extra;
        out[i].hi[d] = std::max(x[step][i][d], x[step + 1][i][d]) + inflation + extra;
      }
  };
  auto face_box = [&](const std::vector<Box>& vb, std::size_t f) {
    Box b = vb[faces[f][0]];
    for (int k = 1; k < 3; ++k)
      for (int d = 0; d < 3; ++d) b.lo[d] = std::min(b.lo[d], vb[faces[f][k]].lo[d]), b.hi[d] = std::max(b.hi[d], vb[faces[f][k]].hi[d]);
    return b;
  };
  auto edge_box = [&](const std::vector<Box>& vb, std::size_t e) {
    Box b = vb[edges[e].first];
    for (int d = 0; d < 3; ++d) b.lo[d] = std::min(b.lo[d], vb[edges[e].second].lo[d]), b.hi[d] = std::max(b.hi[d], vb[edges[e].second].hi[d]);
    return b;
  };
  // The list at t0 (brute force over the grown boxes).
  std::vector<Box> vb;
  vertex_boxes(0, grow, vb);
  std::vector<Box> fb(nf), eb(edges.size());
  for (std::size_t f = 0; f < nf; ++f) fb[f] = face_box(vb, f);
  for (std::size_t e = 0; e < edges.size(); ++e) eb[e] = edge_box(vb, e);
  struct Pair {
    int kind;  // 0: vertex a, face b; 1: edges a, b
    int a, b;
  };
  std::vector<Pair> list;
  for (std::size_t v = 0; v < nv; ++v)
    for (std::size_t f = 0; f < nf; ++f) {
      const auto& t = faces[f];
      if (t[0] == static_cast<int>(v) || t[1] == static_cast<int>(v) || t[2] == static_cast<int>(v)) continue;
      if (overlap(vb[v], fb[f])) list.push_back({0, static_cast<int>(v), static_cast<int>(f)});
    }
  for (std::size_t i = 0; i < edges.size(); ++i)
    for (std::size_t j = i + 1; j < edges.size(); ++j) {
      const auto& p = edges[i];
      const auto& q = edges[j];
      if (p.first == q.first || p.first == q.second || p.second == q.first || p.second == q.second) continue;
      if (overlap(eb[i], eb[j])) list.push_back({1, static_cast<int>(i), static_cast<int>(j)});
    }
  std::printf("bear steps %d..%d, margin %.3g mean edges (%.3g normalized): %zu listed pairs\n", t0, t0 + 4, g_edges, grow, list.size());
  // The filter at each later step, on 1 and 2 threads.
  std::vector<int> keep(list.size());
  auto filter = [&](const std::vector<Box>& cur, std::size_t b, std::size_t e) {
    std::size_t n = b;
    for (std::size_t i = b; i < e; ++i) {
      const Pair& p = list[i];
      bool hit;
      if (p.kind == 0) {
        hit = overlap(cur[p.a], face_box(cur, p.b));
      } else {
        hit = overlap(edge_box(cur, p.a), edge_box(cur, p.b));
      }
      keep[n] = static_cast<int>(i);
      n += hit;
    }
    return n - b;
  };
  // Variant "boxes": the step's face and edge boxes computed first (one pass over the
  // primitives, part of the time), then each pair gathers two boxes and tests them without a
  // branch.
  std::vector<Box> cur_f(nf), cur_e(edges.size());
  auto overlap_nb = [](const Box& a, const Box& b) {
    return (a.hi[0] >= b.lo[0]) & (b.hi[0] >= a.lo[0]) & (a.hi[1] >= b.lo[1]) & (b.hi[1] >= a.lo[1]) &
           (a.hi[2] >= b.lo[2]) & (b.hi[2] >= a.lo[2]);
  };
  auto filter_boxes = [&](const std::vector<Box>& cur, std::size_t b, std::size_t e) {
    std::size_t n = b;
    for (std::size_t i = b; i < e; ++i) {
      const Pair& p = list[i];
      const Box& first = p.kind == 0 ? cur[p.a] : cur_e[p.a];
      const Box& second = p.kind == 0 ? cur_f[p.b] : cur_e[p.b];
      keep[n] = static_cast<int>(i);
      n += overlap_nb(first, second);
    }
    return n - b;
  };
  auto primitive_boxes = [&](const std::vector<Box>& cur, std::size_t part, std::size_t parts) {
    for (std::size_t f = nf * part / parts; f < nf * (part + 1) / parts; ++f) cur_f[f] = face_box(cur, f);
    for (std::size_t e = edges.size() * part / parts; e < edges.size() * (part + 1) / parts; ++e) cur_e[e] = edge_box(cur, e);
  };
  // Times run(cur, threads) -> survivors over the 5 steps, REPS calls each; prints the median.
  auto measure = [&](const char* label, int threads, auto run) {
    std::vector<double> ms;
    std::size_t survivors = 0;
    for (int step = 0; step < 5; ++step) {
      std::vector<Box> cur;
      vertex_boxes(step, 0.0, cur);
      for (int r = 0; r < reps; ++r) {
        const auto start = std::chrono::steady_clock::now();
        survivors = run(cur, threads);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
      }
    }
    std::sort(ms.begin(), ms.end());
    std::printf("%s, %d thread%s: median %.3f ms per step (%.2f ns per listed pair), %zu survivors at the last step\n",
                label, threads, threads == 1 ? "" : "s", ms[ms.size() / 2],
                ms[ms.size() / 2] * 1e6 / static_cast<double>(list.size()), survivors);
  };
  // The list in one part, or in two halves on two threads (std::thread started per call).
  auto halves = [&](int threads, auto part) {
    if (threads == 1) return part(std::size_t{0}, list.size());
    const std::size_t half = list.size() / 2;
    std::size_t second = 0;
    std::thread other([&] { second = part(half, list.size()); });
    const std::size_t first = part(std::size_t{0}, half);
    other.join();
    return first + second;
  };
  for (int threads : {1, 2})
    measure("boxes first", threads, [&](const std::vector<Box>& cur, int t) {
      if (t == 1) {
        primitive_boxes(cur, 0, 1);
      } else {
        std::thread other([&] { primitive_boxes(cur, 1, 2); });
        primitive_boxes(cur, 0, 2);
        other.join();
      }
      return halves(t, [&](std::size_t b, std::size_t e) { return filter_boxes(cur, b, e); });
    });
  for (int threads : {1, 2})
    measure("gathered per pair", threads, [&](const std::vector<Box>& cur, int t) {
      return halves(t, [&](std::size_t b, std::size_t e) { return filter(cur, b, e); });
    });
  return 0;
}
