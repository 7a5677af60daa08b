// shellcontract regions IN -o OUT.ply [--face-list FILE] [thresholds]: shows the local spherical
// regions that `run --regions auto` would choose. Exit 0 ok, 1 bad usage (also an unwritable
// output), 2 bad input mesh.
#include <boost/program_options.hpp>

#include "commands.hpp"
#include "command_line.hpp"
#include "output_paths.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "shellcontract/core/error.hpp"
#include "shellcontract/geometry/curvature.hpp"
#include "shellcontract/geometry/region_selection.hpp"
#include "shellcontract/mesh/eigen_point_map.hpp"
#include "shellcontract/mesh/io.hpp"

namespace shellcontract::cli {


namespace {

namespace po = boost::program_options;

constexpr const char* REGIONS_USAGE = R"(usage: shellcontract regions INPUT -o OUT.ply [--face-list FILE] [thresholds]

Finds the local spherical regions (bumps, heads, fingertips) of a closed mesh by curvature, the
ones 'run --regions auto' uses, and writes the mesh as an ASCII PLY with one colour per region
(grey = none), a per-face 'region' id and per-vertex 'mean_curvature' / 'gaussian_curvature'
(input units). Prints the regions with their face count and area fraction.

A vertex seeds a region when it is convex, close to umbilic (k_min/k_max >= --umbilic-ratio) and
its mean curvature is at least --contrast times the area-weighted median |H| of the mesh; each
group of seeds grows over the faces that lie on a sphere fitted to it. Every threshold is a
ratio, so scaling the mesh does not change the result.

exit codes: 0 success, 1 bad usage or unwritable output, 2 the mesh cannot be used

options)";

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace

int command_regions(int argc, char** argv) {
  std::string input, output, face_list;
  RegionOptions options;
  po::options_description visible;
  visible.add_options()
      ("help,h", "show this help")
      ("output,o", po::value(&output), "output mesh, .ply (face colours, region ids, curvature)")
      ("face-list", po::value(&face_list), "also write the regions as a face-list file (one line per region, "
                                           "0-based face ids; the format 'run --regions FILE' reads)")
      ("smoothing-rings", po::value(&options.smoothing_rings)->default_value(options.smoothing_rings),
       "vertex rings over which H and K are averaged before the tests (0 = none)")
      ("umbilic-ratio", po::value(&options.min_principal_ratio)->default_value(options.min_principal_ratio),
       "minimum k_min/k_max of a seed (1 = sphere, 0 = cylinder)")
      ("contrast", po::value(&options.min_curvature_contrast)->default_value(options.min_curvature_contrast),
       "minimum H of a seed as a multiple of the area-weighted median |H|")
      ("fit-distance", po::value(&options.fit_distance_tolerance)->default_value(options.fit_distance_tolerance),
       "growth: corners within this fraction of the fitted radius from the fitted sphere")
      ("fit-normal-deg", po::value(&options.fit_normal_tolerance_deg)->default_value(options.fit_normal_tolerance_deg),
       "growth: face normal within this angle (degrees) of the sphere's radial direction")
      ("min-area-fraction", po::value(&options.min_area_fraction)->default_value(options.min_area_fraction),
       "drop regions smaller than this fraction of the total area")
      ("max-area-fraction", po::value(&options.max_area_fraction)->default_value(options.max_area_fraction),
       "drop regions larger than this fraction of the total area (not local)");
  try {
    const po::variables_map vm = parse_command_line(argc, argv, visible, input);
    if (vm.count("help")) {
      std::cout << REGIONS_USAGE << '\n' << visible << '\n';
      return static_cast<int>(ExitCode::Success);
    }
    if (input.empty()) throw UsageError("missing INPUT mesh");
    if (output.empty()) throw UsageError("missing -o OUT.ply");
    if (lower_extension(output) != ".ply") throw UsageError("the output must be a .ply file (got '" + output + "')");
    if (options.smoothing_rings < 0) throw UsageError("--smoothing-rings must be >= 0");
    if (!(options.fit_distance_tolerance >= 0.0) || !(options.fit_normal_tolerance_deg >= 0.0))
      throw UsageError("--fit-distance and --fit-normal-deg must be >= 0");
    for (const double t : {options.min_principal_ratio, options.min_curvature_contrast, options.fit_distance_tolerance,
                           options.fit_normal_tolerance_deg, options.min_area_fraction, options.max_area_fraction})
      if (!std::isfinite(t) || t < 0.0) throw UsageError("every threshold must be a finite number >= 0");
    OutputPlan plan;
    plan.inputs.push_back({"INPUT", input});
    plan.outputs.push_back({"-o", output});
    if (!face_list.empty()) plan.outputs.push_back({"--face-list", face_list});
    check_planned_outputs(plan);  // none is the input or the other, all writable (output_paths.hpp)
  } catch (const po::error& e) {
    return usage_error("regions", e.what());
  } catch (const UsageError& e) {
    return usage_error("regions", e.what());
  }

  try {
    InputReport input_report;
    Mesh mesh = read_input_mesh(input, &input_report);
    for (const std::string& w : input_report.warnings) std::cerr << "warning: " << w << '\n';
    const Positions x = positions_from_mesh(mesh);
    RegionReport report;
    mark_spherical_regions(mesh, x, options, &report);  // f:region and the curvature maps
    write_region_ply(output, mesh, x);
    if (!face_list.empty()) write_region_file(face_list, stored_regions(mesh));

    std::ostringstream out;
    out << std::setprecision(4);
    out << "file: " << input << '\n'
        << "faces: " << mesh.number_of_faces() << '\n'
        << "reference_mean_curvature: " << report.reference_mean_curvature << " (area-weighted median |H|)\n"
        << "seed_vertices: " << report.seed_vertices << '\n'
        << "dropped: " << report.dropped_small << " small, " << report.dropped_large << " large\n"
        << "regions: " << report.regions.size() << '\n';
    for (std::size_t r = 0; r < report.regions.size(); ++r) {
      const RegionSummary& s = report.regions[r];
      out << "  region " << r << ": faces " << s.faces << ", area fraction " << s.area_fraction
          << ", mean curvature " << s.mean_curvature << " (" << s.contrast << " x reference)\n";
    }
    out << "wrote: " << output << '\n';
    if (!face_list.empty()) out << "wrote: " << face_list << '\n';
    std::cout << out.str();
    return static_cast<int>(ExitCode::Success);
  } catch (const InputError& e) {
    std::cerr << "shellcontract regions: " << e.what() << '\n';
    return static_cast<int>(ExitCode::BadInput);
  } catch (const UsageError& e) {  // e.g. the output folder is not writable
    std::cerr << "shellcontract regions: " << e.what() << '\n';
    return static_cast<int>(ExitCode::BadUsage);
  }
}

}  // namespace shellcontract::cli
