// shellcontract check IN [--json]: reads and checks a mesh the way `run` does, and prints what
// it found. Exit 0 if the mesh can be used, 2 (with the reason on stderr) if not, 1 on bad usage.
#include <boost/program_options.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "command_line.hpp"
#include "json_writer.hpp"
#include "shellcontract/core/error.hpp"
#include "shellcontract/mesh/eigen_point_map.hpp"
#include "shellcontract/mesh/io.hpp"
#include "shellcontract/validation/self_intersection.hpp"

namespace shellcontract::cli {
namespace {

namespace po = boost::program_options;

constexpr const char* CHECK_USAGE = R"(usage: shellcontract check INPUT [--json]

Reads INPUT (.off, .obj, .ply, .stl) with the same checks as 'run' and reports: vertices, faces,
edges, connected components, Euler characteristic and genus, closed, manifold, enclosed volume,
bounding-box diagonal, zero-area faces and self-intersecting face pairs.
Polygons are triangulated and inside-out components flipped, as 'run' would (see the warnings).

exit codes: 0 the mesh can be used (self-intersections already in the input are reported, not
            refused), 1 bad usage, 2 the mesh cannot be used (the message says what and where)

options)";

/// Indices as a JSON array text.
std::string json_array(const std::vector<std::size_t>& ids) {
  std::string s = "[";
  for (std::size_t i = 0; i < ids.size(); ++i) s += (i ? ", " : "") + std::to_string(ids[i]);
  return s + "]";
}

}  // namespace

int command_check(int argc, char** argv) {
  std::string input;
  bool json = false;
  po::options_description visible;
  visible.add_options()
      ("help,h", "show this help")
      ("json", po::bool_switch(&json), "print the report as a JSON object on stdout");
  try {
    const po::variables_map vm = parse_command_line(argc, argv, visible, input);
    if (vm.count("help")) {
      std::cout << CHECK_USAGE << '\n' << visible << '\n';
      return static_cast<int>(ExitCode::Success);
    }
    if (input.empty()) throw UsageError("missing INPUT mesh");
  } catch (const po::error& e) {
    return usage_error("check", e.what());
  } catch (const UsageError& e) {
    return usage_error("check", e.what());
  }

  try {
    InputReport report;
    const Mesh mesh = read_input_mesh(input, &report);
    for (const std::string& w : report.warnings) std::cerr << "warning: " << w << '\n';
    const Positions x = positions_from_mesh(mesh);
    const double diagonal = (x.colwise().maxCoeff() - x.colwise().minCoeff()).norm();
    const std::vector<FacePair> pairs = self_intersecting_pairs(mesh, x);
    const long long chi = static_cast<long long>(mesh.number_of_vertices()) -
                          static_cast<long long>(mesh.number_of_edges()) +
                          static_cast<long long>(mesh.number_of_faces());
    // read_input_mesh refuses open, non-manifold and non-orientable input, so every component
    // is a closed orientable surface: chi = sum (2 - 2 g_i).
    const long long genus = (2 * static_cast<long long>(report.components) - chi) / 2;

    if (json) {
      std::string pairs_json = "[";
      for (std::size_t i = 0; i < pairs.size(); ++i)
        pairs_json += (i ? ", " : "") + json_array({pairs[i].first.idx(), pairs[i].second.idx()});
      pairs_json += "]";
      JsonObject o;
      o.add("file", input).add("usable", true).add("vertices", report.vertices).add("faces", report.faces)
          .add("edges", static_cast<std::size_t>(mesh.number_of_edges())).add("components", report.components)
          .add_raw("euler_characteristic", std::to_string(chi)).add_raw("genus", std::to_string(genus))
          .add("closed", true).add("manifold", true).add("volume", report.volume)
          .add("bounding_box_diagonal", diagonal).add("reoriented", report.reoriented)
          .add("triangulated_faces", report.triangulated_faces)
          .add_raw("zero_area_faces", json_array(report.zero_area_faces))
          .add("self_intersecting_pairs", pairs.size()).add_raw("self_intersections", pairs_json)
          .add("warnings", report.warnings);
      std::cout << o.str() << '\n';
    } else {
      std::ostringstream out;
      out << std::setprecision(std::numeric_limits<double>::max_digits10);
      out << "file: " << input << '\n'
          << "vertices: " << report.vertices << '\n'
          << "faces: " << report.faces << '\n'
          << "edges: " << mesh.number_of_edges() << '\n'
          << "components: " << report.components << '\n'
          << "euler_characteristic: " << chi << '\n'
          << "genus: " << genus << '\n'
          << "closed: yes\n"
          << "manifold: yes\n"
          << "volume: " << report.volume << '\n'
          << "bounding_box_diagonal: " << diagonal << '\n'
          << "reoriented: " << (report.reoriented ? "yes" : "no") << '\n'
          << "triangulated_faces: " << report.triangulated_faces << '\n'
          << "zero_area_faces: " << report.zero_area_faces.size();
      if (!report.zero_area_faces.empty()) {
        out << " (";
        for (std::size_t i = 0; i < report.zero_area_faces.size() && i < 20; ++i)
          out << (i ? " " : "") << report.zero_area_faces[i];
        out << (report.zero_area_faces.size() > 20 ? " ...)" : ")");
      }
      out << "\nself_intersecting_pairs: " << pairs.size();
      if (!pairs.empty()) {
        out << " (";
        for (std::size_t i = 0; i < pairs.size() && i < 20; ++i)
          out << (i ? " " : "") << pairs[i].first.idx() << '-' << pairs[i].second.idx();
        out << (pairs.size() > 20 ? " ...)" : ")");
      }
      out << "\nusable: yes\n";
      std::cout << out.str();
    }
    return static_cast<int>(ExitCode::Success);
  } catch (const InputError& e) {
    std::cerr << "shellcontract check: " << e.what() << '\n';
    if (json) {
      JsonObject o;
      o.add("file", input).add("usable", false).add("error", std::string(e.what()));
      std::cout << o.str() << '\n';
    }
    return static_cast<int>(ExitCode::BadInput);
  }
}

}  // namespace shellcontract::cli
