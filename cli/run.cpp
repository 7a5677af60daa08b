// shellcontract run: parse the options (from the library's option table), check the outputs,
// call run_contraction with the CLI's observers, write the files and return the exit code. The
// steps are in run_steps.hpp; command_run takes them in order and reports what stopped them.
#include "shellcontract/run.hpp"

#include <boost/program_options.hpp>
#include <iostream>
#include <memory>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>

#include "commands.hpp"
#include "core/memory_error.hpp"
#include "mesh/formats.hpp"
#include "output_paths.hpp"
#include "run_checkpoint.hpp"
#include "run_command_line.hpp"
#include "run_document.hpp"
#include "run_failure.hpp"
#include "run_interrupt.hpp"
#include "run_precision.hpp"
#include "run_steps.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"
#include "stage_notice.hpp"

namespace po = boost::program_options;

namespace shellcontract::cli {

void describe_run_options(po::options_description& desc, RunRequest& q) {
  // The formats from the table (mesh/formats.hpp); Boost copies the description.
  const std::string output_help = "output mesh (format from the extension: " +
                                  extension_list(&MeshFormat::plain_writer, "", ", ") + "; " +
                                  extension_list(&MeshFormat::gltf, "", " or ") +
                                  " for an input of that format)";
  desc.add_options()("help,h", "show this help")(
      "output,o", po::value(&q.output)->value_name("FILE"), output_help.c_str())(
      "repair", po::bool_switch(&q.repair),
      "repair the input first if 'check' refuses it (as 'shellcontract repair' does; the output "
      "then has the repaired mesh's vertices and faces)");
  add_table_options(desc, q.values, q.switches, q.lists);
  desc.add_options()(
      "fields", po::value(&q.fields_prefix)->value_name("PREFIX"),
      "write PREFIX_start.ply and PREFIX_end.ply: per-vertex mean and Gaussian curvature, "
      "pressure load and elastic energy density, coloured by --fields-colour")(
      "fields-colour",
      po::value(&q.fields_colour)->default_value(q.fields_colour)->value_name("NAME"),
      "mean | gaussian | pressure | energy: blue-white-red over the 2nd-98th percentile")(
      "export-every", po::value(&q.export_every_text)->value_name("N"),
      "with --export-dir or --gltf: keep every N-th frame (and the first and last); default: "
      "about 100 frames of the run (N = --frames / 100, rounded up)")(
      "export-dir", po::value(&q.exports.dir)->value_name("DIR"),
      "write the kept frames as DIR/<output name>_<frame>.<output format> (created if missing), "
      "each written as -o is (an OBJ or PLY input's attributes kept)")(
      "export-failure",
      po::value(&q.export_failure)->default_value(q.export_failure)->value_name("WHAT"),
      "when a frame file cannot be written (a full disk): warn (the export stops, the run goes "
      "on) or stop (the run ends there); either way the result, log and summary are written")(
      "gltf", po::value(&q.exports.gltf)->value_name("FILE.glb"),
      "write the kept frames as one animated glTF 2.0 binary (morph targets, normals, the end "
      "state's fields as custom attributes), named after the input; the input's materials and "
      "textures (an OBJ's .mtl, a PLY's TextureFile, a glTF's own; images embedded), one "
      "primitive per material; open it with scripts/view.py")(
      "gltf-fps", po::value(&q.gltf_fps)->value_name("F"),
      "with --gltf: the animation's frame rate, run frame k keyed at k / F seconds (default 24, "
      "at most 1000)")("log", po::value(&q.log_path)->value_name("FILE.csv"), "per-frame CSV log")(
      "summary", po::value(&q.summary_path)->value_name("FILE.json"), "JSON summary of the run")(
      "quiet,q", po::bool_switch(&q.quiet), "no progress on stderr")(
      "checkpoint", po::value(&q.checkpoint_path)->value_name("FILE"),
      "save the whole state to FILE (atomically) every --checkpoint-every frames and on SIGINT, "
      "SIGTERM, SIGHUP or SIGUSR1, which then stop the run (exit code 130, no other output); "
      "--resume continues it; a second run with FILE is refused while this one runs (default "
      "with --resume FILE: FILE)")(
      "checkpoint-every", po::value(&q.checkpoint_every_text)->value_name("N"),
      "with --checkpoint or --resume: frames between saves (default: the resumed run's; else only "
      "on a signal)")(
      "resume", po::value(&q.resume_path)->value_name("FILE"),
      "continue the run saved in FILE (its input, unless INPUT is given, and its options; options "
      "given must equal its own, --threads excepted; the face list or weights file must not have "
      "changed): the same result, to the byte, as the run that was not interrupted; it goes on "
      "saving to FILE unless --checkpoint names another");
}

int command_run(int argc, char** argv) {
  RunRequest request;
  po::options_description desc(RUN_USAGE, 100, 50);
  describe_run_options(desc, request);
  RunClaims claims;
  if (const std::optional<int> ended = prepare_run(argc, argv, desc, request, claims))
    return *ended;

  RunTrace trace;
  trace.stage = (request.repair ? "reading and repairing " : "reading ") + request.input;
  const ExportRequest& exports = request.exports;
  try {
    // Names a stage silent for a second (cli/stage_notice.hpp): reading, the run's preparation,
    // the check at the end, the writing. Made first: destroyed (its thread stopped) last.
    StageNotice notice(std::cerr, !request.quiet);
    const RunInputMesh input = read_run_input(request, notice);
    const Mesh& mesh = input.mesh;
    // Shared with the frame writer's thread (run_document.hpp).
    const std::shared_ptr<const MeshDocument> document =
        run_input_document(request.input, request.output, !exports.gltf.empty(), mesh,
                           request.repair, input.report.triangulated_faces);
    const std::string float32_warning =
        warn_float32_gltf(request.output, document.get(), mesh, request.options, notice);
    RunObservers observers(request, mesh, document, notice);

    trace.faces = std::to_string(mesh.number_of_faces()) + " faces";
    // run_contraction ends the run itself when memory runs out during the frames.
    trace.stage = "preparing the run or taking its result";
    CliCheckpointer& checkpointer = *observers.checkpointer;
    RunResult r = run_contraction(mesh, request.options, &observers.list, &checkpointer);
    notice.end();  // a run cancelled in its preparation ends no stage itself
    // Said before the run, it belongs with the run's warnings in the summary.
    if (!float32_warning.empty()) r.warnings.insert(r.warnings.begin(), float32_warning);
    // Nothing is written: the run is not over (its state is in the checkpoint, if any).
    if (r.status == RunStatus::Cancelled && checkpointer.interrupted())
      return report_interrupted(r, checkpointer, request.output, exports,
                                observers.exporter.frame_stats(), !request.fields_prefix.empty());
    second_signal::phase.store(second_signal::Outputs);
    // A signal during the last step came too late to stop it (the handler says so itself for
    // one from now on).
    if (checkpoint_signal::received != 0) second_signal::acknowledge_late_stop();

    // Before the summary is made: `validate` judges the result as the -o file will hold it.
    trace.stage = "checking the result as " + request.output + " stores it";
    validate_as_written(request.output, document.get(), mesh, request.options, r, notice);
    OutputWriter writer(notice, trace);
    write_run_outputs(writer, request, input, document, r, observers);
    return report_run_end(request, r, writer.outputs);
  } catch (const InputError& e) {
    std::cerr << "shellcontract run: " << spell_options(e.what(), OptionSpelling::Cli) << '\n';
    return static_cast<int>(ExitCode::BadInput);
  } catch (const UsageError& e) {
    std::cerr << "shellcontract run: " << spell_options(e.what(), OptionSpelling::Cli) << '\n';
    return static_cast<int>(ExitCode::BadUsage);
  } catch (const OutOfMemoryError& e) {
    // An input larger than the memory there is: its reader's message names it.
    std::cerr << "shellcontract run: " << e.what() << "; "
              << what_was_left(trace.written, count_frame_files(claims.frames), exports.dir)
              << '\n';
    return static_cast<int>(ExitCode::SimulationFailed);
  } catch (const std::bad_alloc&) {
    // The frame files already written stay (the writer finished them as it was destroyed).
    std::cerr << "shellcontract run: out of memory while " << trace.stage
              << (trace.faces.empty() ? "" : " (" + trace.faces + ")") << "; "
              << what_was_left(trace.written, count_frame_files(claims.frames), exports.dir)
              << '\n';
    return static_cast<int>(ExitCode::SimulationFailed);
  } catch (const std::runtime_error& e) {
    // A resource the system refused besides memory (TBB's threads: "pthread_create has failed").
    std::cerr << "shellcontract run: " << e.what() << " (while " << trace.stage << "); "
              << what_was_left(trace.written, count_frame_files(claims.frames), exports.dir)
              << '\n';
    return static_cast<int>(ExitCode::SimulationFailed);
  }
}

}  // namespace shellcontract::cli
