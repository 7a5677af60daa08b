// shellcontract repair IN -o OUT [--json] [--max-hole-edges N]: makes a refused mesh usable with
// CGAL's repair functions (repair_input_mesh) and writes it (write_repair_output: a usable input
// unchanged; OFF, OBJ, PLY, STL, .glb or .gltf), naming what the output does not carry; on
// failure writes nothing.
#include "shellcontract/repair.hpp"

#include <boost/program_options.hpp>
#include <iostream>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "commands.hpp"
#include "json_writer.hpp"
#include "mesh/formats.hpp"
#include "mesh/repair_output.hpp"
#include "output_paths.hpp"
#include "shellcontract/error.hpp"
#include "stage_notice.hpp"

namespace shellcontract::cli {
namespace {

namespace po = boost::program_options;

constexpr const char* REPAIR_USAGE =
    R"(usage: shellcontract repair INPUT -o OUTPUT [--json] [--max-hole-edges N]

Makes a mesh that 'check' refuses usable, with CGAL's Polygon Mesh Processing: merges duplicate
points and faces, removes degenerate faces, orients the faces consistently, stitches borders,
fills every hole (triangulate, refine and fair), drops components that are still open or enclose
no volume, orients each component outward, and checks the result as 'check' does. Prints what
changed, and what OUTPUT does not carry, on stderr (--json: on stdout).

What OUTPUT keeps:
  a mesh 'check' accepts is not rewritten: an OUTPUT of its format is a byte-for-byte copy (UVs,
  normals, groups, materials, quads, comments, extra PLY properties, binary STL or PLY, a glTF's
  nodes, materials and textures); another format gets its vertices and polygons as read, in
  their order and winding (STL and glTF: triangles). A .gltf copied into another folder: a
  warning names each buffer or image file it reads that is not beside the copy.
  A repaired mesh has new vertices and triangles in another order: the input's UVs, normals,
  groups, materials, colours, extra PLY properties, comments, glTF nodes, textures and names are
  dropped, each one named in the report ("dropped from OUTPUT ..."); a binary PLY stays binary,
  a binary STL too in an STL.
  A .glb or .gltf that is not a copy holds one node and one mesh: POSITION (32-bit floats: digits
  that a float does not hold are named among the dropped), area-weighted vertex normals (NORMAL)
  and 32-bit indices; a .gltf carries its buffer inside, as a base64 data URI.

exit codes: 0 OUTPUT written and usable, 1 bad usage (also: an OUTPUT whose extension is none
            of -o's formats, refused before INPUT is read; an STL OUTPUT in which two vertices
            would be stored at one position, which an STL reader merges; a glTF OUTPUT whose
            positions rounded to 32-bit floats would no longer be usable), 2 the input cannot be
            repaired into a usable mesh (the message says why; nothing is written), 3 memory ran
            out or the system refused a resource (a thread, an open file), 130 interrupted

options)";

JsonObject report_json(const std::string& input, const std::string& output, const RepairReport& r,
                       const RepairOutput* written) {
  JsonObject o;
  o.add("file", input)
      .add("output", written ? output : std::string())
      .add("written_as", written ? written->kind_name() : std::string())
      .add("binary", written && written->binary)
      .add("dropped", written ? written->dropped : std::vector<std::string>())
      .add("material_paths_rewritten", written && written->material_paths_rewritten)
      .add("warnings", written ? written->warnings : std::vector<std::string>())
      .add("usable", r.usable)
      .add("already_usable", r.already_usable)
      .add("input_problem", r.input_problem)
      .add("failure", r.failure)
      .add("input_vertices", r.input_vertices)
      .add("input_polygons", r.input_polygons)
      .add("missing_vertex_faces_dropped", r.missing_vertex_faces_dropped)
      .add("duplicate_points_merged", r.duplicate_points_merged)
      .add("soup_polygons_removed", r.soup_polygons_removed)
      .add("points_duplicated_to_orient", r.points_duplicated_to_orient)
      .add("polygons_triangulated", r.polygons_triangulated)
      .add("border_edges_stitched", r.border_edges_stitched)
      .add("degenerate_faces_removed", r.degenerate_faces_removed)
      .add("isolated_vertices_removed", r.isolated_vertices_removed)
      .add("holes_filled", r.holes_filled)
      .add("hole_faces_added", r.hole_faces_added)
      .add("hole_vertices_added", r.hole_vertices_added)
      .add("largest_hole_edges", r.largest_hole_edges)
      .add("holes_not_faired", r.holes_not_faired)
      .add("holes_unfilled", r.holes_unfilled)
      .add("hole_self_intersections", r.hole_self_intersections)
      .add("components_dropped", r.components_dropped)
      .add("faces_dropped", r.faces_dropped)
      .add("vertices", r.usable ? r.input_report.vertices : 0)
      .add("faces", r.usable ? r.input_report.faces : 0)
      .add("components", r.usable ? r.input_report.components : 0)
      .add("volume", r.usable ? r.input_report.volume : 0.0);
  return o;
}

}  // namespace

