// Contracts a mesh through run_contraction, linked from the installed package.
//   app INPUT [FRAMES]; exit 0 when the run completed and the volume went down.
#include <cstdio>
#include <string>

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
  const shellcontract::RunResult r = shellcontract::run_contraction(mesh, options, &counter);
  std::printf("frames %d (observed %d), V/V0 %.6f, status %d\n", r.frames_run, counter.frames,
              r.final_volume_ratio, static_cast<int>(r.status));
  const bool ok = r.status == shellcontract::RunStatus::Completed && counter.frames == r.frames_run &&
                  r.frames_run > 0 && r.final_volume_ratio < 1.0;
  return ok ? 0 : 1;
}
