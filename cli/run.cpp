// shellcontract run: parse the options (from the library's option table), check the outputs,
// call run_contraction with the CLI's observers, write the files and return the exit code.
#include "shellcontract/run.hpp"

#include <algorithm>
#include <boost/program_options.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <new>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "command_line.hpp"
#include "commands.hpp"
#include "core/decimal_text.hpp"
#include "core/memory_error.hpp"
#include "core/plural.hpp"
#include "export_observer.hpp"
#include "json_writer.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/output_check.hpp"
#include "mesh/stl_positions.hpp"
#include "output_paths.hpp"
#include "output_sizes.hpp"
#include "run_checkpoint.hpp"
#include "run_command_line.hpp"
#include "run_document.hpp"
#include "run_failure.hpp"
#include "run_interrupt.hpp"
#include "run_observers.hpp"
#include "run_summary.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/repair.hpp"
#include "shellcontract/report.hpp"
#include "sim/checkpoint.hpp"
#include "stage_notice.hpp"

namespace po = boost::program_options;

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

}  // namespace

int command_run(int argc, char** argv) {
  std::string input, output, log_path, summary_path, fields_prefix, fields_colour = "mean";
  std::string export_failure = "warn", gltf_fps;
  ExportRequest exports;
  bool quiet = false, repair = false;
  std::map<std::string, std::string> values;
  std::map<std::string, bool> switches;
  RunOptions options;
  std::string checkpoint_path, resume_path;
  int checkpoint_every = 0;
  std::string checkpoint_every_text, export_every_text;  // frame_count reads them
  bool saves_to_resumed = false;  // run --resume FILE without --checkpoint: saves to FILE
  Checkpoint resume;
  std::vector<RunInput> inputs;
  po::options_description desc(RUN_USAGE, 100, 50);
  desc.add_options()("help,h", "show this help")(
      "output,o", po::value(&output)->value_name("FILE"),
      "output mesh (format from the extension: off, obj, ply, stl; glb or gltf for an input of "
      "that format)")(
      "repair", po::bool_switch(&repair),
      "repair the input first if 'check' refuses it (as 'shellcontract repair' does; the output "
      "then has the repaired mesh's vertices and faces)");
  std::map<std::string, std::vector<std::string>> lists;
  add_table_options(desc, values, switches, lists);
  desc.add_options()(
      "fields", po::value(&fields_prefix)->value_name("PREFIX"),
      "write PREFIX_start.ply and PREFIX_end.ply: per-vertex mean and Gaussian curvature, "
      "pressure load and elastic energy density, coloured by --fields-colour")(
      "fields-colour", po::value(&fields_colour)->default_value(fields_colour)->value_name("NAME"),
      "mean | gaussian | pressure | energy: blue-white-red over the 2nd-98th percentile")(
      "export-every", po::value(&export_every_text)->value_name("N"),
      "with --export-dir or --gltf: keep every N-th frame (and the first and last); default: "
      "about 100 frames of the run (N = --frames / 100, rounded up)")(
      "export-dir", po::value(&exports.dir)->value_name("DIR"),
      "write the kept frames as DIR/<output name>_<frame>.<output format> (created if missing), "
      "each written as -o is (an OBJ or PLY input's attributes kept)")(
      "export-failure",
      po::value(&export_failure)->default_value(export_failure)->value_name("WHAT"),
      "when a frame file cannot be written (a full disk): warn (the export stops, the run goes "
      "on) or stop (the run ends there); either way the result, log and summary are written")(
      "gltf", po::value(&exports.gltf)->value_name("FILE.glb"),
      "write the kept frames as one animated glTF 2.0 binary (morph targets, normals, the end "
      "state's fields as custom attributes), named after the input; the input's materials and "
      "textures (an OBJ's .mtl, a PLY's TextureFile, a glTF's own; images embedded), one "
      "primitive per material; open it with scripts/view.py")(
      "gltf-fps", po::value(&gltf_fps)->value_name("F"),
      "with --gltf: the animation's frame rate, run frame k keyed at k / F seconds (default 24, "
      "at most 1000)")("log", po::value(&log_path)->value_name("FILE.csv"), "per-frame CSV log")(
      "summary", po::value(&summary_path)->value_name("FILE.json"), "JSON summary of the run")(
      "quiet,q", po::bool_switch(&quiet), "no progress on stderr")(
      "checkpoint", po::value(&checkpoint_path)->value_name("FILE"),
      "save the whole state to FILE (atomically) every --checkpoint-every frames and on SIGINT, "
      "SIGTERM, SIGHUP or SIGUSR1, which then stop the run (exit code 130, no other output); "
      "--resume continues it; a second run with FILE is refused while this one runs (default "
      "with --resume FILE: FILE)")(
      "checkpoint-every", po::value(&checkpoint_every_text)->value_name("N"),
      "with --checkpoint or --resume: frames between saves (default: the resumed run's; else only "
      "on a signal)")(
      "resume", po::value(&resume_path)->value_name("FILE"),
      "continue the run saved in FILE (its input, unless INPUT is given, and its options; options "
      "given must equal its own, --threads excepted; the face list or weights file must not have "
      "changed): the same result, to the byte, as the run that was not interrupted; it goes on "
      "saving to FILE unless --checkpoint names another");
  FieldColour colour = FieldColour::MeanCurvature;
  std::unique_ptr<ExportFolderLock> export_lock;  // held until the run's files are written
  PlannedFrames frames_planned;    // the frames of --export-dir, for what a failed run leaves
  CheckpointLocks checkpoint_locks;  // held until the run ends
  CheckpointLocks resumed_lock;      // --resume's, taken before it is read: into checkpoint_locks
  try {
    const po::variables_map vm = parse_command_line(argc, argv, desc, input);
    if (vm.count("help")) {
      std::cout << desc << RUN_EXIT_CODES;
      return 0;
    }
    if (!resume_path.empty()) {
      // Read under its lock: a run that holds it may be saving there (UsageError: exit 1).
      resumed_lock = lock_resumed_checkpoint(resume_path, checkpoint_path, OptionSpelling::Cli);
      resume = read_checkpoint(resume_path);  // InputError: exit 2
    }
    if (input.empty() && !resume_path.empty()) input = checkpoint_input(resume, resume_path);
    if (input.empty()) throw UsageError("missing INPUT mesh");
    if (output.empty()) throw UsageError("missing -o OUTPUT");
    for (const OptionSpec& o : run_option_table()) {
      if (o.is_switch) {
        if (switches[o.name]) o.set(options, "on");
      } else if (o.repeatable) {
        std::string joined;
        for (const std::string& v : lists[o.name]) joined += (joined.empty() ? "" : ";") + v;
        if (vm.count(o.name)) o.set(options, joined);
      } else if (vm.count(o.name) && !vm[o.name].defaulted()) {
        o.set(options, values[o.name]);
      }
    }
    if (!resume_path.empty()) options = options_for_resume(resume, options);
    resolve_run_options(options);
    // The face list or weights file as the run starts, recorded in its checkpoints; a resumed
    // run's must be the checkpoint's (InputError: exit 2).
    if (!checkpoint_path.empty() || !resume_path.empty()) inputs = run_inputs(options);
    if (!resume_path.empty()) check_checkpoint_files(resume, inputs);
    if (vm.count("checkpoint-every"))
      checkpoint_every = frame_count("--checkpoint-every", checkpoint_every_text);
    if (vm.count("export-every")) exports.every = frame_count("--export-every", export_every_text);
    if (vm.count("checkpoint-every") && (checkpoint_path.empty() && resume_path.empty()))
      throw UsageError(
          "--checkpoint-every: expected an integer >= 1, with --checkpoint or --resume");
    if (!resume_path.empty() && (!fields_prefix.empty() || !exports.dir.empty() ||
                                 !exports.gltf.empty()))
      throw UsageError(
          "--fields, --export-dir and --gltf cannot be combined with --resume: the frames before "
          "the checkpoint are not in it");
    colour = parse_field_colour(fields_colour);
    if (export_failure != "warn" && export_failure != "stop")
      throw UsageError("--export-failure: '" + export_failure + "' is not warn or stop");
    exports.stop_run_on_failure = export_failure == "stop";
    // Options that shape an output not asked for: warnings, as for the run's own options
    // (ineffective_options), not errors, so that a script can keep them while it toggles the output.
    const auto given = [&](const char* name) { return vm.count(name) && !vm[name].defaulted(); };
    if (given("fields-colour") && fields_prefix.empty())
      std::cerr << "warning: --fields-colour has no effect: it colours the files of --fields\n";
    if (given("export-failure") && exports.dir.empty() && exports.gltf.empty())
      std::cerr << "warning: --export-failure has no effect: it is what a failed frame file of "
                   "--export-dir or --gltf does\n";
    // A resumed run saves as the interrupted one did: into the file it resumed from (unless
    // --checkpoint names another) and as often (unless --checkpoint-every says otherwise).
    saves_to_resumed = !resume_path.empty() && checkpoint_path.empty();
    if (saves_to_resumed) checkpoint_path = resumed_run_checkpoint(resume_path, {{"INPUT", input}});
    if (!resume_path.empty() && !vm.count("checkpoint-every")) checkpoint_every = resume.save_every;
    // Only the CSV log reports the energies; a checkpointed run keeps them for the log of the
    // run that resumes it (they are measured, the state does not depend on them).
    options.sim.frame_energies = !log_path.empty() || !checkpoint_path.empty();
    check_result_format(input, output, !exports.dir.empty());
    OutputPlan plan;
    std::vector<PlannedOutput>& planned = plan.outputs;
    planned.push_back({"-o", output});
    if (!log_path.empty()) planned.push_back({"--log", log_path});
    if (!summary_path.empty()) planned.push_back({"--summary", summary_path});
    if (!checkpoint_path.empty()) {
      const std::string option = saves_to_resumed ? "--resume" : "--checkpoint";
      planned.push_back({option, checkpoint_path});
      planned.push_back({option + "'s log", checkpoint_log_path(checkpoint_path)});
      planned.push_back({option + "'s volume history", checkpoint_history_path(checkpoint_path)});
    }
    if (!fields_prefix.empty()) {
      planned.push_back({"--fields", fields_prefix + "_start.ply"});
      planned.push_back({"--fields", fields_prefix + "_end.ply"});
    }
    if (!exports.gltf.empty()) {
      if (lower_extension(exports.gltf) != "glb")
        throw UsageError("--gltf " + exports.gltf + ": expected a .glb file");
      planned.push_back({"--gltf", exports.gltf});
    }
    if (vm.count("export-every") && exports.dir.empty() && exports.gltf.empty())
      throw UsageError("--export-every has no effect without --export-dir or --gltf");
    if (vm.count("gltf-fps")) {
      // Bounded so that every key time (up to INT_MAX frames) is a finite float32.
      double fps = 0.0;
      if (!parse_decimal(gltf_fps, fps) || !(fps >= 0.001 && fps <= 1000.0))
        throw UsageError("--gltf-fps: expected a frame rate from 0.001 to 1000, got '" +
                         printable(gltf_fps) + "'");
      if (exports.gltf.empty()) throw UsageError("--gltf-fps has no effect without --gltf");
      exports.seconds_per_frame = 1.0 / fps;
    }
    plan.inputs.push_back({"INPUT", input});
    // The checkpoint a run resumes is one of its inputs: only --checkpoint may name it (a resumed
    // run that goes on saving to the same file); a log or summary over it would destroy the only
    // copy of the state. With --checkpoint on the same file, any other output over it is already
    // refused as the same file as --checkpoint.
    if (!resume_path.empty()) {
      std::error_code ec;
      if (checkpoint_path.empty() || !std::filesystem::equivalent(resume_path, checkpoint_path, ec))
        plan.inputs.push_back({"--resume", resume_path});
    }
    if (options.regions == RegionSource::File) plan.inputs.push_back({"--regions", options.region_file});
    if (!options.region_weight_file.empty()) plan.inputs.push_back({"--region-weights", options.region_weight_file});
    if (!exports.dir.empty()) {
      exports.name = std::filesystem::path(output).stem().string();
      exports.ext = lower_extension(output);
      // Every frame name, not only frame 0's: a run that stops early writes its last frame.
      plan.frames = {exports.dir, exports.name, exports.ext, options.sim.frames};
      frames_planned = plan.frames;
    }
    // One decision for every output (output_paths.hpp), then the export folder: created, locked
    // against a second run, refused if another run's frames are there. Nothing before this
    // creates a file or folder.
    check_planned_outputs(plan);
    export_lock = prepare_export_folder(plan.frames);
    checkpoint_locks = lock_run_checkpoints(checkpoint_path, resume_path, saves_to_resumed,
                                            std::move(resumed_lock));
    if (saves_to_resumed && !checkpoint_path.empty() && !quiet)
      std::cerr << "note: " << resumed_saving_note(checkpoint_path, checkpoint_every) << '\n';
  } catch (const po::error& e) {
    return usage_error("run", e.what());
  } catch (const UsageError& e) {
    return usage_error("run", spell_options(e.what(), OptionSpelling::Cli));
  } catch (const InputError& e) {
    std::cerr << "shellcontract run: " << spell_options(e.what(), OptionSpelling::Cli) << '\n';
    return static_cast<int>(ExitCode::BadInput);
  }

  // For a message if memory runs out outside the frames (those end the run with the last good
  // state, see run_contraction): what the tool was doing, and what it had written.
  std::string stage = (repair ? "reading and repairing " : "reading ") + input;
  std::string faces, written;
  try {
    // Names a stage silent for a second (cli/stage_notice.hpp): reading, the run's preparation,
    // the check at the end, the writing. Made first: destroyed (its thread stopped) last.
    StageNotice notice(std::cerr, !quiet);
    InputReport report;
    const auto read_start = std::chrono::steady_clock::now();
    RepairReport repair_report;
    const Mesh mesh = [&] {
      const ProgressStageScope stages = notice.scope();
      return repair ? repair_input_mesh(input, &repair_report) : read_input_mesh(input, &report);
    }();
    notice.end();
    if (repair) {
      report = repair_report.input_report;
      if (!repair_report.already_usable) {
        std::cerr << "repaired " << input << " (refused as read: " << repair_report.input_problem << ")\n";
        for (const std::string& line : repair_report.summary_lines()) std::cerr << "  " << line << '\n';
        refuse_ids_of_the_input(options, input);
      }
    }
    const double read_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();
    for (const std::string& w : report.warnings) std::cerr << "warning: " << w << '\n';
    for (const std::string& n : report.notes) std::cerr << "note: " << n << '\n';
    // Two vertices at one position read back from an STL as one: refused before the run.
    if (lower_extension(output) == "stl")
      require_distinct_stl_positions(
          "-o " + output + (exports.dir.empty() ? "" : " and its frames"), mesh,
          positions_from_mesh(mesh), false);
    // A large mesh takes seconds to read and check (bear subdivided three times, 1.77 M faces:
    // about 3 s), before any frame's progress line.
    if (!quiet && read_seconds >= 1.0)
      std::cerr << "read " << input << ": " << mesh.number_of_vertices() << " vertices, "
                << mesh.number_of_faces() << " faces in " << std::setprecision(3) << read_seconds
                << " s\n";
    // Shared with the frame writer's thread (run_document.hpp).
    const std::shared_ptr<const MeshDocument> document = run_input_document(
        input, output, !exports.gltf.empty(), mesh, repair, report.triangulated_faces);
    ObserverList observers;
    WarningPrinter warnings(notice);
    observers.add(warnings);
    // Regions are auto-selected when asked for, or implied by an anisotropic energy.
    const bool auto_regions =
        options.regions == RegionSource::Auto ||
        (options.regions == RegionSource::None && !options.given.count("regions") &&
         (options.sim.solver.aniso != AnisoKind::None || options.measure_regions));
    // --region-at makes the regions Auto too (resolve_run_options): its caps are at the points.
    ProgressPrinter progress(options.sim.frames,
                             !auto_regions ? std::string()
                             : options.region_points.empty()
                                 ? "spherical regions selected by curvature"
                                 : "regions grown at the --region-at points",
                             notice);
    if (!quiet) observers.add(progress);
    CsvLog csv;
    if (!log_path.empty() || !checkpoint_path.empty()) observers.add(csv);
    if (!resume_path.empty()) {
      check_checkpoint_input(resume, input, mesh);  // InputError: exit 2
      csv.restore(resume.log);
    }
    second_signal::describe(checkpoint_path, output, exports.dir);  // before its handler
    CliCheckpointer checkpointer(checkpoint_path, checkpoint_every,
                                 resume_path.empty() ? nullptr : &resume, input, mesh_hash(mesh),
                                 inputs, options, csv);
    FieldsWriter fields(fields_prefix, colour);
    if (!fields_prefix.empty()) observers.add(fields);
    FrameExporter exporter(exports, mesh, options.sim.frames);
    if (!exports.dir.empty() || !exports.gltf.empty()) observers.add(exporter);
    if (!exports.gltf.empty()) prepare_gltf_animation(exporter, input, document.get(), mesh);
    exporter.set_document(document);
    // The large outputs' sizes, known before the run (output_sizes.hpp): a .glb over the 4 GiB
    // it can hold is refused now, not corrupted after hours; very large outputs are warned of.
    check_run_output_sizes(exporter, exports, mesh, document.get(), input, fields_prefix,
                           options.sim.frames, std::cerr);

    faces = std::to_string(mesh.number_of_faces()) + " faces";
    // run_contraction ends the run itself when memory runs out during the frames.
    stage = "preparing the run or taking its result";
    const RunResult r = run_contraction(mesh, options, &observers, &checkpointer);
    notice.end();  // a run cancelled in its preparation ends no stage itself
    // Nothing is written: the run is not over (its state is in the checkpoint, if any).
    if (r.status == RunStatus::Cancelled && checkpointer.interrupted())
      return report_interrupted(r, checkpointer, output, exports, exporter.frame_stats(),
                                !fields_prefix.empty());
    second_signal::phase.store(second_signal::Outputs);
    // A signal during the last step came too late to stop it (the handler says so itself for
    // one from now on).
    if (checkpoint_signal::received != 0) second_signal::acknowledge_late_stop();

    // A finished result is never thrown away: each output is written on its own, one that
    // fails (a full disk) is reported and the others are still written (output-safety.md).
    OutputStatus outputs;
    // A checkpoint that could not be saved is no failed output (the run went on without it,
    // its result is whole) but the summary says so: a pipeline relying on it must learn.
    if (!checkpointer.failure_report().empty())
      outputs.note("--checkpoint", checkpoint_path, checkpointer.failure_report());
    if (!exporter.export_error().empty()) {
      std::cerr << "warning: the frame export stopped: " << exporter.export_error() << '\n';
      outputs.add("--export-dir", exports.dir,
                  std::to_string(exporter.frame_stats().frames_written) +
                      " frames written, then failed: " + exporter.export_error());
    } else if (!exports.dir.empty()) {
      const auto frames = static_cast<std::size_t>(exporter.frame_stats().frames_written);
      outputs.add("--export-dir", exports.dir, "written (" + counted(frames, "frame", "frames") + ")");
    }
    // Every file written from the document (frames, result) warns alike of the input: once a run.
    std::set<std::string> warned;
    const auto warn_once = [&](const std::string& w) {
      if (warned.insert(w).second) std::cerr << "warning: " << w << '\n';
    };
    for (const std::string& w : exporter.frame_warnings()) warn_once(w);
    const auto attempt = [&](const char* option, const std::string& path, const std::function<void()>& write) {
      stage = "writing " + path;
      notice.begin(stage);
      const auto failed = [&](const std::string& why) {
        std::error_code ec;  // a file there before the run is left as it was
        outputs.add(
            option, path,
            (std::filesystem::exists(path, ec) ? "failed, the old file kept: " : "failed: ") + why);
      };
      try {
        write();
        written = written.empty() ? path : written + " and " + path;
        outputs.add(option, path, "written");
      } catch (const UsageError& e) {
        failed(e.what());
      } catch (const std::invalid_argument& e) {
        // A state the writer refuses (not finite): this output's failure, not std::terminate.
        failed(e.what());
      }
      notice.end();
    };
    if (!exports.gltf.empty()) attempt("--gltf", exports.gltf, [&] { exporter.write_gltf(); });
    attempt("-o", output, [&] {
      if (document && document->format() == lower_extension(output)) {
        std::vector<std::string> doc_warnings;  // a material library that does not exist
        write_mesh_document_atomic(output, *document, input_positions(mesh, r.positions), &doc_warnings);
        for (const std::string& w : doc_warnings) warn_once(w);
      } else {
        write_mesh_atomic(output, mesh, r.positions);
      }
    });
    if (!fields_prefix.empty()) attempt("--fields", fields_prefix + "_*.ply", [&] { fields.write(); });
    if (!log_path.empty()) attempt("--log", log_path, [&] { write_text_atomic(log_path, csv.text()); });
    if (!summary_path.empty()) {
      // The summary is written last: an output that failed before it makes the process exit 1
      // (or the run's own failure code), and the summary says so (its own failure is reported on
      // stderr only).
      JsonObject summary = summary_json(
          input, output, report, options, r,
          outputs.failed() ? std::optional<int>(output_failure_exit_code(r)) : std::nullopt);
      JsonObject setup;
      setup.add("read_and_check_seconds", read_seconds)
          .add("read_seconds", report.read_seconds)
          .add("check_seconds", report.check_seconds)
          .add("regions_seconds", r.regions_seconds)
          .add("prepare_seconds", r.prepare_seconds);
      summary.add("setup", setup).add("peak_memory_mb", peak_memory_mb());
      if (repair) {
        JsonObject rep;
        rep.add("already_usable", repair_report.already_usable)
            .add("input_problem", repair_report.input_problem)
            .add("changes", repair_report.summary_lines());
        summary.add("repair", rep);
      }
      if (!exports.dir.empty() || !exports.gltf.empty())
        summary.add("export", export_json(exporter));
      summary.add("outputs", outputs.json());
      attempt("--summary", summary_path, [&] { write_text_atomic(summary_path, summary.str() + "\n"); });
    }
    if (outputs.failed()) {
      std::cerr << "shellcontract run: not every output could be written (the run itself ended: "
                << status_name(r.status) << ", frame " << r.frames_run << ")\n"
                << outputs.text();
      // The run's own failure too (out of memory, a blow-up, validation): the list names only
      // its status, and the exit code is the failure's (output_failure_exit_code).
      const std::string why = run_failure_text(r);
      if (!why.empty()) std::cerr << "shellcontract run: " << why << '\n';
      return output_failure_exit_code(r);
    }
    switch (r.status) {
      case RunStatus::NewIntersections:
        std::cerr << "shellcontract run: validation found new self-intersections: " << r.message
                  << '\n';
        break;
      case RunStatus::SimulationFailed:
        std::cerr << "shellcontract run: simulation failed: " << r.message
                  << "\nthe last good state (frame " << r.frames_run << ") was written to "
                  << output << '\n';
        break;
      case RunStatus::TargetNotReached:
        std::cerr << "warning: " << r.message << "\nthe result (frame " << r.frames_run << ", V/V0 "
                  << r.final_volume_ratio << ") was written to " << output << '\n';
        break;
      default:
        if (!quiet)
          std::cerr << "wrote " << output << ": " << r.frames_run
                    << " frames, V/V0 = " << r.final_volume_ratio << '\n';
    }
    return r.exit_code();
  } catch (const InputError& e) {
    std::cerr << "shellcontract run: " << spell_options(e.what(), OptionSpelling::Cli) << '\n';
    return static_cast<int>(ExitCode::BadInput);
  } catch (const UsageError& e) {
    std::cerr << "shellcontract run: " << spell_options(e.what(), OptionSpelling::Cli) << '\n';
    return static_cast<int>(ExitCode::BadUsage);
  } catch (const OutOfMemoryError& e) {
    // An input larger than the memory there is: its reader's message names it.
    std::cerr << "shellcontract run: " << e.what() << "; "
              << what_was_left(written, count_frame_files(frames_planned), exports.dir) << '\n';
    return static_cast<int>(ExitCode::SimulationFailed);
  } catch (const std::bad_alloc&) {
    // The frame files already written stay (the writer finished them as it was destroyed).
    std::cerr << "shellcontract run: out of memory while " << stage
              << (faces.empty() ? "" : " (" + faces + ")") << "; "
              << what_was_left(written, count_frame_files(frames_planned), exports.dir) << '\n';
    return static_cast<int>(ExitCode::SimulationFailed);
  } catch (const std::runtime_error& e) {
    // A resource the system refused besides memory (TBB's threads: "pthread_create has failed").
    std::cerr << "shellcontract run: " << e.what() << " (while " << stage << "); "
              << what_was_left(written, count_frame_files(frames_planned), exports.dir) << '\n';
    return static_cast<int>(ExitCode::SimulationFailed);
  }
}

}  // namespace shellcontract::cli
