// shellcontract reconstruct: closed surface from an oriented point set (the paper's kitten).
#include <boost/program_options.hpp>
#include <iostream>
#include <string>

#include "command_line.hpp"
#include "commands.hpp"
#include "mesh/eigen_point_map.hpp"
#include "mesh/reconstruction.hpp"
#include "output_paths.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace po = boost::program_options;

namespace shellcontract::cli {

int command_reconstruct(int argc, char** argv) {
  std::string input, output;
  ReconstructionOptions options;
  po::options_description visible(
      "usage: shellcontract reconstruct POINTS.xyz -o OUT.off\n\n"
      "Closed surface from an oriented point set (x y z nx ny nz per line) with CGAL's Poisson\n"
      "surface reconstruction, e.g. the paper's kitten from data/points_3/kitten.xyz. A position "
      "given\n"
      "on several lines counts once. The faces are written in a canonical order (each from its "
      "smallest\n"
      "vertex index, sorted), so the same points give the same file whatever the allocator does.\n"
      "--radius and --distance are multiples of the average distance from a point to its 6 "
      "nearest\n"
      "neighbours; out of their ranges (and an --angle above 30) CGAL's surface mesher may not "
      "end.\n\n"
      "The surface is checked against the points before anything is written: one that misses "
      "points\n"
      "(separate objects: reconstruct them one by one) or that a tenth of the normals point into\n"
      "(normals not consistently oriented) is refused.\n\n"
      "exit codes: 0 success, 1 bad usage (also a criterion out of its range), 2 an unusable "
      "point\n"
      "            set (the message names the file and line): fewer than 10 distinct positions, a\n"
      "            stray point far from the others, coordinates beyond 1e30, one position with "
      "normals\n"
      "            90 degrees apart, all in one plane...; no closed surface came out (also: "
      "CGAL's\n"
      "            surface mesher stopped on one of its own checks); or the surface misses points "
      "or\n"
      "            disagrees with their normals; 3 memory ran out or the system refused a "
      "resource\n"
      "            (a thread, an open file); 130 interrupted (Ctrl-C, SIGTERM)\n\n"
      "options");
  visible.add_options()("help,h", "show this help")("output,o", po::value(&output), "output mesh")(
      "angle", po::value(&options.angle)->default_value(options.angle),
      "min triangle angle, degrees in [0, 30] (CGAL's surface mesher ends for sure only up to 30; "
      "0: no angle bound)")(
      "radius", po::value(&options.radius)->default_value(options.radius),
      "max triangle size, x average point spacing, in [0.5, 1e6]")(
      "distance", po::value(&options.distance)->default_value(options.distance),
      "approximation error, x average point spacing, in [0.1, 1e6]");
  try {
    const po::variables_map vm = parse_command_line(argc, argv, visible, input);
    if (vm.count("help")) {
      std::cout << visible << '\n';
      return 0;
    }
    if (input.empty()) throw UsageError("missing POINTS file");
    if (output.empty()) throw UsageError("missing -o OUT");
    // Before any file is read or written: out of these ranges the mesher may never end.
    check_reconstruction_options(options, "--");
    // -o's format from its name, as run, repair and regions check theirs: before the points are
    // read and reconstructed (minutes on a large cloud), not after.
    check_result_format(input, output, false, false);
    OutputPlan plan;
    plan.inputs.push_back({"INPUT", input});
    plan.outputs.push_back({"-o", output});
    check_planned_outputs(plan);  // never the points file, a writable folder (output_paths.hpp)
  } catch (const po::error& e) {
    return usage_error("reconstruct", e.what());
  } catch (const UsageError& e) {
    return usage_error("reconstruct", e.what());
  }
  try {
    const Mesh mesh = reconstruct_from_oriented_points(input, options);
    write_mesh_atomic(output, mesh, positions_from_mesh(mesh));
    std::cerr << "wrote " << output << ": " << mesh.number_of_vertices() << " vertices, "
              << mesh.number_of_faces() << " faces\n";
    return 0;
  } catch (const InputError& e) {
    std::cerr << "shellcontract reconstruct: " << e.what() << '\n';
    return static_cast<int>(ExitCode::BadInput);
  } catch (const UsageError& e) {
    return usage_error("reconstruct", e.what());
  }
}

}  // namespace shellcontract::cli
