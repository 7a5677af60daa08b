// Contracts a mesh through run_contraction, linked from the installed package.
//   app INPUT [FRAMES]; exit 0 when the run completed and the volume went down.
#include <cstdio>
#include <string>
#include <utility>

#include "shellcontract/mesh.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"

class CountFrames final : public shellcontract::RunObserver {
 public:
  void frame(const shellcontract::FrameView&, const shellcontract::FrameMetrics&) override { ++frames; }
  int frames = 0;
};

int main(int argc, char** argv) {
  if (argc < 2) return 1;
  const shellcontract::Mesh mesh = shellcontract::read_input_mesh(argv[1]);
  shellcontract::RunOptions options;
  shellcontract::set_run_option(options, "frames", argc > 2 ? argv[2] : "10");
  CountFrames counter;
  shellcontract::RunResult r = shellcontract::run_contraction(mesh, options, &counter);
  std::printf("frames %d (observed %d), V/V0 %.6f, status %d\n", r.frames_run, counter.frames,
              r.final_volume_ratio, static_cast<int>(r.status));
  // The library allocated the result's matrices; this program resizes and frees them, with its
  // own compiler flags (app_avx2: CMakeLists.txt).
  const shellcontract::Positions input = shellcontract::positions_from_mesh(mesh);
  const Eigen::Index rows = r.positions.rows();
  shellcontract::Positions x = std::move(r.positions);
  x.conservativeResize(rows + 1, Eigen::NoChange);
  x.row(rows).setZero();
  const bool ok = r.status == shellcontract::RunStatus::Completed &&
                  counter.frames == r.frames_run && r.frames_run > 0 &&
                  r.final_volume_ratio < 1.0 && rows == input.rows();
  return ok ? 0 : 1;
}
