// run's input and observers (run_steps.hpp): the mesh read (and repaired), what the reader said,
// and the observers and checkpointer the run reports to.
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>

#include "command_line.hpp"
#include "mesh/output_check.hpp"
#include "mesh/stl_positions.hpp"
#include "output_sizes.hpp"
#include "run_document.hpp"
#include "run_second_signal.hpp"
#include "run_steps.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/repair.hpp"
#include "sim/checkpoint.hpp"

namespace shellcontract::cli {
namespace {

/// --regions FILE and --region-weights FILE number the input's faces and vertices; a repair that
/// changed the mesh renumbered them (CGAL, design/repair.md), so the ids would fall on other
/// faces without a word. Refused (bad usage) once the repair says it changed the mesh.
void refuse_ids_of_the_input(const RunOptions& options, const std::string& input) {
  const auto refuse = [&](const std::string& option, const std::string& file, const char* ids) {
    throw UsageError(option + " " + file + " numbers the " + ids + " of " + input +
                     " as read, and --repair renumbered them (it changed the mesh): run "
                     "`shellcontract repair` first and make the file for the repaired mesh");
  };
  if (options.regions == RegionSource::File) refuse("--regions", options.region_file, "faces");
  if (!options.region_weight_file.empty())
    refuse("--region-weights", options.region_weight_file, "vertices");
}

/// What the progress line says the regions are, "" when the run selects none itself. Regions
/// are auto-selected when asked for, or implied by an anisotropic energy; --region-at makes them
/// Auto too (resolve_run_options): its caps are at the points.
std::string auto_regions_text(const RunOptions& options) {
  const bool auto_regions =
      options.regions == RegionSource::Auto ||
      (options.regions == RegionSource::None && !options.given.count("regions") &&
       (options.sim.solver.aniso != AnisoKind::None || options.measure_regions));
  if (!auto_regions) return std::string();
  return options.region_points.empty() ? "spherical regions selected by curvature"
                                       : "regions grown at the --region-at points";
}

}  // namespace

RunInputMesh read_run_input(const RunRequest& request, StageNotice& notice) {
  const std::string& input = request.input;
  RunInputMesh in;
  const auto read_start = std::chrono::steady_clock::now();
  {
    const ProgressStageScope stages = notice.scope();
    in.mesh = request.repair ? repair_input_mesh(input, &in.repair_report)
                             : read_input_mesh(input, &in.report);
  }
  notice.end();
  if (request.repair) {
    in.report = in.repair_report.input_report;
    if (!in.repair_report.already_usable) {
      std::cerr << "repaired " << input << " (refused as read: " << in.repair_report.input_problem
                << ")\n";
      for (const std::string& line : in.repair_report.summary_lines())
        std::cerr << "  " << line << '\n';
      refuse_ids_of_the_input(request.options, input);
    }
  }
  in.read_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();
  for (const std::string& w : in.report.warnings) std::cerr << "warning: " << w << '\n';
  for (const std::string& n : in.report.notes) std::cerr << "note: " << n << '\n';
  // Two vertices at one position read back from an STL as one: refused before the run.
  const std::string& output = request.output;
  if (lower_extension(output) == "stl")
    require_distinct_stl_positions(
        "-o " + output + (request.exports.dir.empty() ? "" : " and its frames"), in.mesh,
        positions_from_mesh(in.mesh), false);
  // A large mesh takes seconds to read and check (bear subdivided three times, 1.77 M faces:
  // about 3 s), before any frame's progress line.
  if (!request.quiet && in.read_seconds >= 1.0)
    std::cerr << "read " << input << ": " << in.mesh.number_of_vertices() << " vertices, "
              << in.mesh.number_of_faces() << " faces in " << std::setprecision(3)
              << in.read_seconds << " s\n";
  return in;
}

RunObservers::RunObservers(const RunRequest& request, const Mesh& mesh,
                           const std::shared_ptr<const MeshDocument>& document, StageNotice& notice)
    : warnings(notice),
      progress(request.options.sim.frames, auto_regions_text(request.options), notice),
      fields(request.fields_prefix, request.colour),
      exporter(request.exports, mesh, request.options.sim.frames) {
  const ExportRequest& exports = request.exports;
  list.add(warnings);
  if (!request.quiet) list.add(progress);
  if (!request.log_path.empty() || !request.checkpoint_path.empty()) list.add(csv);
  const Checkpoint* resume = request.resume_path.empty() ? nullptr : &request.resume;
  if (resume) {
    check_checkpoint_input(*resume, request.input, mesh);  // InputError: exit 2
    csv.restore(resume->log);
  }
  // Before the checkpointer sets its handler.
  second_signal::describe(request.checkpoint_path, request.output, exports.dir);
  checkpointer.emplace(request.checkpoint_path, request.checkpoint_every, resume, request.input,
                       mesh_hash(mesh), request.inputs, request.options, csv);
  if (!request.fields_prefix.empty()) list.add(fields);
  if (!exports.dir.empty() || !exports.gltf.empty()) list.add(exporter);
  if (!exports.gltf.empty()) prepare_gltf_animation(exporter, request.input, document.get(), mesh);
  exporter.set_document(document);
  const RunOptions& o = request.options;
  exporter.expect_regions(!auto_regions_text(o).empty() || o.regions == RegionSource::File ||
                          o.regions == RegionSource::Weights || !o.region_weight_file.empty() ||
                          !o.region_points.empty());
  // The large outputs' sizes, known before the run (output_sizes.hpp): a .glb over the 4 GiB
  // it can hold is refused now, not corrupted after hours; very large outputs are warned of.
  check_run_output_sizes(exporter, exports, mesh, document.get(), request.input,
                         request.fields_prefix, request.options.sim.frames, std::cerr);
}

}  // namespace shellcontract::cli
