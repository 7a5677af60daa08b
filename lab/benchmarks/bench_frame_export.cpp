// The cost of writing a run's frames (issue 26 bounds it at 10 % of a bear run with every 5th
// frame exported): 11 OFF frames of bear through FrameSequenceWriter, the caller's time (copy,
// enqueue, waiting for queue room) and the writer thread's, per frame. Moved here from the
// tests (issue 59: timings are measurements, not tests).
// Usage: bench_frame_export [--mesh=PATH] [google-benchmark flags]
// Default mesh: data/meshes/bear.off (scripts/fetch_paper_meshes.sh).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>

#include "export/frame_sequence_writer.hpp"
#include "mesh/eigen_point_map.hpp"
#include "shellcontract/mesh_io.hpp"

namespace {

using namespace shellcontract;

std::string g_mesh = std::string(SHELLCONTRACT_PAPER_MESH_DIR) + "/bear.off";

/// A made-up contraction of x at frame / frames: only the file writing is measured.
Positions moved(const Positions& x, int frame, int frames) {
  const double t = static_cast<double>(frame) / frames;
  const Eigen::RowVector3d c = x.colwise().mean();
  Positions y = x;
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    y.row(i) = c + (1.0 - 0.45 * t + 0.1 * t * std::sin(7.0 * x(i, 2))) * (x.row(i) - c);
  return y;
}

void BM_OffFramesEveryFifthOfFifty(benchmark::State& state) {
  const Mesh mesh = read_input_mesh(g_mesh);
  const Positions x = positions_from_mesh(mesh);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "shellcontract_bench_frames";
  double caller = 0.0, writer = 0.0;
  int frames = 0;
  std::uint64_t bytes = 0;
  for (auto _ : state) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    FrameSequenceWriter w(dir.string(), "bear", "off", mesh, 50);
    for (int f = 0; f <= 50; f += 5) w.write(f, moved(x, f, 50));
    w.finish();
    const ExportStats s = w.stats();
    caller += s.caller_seconds;
    writer += s.writer_seconds;
    frames += s.frames_written;
    bytes += s.bytes;
  }
  std::filesystem::remove_all(dir);
  if (frames > 0) {
    state.counters["caller_ms_per_frame"] = 1e3 * caller / frames;
    state.counters["writer_ms_per_frame"] = 1e3 * writer / frames;
    state.counters["bytes_per_frame"] = static_cast<double>(bytes) / frames;
  }
}
BENCHMARK(BM_OffFramesEveryFifthOfFifty)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {  // our own flag first, then Google Benchmark's
    if (std::strncmp(argv[i], "--mesh=", 7) == 0) {
      g_mesh = argv[i] + 7;
      for (int j = i; j + 1 < argc; ++j) argv[j] = argv[j + 1];
      --argc;
      --i;
    }
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
