// Writes the files of a made-up run for the glTF validator and viewer tests (CTest fixture):
// OUTDIR/NAME.glb (every EVERY-th frame and the last, two colour fields), OUTDIR/NAME.csv (one
// row per frame, the run log's columns frame,time,volume_ratio,...) and OUTDIR/NAME.json (the
// summary's frames_run, final_volume_ratio, min_volume_ratio). The motion is the export
// tests' fake contraction, not physics: the point is files shaped like a real run's.
// Usage: write_sample_run MESH OUTDIR NAME FRAMES EVERY
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>

#include "../export/export_fixtures.hpp"
#include "shellcontract/export.hpp"
#include "support/mesh_fixtures.hpp"

int main(int argc, char** argv) {
  using namespace shellcontract;
  if (argc != 6) {
    std::cerr << "usage: write_sample_run MESH OUTDIR NAME FRAMES EVERY\n";
    return 1;
  }
  try {
    std::filesystem::create_directories(argv[2]);
    const std::string out = std::string(argv[2]) + "/" + argv[3];
    const int frames = std::atoi(argv[4]), every = std::atoi(argv[5]);
    if (frames < 1 || every < 1) throw std::invalid_argument("FRAMES and EVERY must be >= 1");
    const Mesh mesh = read_input_mesh(argv[1]);
    const Positions x = positions_from_mesh(mesh);
    GltfAnimation a;
    a.faces = test::faces_of(mesh);
    const double v0 = test::signed_volume(x, a.faces);
    std::ofstream csv(out + ".csv");
    csv << "frame,time,volume_ratio,max_displacement\n" << std::setprecision(17);
    Positions previous = x;
    double ratio = 1.0, min_ratio = 1.0;
    for (int f = 0; f <= frames; ++f) {
      const Positions y = test::fake_frame(x, f, frames);
      ratio = test::signed_volume(y, a.faces) / v0;
      min_ratio = std::min(min_ratio, ratio);
      csv << f << ',' << 0.01 * f << ',' << ratio << ','
          << (y - previous).rowwise().norm().maxCoeff() << '\n';
      previous = y;
      if (f % every == 0 || f == frames) {
        a.frame_numbers.push_back(f);
        a.frames.push_back(y);
      }
    }
    const Eigen::RowVector3d c = x.colwise().mean();
    a.colour_fields.push_back({"height", x.col(2)});
    a.colour_fields.push_back({"distance_to_centre", (x.rowwise() - c).rowwise().norm()});
    a.seconds_per_frame = 0.04;
    const GltfStats s = write_gltf_animation(out + ".glb", a);
    if (!csv.flush()) throw std::runtime_error("cannot write " + out + ".csv");
    // The summary's fields that the viewer reads (the run's --summary has more).
    std::ofstream json(out + ".json");
    json << std::setprecision(17) << "{\"frames_run\": " << frames
         << ", \"final_volume_ratio\": " << ratio << ", \"min_volume_ratio\": " << min_ratio
         << "}\n";
    if (!json.flush()) throw std::runtime_error("cannot write " + out + ".json");
    std::cout << out << ".glb: " << a.frames.size() << " keyframes, " << s.bytes << " bytes\n";
  } catch (const std::exception& e) {
    std::cerr << "write_sample_run: " << e.what() << '\n';
    return 2;
  }
  return 0;
}
