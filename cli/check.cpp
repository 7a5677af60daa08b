// shellcontract check IN [--json] [--against INPUT] [--fail-on-self-intersections]: reads and
// checks a mesh the way `run` does, and prints what it found. Exit 0 if the mesh can be used, 2
// (with the reason on stderr) if not, 1 on bad usage, 4 when it fails --against or
// --fail-on-self-intersections (a result can be refused, not only an input).
#include <algorithm>
#include <array>
#include <boost/program_options.hpp>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "check_against.hpp"
#include "command_line.hpp"
#include "commands.hpp"
#include "core/classic_locale.hpp"
#include "json_writer.hpp"
#include "mesh/eigen_point_map.hpp"
#include "mesh/formats.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/validation.hpp"

namespace shellcontract::cli {
namespace {

namespace po = boost::program_options;

/// The help's text before the options; the formats read are the table's (mesh/formats.hpp).
std::string check_usage() {
  return R"(usage: shellcontract check MESH [--json] [--against INPUT] [--fail-on-self-intersections]

Reads MESH ()" +
         extension_list(any_format, ".", ", ") +
         R"() with the same checks as 'run' and reports:
vertices, faces, edges, connected components, Euler characteristic and genus, closed, manifold,
enclosed volume, bounding-box diagonal, zero-area faces and self-intersecting face pairs.
Polygons are triangulated and inside-out components flipped, as 'run' would (see the warnings;
with --against, each warning names its file, MESH or INPUT).
With --against, MESH is a result of 'run' on INPUT (same vertices and faces, moved): each polygon
of MESH that is INPUT's polygon of the same index is split into the triangles INPUT's was split
into, the ones 'run' simulated (not along the diagonal MESH's folded shape would choose; a warning
says when they make no usable mesh and MESH's own split is checked), and the face pairs that
intersect in MESH but not in INPUT are counted (compared polygon by polygon). A pair that
intersects or touches in INPUT is not new however far it crosses in MESH: parts touching in INPUT
may pass through each other unseen ('run' warns of them). Another tool may split a folded quad of
MESH along its other diagonal.

exit codes: 0 the mesh can be used (self-intersections already in the input are reported, not
            refused), 1 bad usage (also: MESH and INPUT do not have the same vertices and faces),
            2 the mesh (or INPUT) cannot be used (the message says what and where), 4 MESH has
            self-intersecting pairs that INPUT lacks (--against), or has any
            (--fail-on-self-intersections), 3 memory ran out or the system refused a resource
            (a thread, an open file), 130 interrupted (Ctrl-C, SIGTERM)

options)";
}

/// Pairs as a JSON array text.
std::string json_pairs(const std::vector<FacePair>& pairs) {
  std::string s = "[";
  for (std::size_t i = 0; i < pairs.size(); ++i)
    s += (i ? ", [" : "[") + std::to_string(pairs[i].first.idx()) + ", " +
         std::to_string(pairs[i].second.idx()) + "]";
  return s + "]";
}

/// " (a-b c-d ...)": the first 20 pairs for the text report, nothing when there are none.
std::string text_pairs(const std::vector<FacePair>& pairs, std::size_t count) {
  if (count == 0) return "";
  std::string s = " (";
  for (std::size_t i = 0; i < pairs.size() && i < 20; ++i)
    s += (i ? " " : "") + std::to_string(pairs[i].first.idx()) + '-' +
         std::to_string(pairs[i].second.idx());
  return s + (count > 20 ? " ...)" : ")");
}

/// Indices as a JSON array text.
std::string json_array(const std::vector<std::size_t>& ids) {
  std::string s = "[";
  for (std::size_t i = 0; i < ids.size(); ++i) s += (i ? ", " : "") + std::to_string(ids[i]);
  return s + "]";
}

}  // namespace

int command_check(int argc, char** argv) {
  std::string input, against;
  bool json = false, fail_on_intersections = false;
  po::options_description visible;
  visible.add_options()("help,h", "show this help")("json", po::bool_switch(&json),
                                                    "print the report as a JSON object on stdout")(
      "against", po::value(&against)->value_name("INPUT"),
      "MESH is a result of 'run' on INPUT, read along INPUT's triangles: exit 4 if MESH has "
      "self-intersecting face pairs that INPUT lacks")(
      "fail-on-self-intersections", po::bool_switch(&fail_on_intersections),
      "exit 4 if MESH has any self-intersecting face pairs");
  try {
    const po::variables_map vm = parse_command_line(argc, argv, visible, input);
    if (vm.count("help")) {
      std::cout << check_usage() << '\n' << visible << '\n';
      return static_cast<int>(ExitCode::Success);
    }
    if (input.empty()) throw UsageError("missing INPUT mesh");
  } catch (const po::error& e) {
    return usage_error("check", e.what());
  } catch (const UsageError& e) {
    return usage_error("check", e.what());
  }

  std::string stage = input;  // the file whose problem a JSON error reports
  try {
    // With --against two files are read, and a warning (a polygon split, a face of zero area)
    // is about one of them: it names its file.
    const auto print_warnings = [&against](const std::string& file, const InputReport& r) {
      for (const std::string& w : r.warnings)
        std::cerr << "warning: " << (against.empty() ? std::string() : file + ": ") << w << '\n';
      for (const std::string& n : r.notes)
        std::cerr << "note: " << (against.empty() ? std::string() : file + ": ") << n << '\n';
    };
    // With --against, INPUT is read first: MESH's polygons are split into the triangles `run`
    // simulated, INPUT's (read_result_mesh), not along the diagonals MESH's folded shape prefers,
    // which could cross a sheet the simulated pair kept apart.
    InputReport report, against_report;
    Mesh input_mesh;
    Polygons in;
    if (!against.empty()) {
      stage = against;
      input_mesh = read_input_mesh(against, &against_report);
      in = read_polygons(against);
      stage = input;
    }
    const Mesh mesh = against.empty() ? read_input_mesh(input, &report)
                                      : read_result_mesh(input, against, input_mesh, in, &report);
    print_warnings(input, report);
    if (!against.empty()) print_warnings(against, against_report);
    const Positions x = positions_from_mesh(mesh);
    // stableNorm: the squares of extents near 1e+-160 and beyond leave double's range, and
    // check reports on any mesh it can read, however far its scale is from the engine's.
    const double diagonal = (x.colwise().maxCoeff() - x.colwise().minCoeff()).stableNorm();
    const SurfaceTopology topology = surface_topology(mesh, report.components);
    const long long chi = topology.euler_characteristic, genus = topology.genus;

    // A result judged against its input, or on its own (exit 4 when it fails).
    std::size_t input_pair_count = 0;
    std::optional<NewPairs> is_new;
    if (!against.empty()) {
      stage = against;
      // INPUT's pairs are all kept, to tell MESH's new ones from them: bounded as run
      // --validate bounds its own (validation.hpp, baseline_pair_limit).
      const std::size_t limit = baseline_pair_limit(input_mesh.number_of_faces());
      const SelfIntersectionCount own =
          count_self_intersections(input_mesh, positions_from_mesh(input_mesh), limit, limit);
      if (!own.complete)
        throw InputError(too_many_own_pairs(against, limit) + "; check " + input +
                         " without --against");
      input_pair_count = own.count;
      is_new = new_pairs(input, mesh, against, input_mesh, in, own.first);
    }
    // MESH's pairs can number the square of its faces (parts that pass through each other):
    // they are counted, and the first CHECK_LISTED_PAIRS in face order listed (docs/cli.md,
    // "check").
    FacePairSample all(CHECK_LISTED_PAIRS), fresh(CHECK_LISTED_PAIRS);
    for_each_self_intersection(mesh, x, [&](const FacePair& p) {
      all.add(p);
      if (is_new && (*is_new)(p)) fresh.add(p);
      return true;
    });
    const std::vector<FacePair> pairs = all.pairs(), fresh_pairs = fresh.pairs();
    const bool fails = fresh.count() > 0 || (fail_on_intersections && all.count() > 0);
    std::string verdict;
    if (fresh.count() > 0)
      verdict = std::to_string(fresh.count()) + " self-intersecting face pairs that " + against +
                " does not have";
    else if (fails)
      verdict = std::to_string(all.count()) +
                " self-intersecting face pairs (--fail-on-self-intersections)";

    if (json) {
      JsonObject o;
      o.add("file", input)
          .add("usable", true)
          .add("vertices", report.vertices)
          .add("faces", report.faces)
          .add("edges", static_cast<std::size_t>(mesh.number_of_edges()))
          .add("components", report.components)
          .add_raw("euler_characteristic", std::to_string(chi))
          .add_raw("genus", std::to_string(genus))
          .add("closed", true)
          .add("manifold", true)
          .add("volume", report.volume)
          .add("bounding_box_diagonal", diagonal)
          .add("reoriented", report.reoriented)
          .add("triangulated_faces", report.triangulated_faces)
          .add_raw("zero_area_faces", json_array(report.zero_area_faces))
          .add("self_intersecting_pairs", all.count())
          .add_raw("self_intersections", json_pairs(pairs))
          .add("self_intersections_truncated", all.truncated())
          .add("warnings", report.warnings);
      if (!against.empty()) {
        o.add("against", against)
            .add("against_warnings", against_report.warnings)
            .add("input_self_intersecting_pairs", input_pair_count)
            .add("new_self_intersecting_pairs", fresh.count())
            .add_raw("new_self_intersections", json_pairs(fresh_pairs))
            .add("new_self_intersections_truncated", fresh.truncated());
      }
      if (!against.empty() || fail_on_intersections) o.add("passes", !fails).add("failure", verdict);
      std::cout << o.str() << '\n';
    } else {
      ClassicOStringStream out;
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
      out << "\nself_intersecting_pairs: " << all.count() << text_pairs(pairs, all.count());
      out << "\nusable: yes\n";
      if (!against.empty()) {
        out << "against: " << against << "\ninput_self_intersecting_pairs: " << input_pair_count
            << "\nnew_self_intersecting_pairs: " << fresh.count()
            << text_pairs(fresh_pairs, fresh.count()) << '\n';
      }
      if (!against.empty() || fail_on_intersections) out << "passes: " << (fails ? "no (" + verdict + ")" : "yes") << '\n';
      std::cout << out.str();
    }
    if (fails) {
      std::cerr << "shellcontract check: " << input << " fails: " << verdict << '\n';
      return static_cast<int>(ExitCode::NewSelfIntersections);
    }
    return static_cast<int>(ExitCode::Success);
  } catch (const UsageError& e) {
    // --json promises an object on stdout whatever the outcome (here: meshes that are not the same).
    if (json) {
      JsonObject o;
      o.add("file", input).add("against", against).add("error", std::string(e.what()));
      std::cout << o.str() << '\n';
    }
    return usage_error("check", e.what());
  } catch (const InputError& e) {
    std::cerr << "shellcontract check: " << e.what() << '\n';
    if (json) {
      JsonObject o;
      o.add("file", stage).add("usable", false).add("error", std::string(e.what()));
      std::cout << o.str() << '\n';
    }
    return static_cast<int>(ExitCode::BadInput);
  }
}

}  // namespace shellcontract::cli