int command_repair(int argc, char** argv) {
  std::string input, output;
  bool json = false;
  // Signed, so that a negative N is read as given and refused: Boost reads "-1" into an unsigned
  // type as its wrapped value, which filled every hole silently.
  long long max_hole_edges = 0;
  po::options_description visible;
  // Every format of the table (mesh/formats.hpp) is written by repair; Boost copies the text.
  const std::string output_help =
      "repaired mesh (format from the extension: " + extension_list(any_format, "", ", ") + ")";
  visible.add_options()("help,h", "show this help")(
      "output,o", po::value(&output)->value_name("FILE"), output_help.c_str())(
      "json", po::bool_switch(&json), "print the report as a JSON object on stdout")(
      "max-hole-edges", po::value(&max_hole_edges)->value_name("N"),
      "leave holes with more than N boundary edges open (their component is then dropped); an "
      "integer >= 0; default (or 0): fill every hole");
  try {
    const po::variables_map vm = parse_command_line(argc, argv, visible, input);
    if (vm.count("help")) {
      std::cout << REPAIR_USAGE << '\n' << visible << '\n';
      return static_cast<int>(ExitCode::Success);
    }
    if (input.empty()) throw UsageError("missing INPUT mesh");
    if (output.empty()) throw UsageError("missing -o OUTPUT");
    if (max_hole_edges < 0)
      throw UsageError("--max-hole-edges " + std::to_string(max_hole_edges) +
                       ": must be an integer >= 0 (0: fill every hole)");
    OutputPlan plan;
    plan.inputs.push_back({"INPUT", input});
    plan.outputs.push_back({"-o", output});
    check_planned_outputs(plan);  // a folder or device at -o is refused for what it is first
    check_repair_output_name("-o", output);
  } catch (const po::error& e) {
    return usage_error("repair", e.what());
  } catch (const UsageError& e) {
    return usage_error("repair", e.what());
  }

  RepairReport r;
  RepairOutput written;
  try {
    // Names a stage silent for a second (cli/stage_notice.hpp): a large mesh's repair takes tens
    // of seconds. Destroyed (its thread stopped) before anything else is printed.
    StageNotice notice(std::cerr, true);
    const ProgressStageScope stages = notice.scope();
    const Mesh mesh = repair_input_mesh(input, &r, static_cast<std::size_t>(max_hole_edges));
    notice.begin("writing " + output);
    written = write_repair_output(input, output, mesh, r);
  } catch (const InputError& e) {
    std::cerr << "shellcontract repair: " << e.what() << '\n';
    if (json) std::cout << report_json(input, output, r, nullptr).str() << '\n';
    return static_cast<int>(ExitCode::BadInput);
  } catch (const UsageError& e) {  // the output could not be written (a full disk, an STL...)
    std::cerr << "shellcontract repair: " << e.what() << '\n';
    // --json promises the report on stdout: what the repair did is as true as when the input
    // was refused, only nothing was written.
    if (json) std::cout << report_json(input, output, r, nullptr).str() << '\n';
    return static_cast<int>(ExitCode::BadUsage);
  }
  for (const std::string& w : written.warnings) std::cerr << "warning: " << w << '\n';
  if (json) {
    std::cout << report_json(input, output, r, &written).str() << '\n';
  } else {
    if (!r.already_usable) std::cerr << "input refused as read: " << r.input_problem << '\n';
    for (const std::string& line : r.summary_lines()) std::cerr << line << '\n';
    if (!written.dropped.empty()) {
      std::cerr << (written.kind == RepairOutput::Kind::Converted
                        ? "not carried into " + output + " (another format: it gets the vertices and polygons; " +
                              "an output in the input's format would be an unchanged copy): "
                        : "dropped from " + output + " (repair writes only its rebuilt vertices and faces): ");
      for (std::size_t i = 0; i < written.dropped.size(); ++i) std::cerr << (i ? "; " : "") << written.dropped[i];
      std::cerr << '\n';
    }
    // A copy holds the file's vertices, seam copies included; the report counts the welded mesh.
    const std::size_t written_vertices =
        r.input_report.vertices + (written.kind == RepairOutput::Kind::Copy ? r.input_report.welded_vertices : 0);
    std::cerr << "wrote " << output << ": " << written_vertices << " vertices"
              << (written_vertices != r.input_report.vertices
                      ? " (" + std::to_string(r.input_report.vertices) + " once its seam copies are welded)"
                      : std::string())
              << ", " << r.input_report.faces << " faces, usable"
              << (written.kind != RepairOutput::Kind::Copy ? ""
                  : written.material_paths_rewritten
                      ? " (the input's bytes, but the mtllib paths rewritten to name the same files from its folder)"
                      : " (the input's bytes, unchanged)")
              << '\n';
  }
  return static_cast<int>(ExitCode::Success);
}

}  // namespace shellcontract::cli
