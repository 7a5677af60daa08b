// run's preparation (run_steps.hpp, prepare_run): the command line read into a RunRequest and
// checked, every file the run writes or reads planned, and the outputs claimed. The checks come
// in the order the steps below take them: with two mistakes on one command line, the first
// step's is the one reported.
#include <boost/program_options.hpp>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "command_line.hpp"
#include "core/decimal_text.hpp"
#include "mesh/file_safety.hpp"
#include "output_paths.hpp"
#include "run_checkpoint.hpp"
#include "run_command_line.hpp"
#include "run_observers.hpp"
#include "run_steps.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"
#include "sim/checkpoint.hpp"

namespace po = boost::program_options;

namespace shellcontract::cli {
namespace {

/// INPUT (a resumed run's own when not given), -o, and the checkpoint --resume continues, read
/// under its lock: a run that holds it may be saving there (UsageError: exit 1).
/// @throws InputError (exit 2) for a checkpoint that cannot be read
void read_input_and_resume(RunRequest& q, RunClaims& claims) {
  if (!q.resume_path.empty()) {
    claims.resumed = lock_resumed_checkpoint(q.resume_path, q.checkpoint_path, OptionSpelling::Cli);
    q.resume = read_checkpoint(q.resume_path);
  }
  if (q.input.empty() && !q.resume_path.empty())
    q.input = checkpoint_input(q.resume, q.resume_path);
  if (q.input.empty()) throw UsageError("missing INPUT mesh");
  if (q.output.empty()) throw UsageError("missing -o OUTPUT");
}

/// The option table's values given (a resumed run's own where it resumes), resolved and checked
/// by the library; the face list or weights file as the run starts, recorded in its checkpoints
/// (a resumed run's must be the checkpoint's: InputError, exit 2).
void read_run_options(const po::variables_map& vm, RunRequest& q) {
  for (const OptionSpec& o : run_option_table()) {
    if (o.is_switch) {
      if (q.switches[o.name]) o.set(q.options, "on");
    } else if (o.repeatable) {
      std::string joined;
      for (const std::string& v : q.lists[o.name]) joined += (joined.empty() ? "" : ";") + v;
      if (vm.count(o.name)) o.set(q.options, joined);
    } else if (vm.count(o.name) && !vm[o.name].defaulted()) {
      o.set(q.options, q.values[o.name]);
    }
  }
  if (!q.resume_path.empty()) q.options = options_for_resume(q.resume, q.options);
  resolve_run_options(q.options);
  if (!q.checkpoint_path.empty() || !q.resume_path.empty()) q.inputs = run_inputs(q.options);
  if (!q.resume_path.empty()) check_checkpoint_files(q.resume, q.inputs);
}

/// The CLI's own options of the run's files: the frame counts, what --resume excludes, the
/// fields' colour and --export-failure.
void read_file_options(const po::variables_map& vm, RunRequest& q) {
  if (vm.count("checkpoint-every"))
    q.checkpoint_every = frame_count("--checkpoint-every", q.checkpoint_every_text);
  if (vm.count("export-every"))
    q.exports.every = frame_count("--export-every", q.export_every_text);
  if (vm.count("checkpoint-every") && (q.checkpoint_path.empty() && q.resume_path.empty()))
    throw UsageError("--checkpoint-every: expected an integer >= 1, with --checkpoint or --resume");
  if (!q.resume_path.empty() &&
      (!q.fields_prefix.empty() || !q.exports.dir.empty() || !q.exports.gltf.empty()))
    throw UsageError(
        "--fields, --export-dir and --gltf cannot be combined with --resume: the frames before "
        "the checkpoint are not in it");
  q.colour = parse_field_colour(q.fields_colour);
  if (q.export_failure != "warn" && q.export_failure != "stop")
    throw UsageError("--export-failure: '" + q.export_failure + "' is not warn or stop");
  q.exports.stop_run_on_failure = q.export_failure == "stop";
  // Options that shape an output not asked for: warnings, as for the run's own options
  // (ineffective_options), not errors, so that a script can keep them while it toggles the output.
  const auto given = [&](const char* name) { return vm.count(name) && !vm[name].defaulted(); };
  if (given("fields-colour") && q.fields_prefix.empty())
    std::cerr << "warning: --fields-colour has no effect: it colours the files of --fields\n";
  if (given("export-failure") && q.exports.dir.empty() && q.exports.gltf.empty())
    std::cerr << "warning: --export-failure has no effect: it is what a failed frame file of "
                 "--export-dir or --gltf does\n";
}

/// Where and how often the run saves its state, and whether its frames measure their energies.
void plan_checkpoints(const po::variables_map& vm, RunRequest& q) {
  // A resumed run saves as the interrupted one did: into the file it resumed from (unless
  // --checkpoint names another) and as often (unless --checkpoint-every says otherwise).
  q.saves_to_resumed = !q.resume_path.empty() && q.checkpoint_path.empty();
  if (q.saves_to_resumed)
    q.checkpoint_path = resumed_run_checkpoint(q.resume_path, {{"INPUT", q.input}});
  if (!q.resume_path.empty() && !vm.count("checkpoint-every"))
    q.checkpoint_every = q.resume.save_every;
  // Only the CSV log reports the energies; a checkpointed run keeps them for the log of the
  // run that resumes it (they are measured, the state does not depend on them).
  q.options.sim.frame_energies = !q.log_path.empty() || !q.checkpoint_path.empty();
}

/// Every file the run writes (its frame files aside), after -o's format is checked.
void list_outputs(const RunRequest& q, OutputPlan& plan) {
  check_result_format(q.input, q.output, !q.exports.dir.empty(), true);
  std::vector<PlannedOutput>& planned = plan.outputs;
  planned.push_back({"-o", q.output});
  if (!q.log_path.empty()) planned.push_back({"--log", q.log_path});
  if (!q.summary_path.empty()) planned.push_back({"--summary", q.summary_path});
  if (!q.checkpoint_path.empty()) {
    const std::string option = q.saves_to_resumed ? "--resume" : "--checkpoint";
    planned.push_back({option, q.checkpoint_path});
    planned.push_back({option + "'s log", checkpoint_log_path(q.checkpoint_path)});
    planned.push_back({option + "'s volume history", checkpoint_history_path(q.checkpoint_path)});
  }
  if (!q.fields_prefix.empty()) {
    planned.push_back({"--fields", q.fields_prefix + "_start.ply"});
    planned.push_back({"--fields", q.fields_prefix + "_end.ply"});
  }
  if (!q.exports.gltf.empty()) {
    if (lower_extension(q.exports.gltf) != "glb")
      throw UsageError("--gltf " + q.exports.gltf + ": expected a .glb file");
    planned.push_back({"--gltf", q.exports.gltf});
  }
}

/// --export-every and --gltf-fps, which need an export to act on.
void read_animation_options(const po::variables_map& vm, RunRequest& q) {
  ExportRequest& exports = q.exports;
  if (vm.count("export-every") && exports.dir.empty() && exports.gltf.empty())
    throw UsageError("--export-every has no effect without --export-dir or --gltf");
  if (vm.count("gltf-fps")) {
    // Bounded so that every key time (up to INT_MAX frames) is a finite float32.
    double fps = 0.0;
    if (!parse_decimal(q.gltf_fps, fps) || !(fps >= 0.001 && fps <= 1000.0))
      throw UsageError("--gltf-fps: expected a frame rate from 0.001 to 1000, got '" +
                       printable(q.gltf_fps) + "'");
    if (exports.gltf.empty()) throw UsageError("--gltf-fps has no effect without --gltf");
    exports.seconds_per_frame = 1.0 / fps;
  }
}

/// The files the run reads (no output may be one of them) and the frame files of --export-dir.
void list_inputs_and_frames(RunRequest& q, OutputPlan& plan, RunClaims& claims) {
  plan.inputs.push_back({"INPUT", q.input});
  // The checkpoint a run resumes is one of its inputs: only --checkpoint may name it (a resumed
  // run that goes on saving to the same file); a log or summary over it would destroy the only
  // copy of the state. With --checkpoint on the same file, any other output over it is already
  // refused as the same file as --checkpoint.
  if (!q.resume_path.empty()) {
    std::error_code ec;
    if (q.checkpoint_path.empty() ||
        !std::filesystem::equivalent(q.resume_path, q.checkpoint_path, ec))
      plan.inputs.push_back({"--resume", q.resume_path});
  }
  const RunOptions& options = q.options;
  if (options.regions == RegionSource::File)
    plan.inputs.push_back({"--regions", options.region_file});
  if (!options.region_weight_file.empty())
    plan.inputs.push_back({"--region-weights", options.region_weight_file});
  ExportRequest& exports = q.exports;
  if (!exports.dir.empty()) {
    exports.name = std::filesystem::path(q.output).stem().string();
    exports.ext = lower_extension(q.output);
    // Every frame name, not only frame 0's: a run that stops early writes its last frame.
    plan.frames = {exports.dir, exports.name, exports.ext, options.sim.frames};
    claims.frames = plan.frames;
  }
}

/// One decision for every output (output_paths.hpp), then the export folder: created, locked
/// against a second run, refused if another run's frames are there; then the checkpoints' locks.
void claim_outputs(const RunRequest& q, const OutputPlan& plan, RunClaims& claims) {
  check_planned_outputs(plan);
  claims.export_lock = prepare_export_folder(plan.frames);
  claims.checkpoint_locks = lock_run_checkpoints(q.checkpoint_path, q.resume_path,
                                                 q.saves_to_resumed, std::move(claims.resumed));
  if (q.saves_to_resumed && !q.checkpoint_path.empty() && !q.quiet)
    std::cerr << "note: " << resumed_saving_note(q.checkpoint_path, q.checkpoint_every) << '\n';
}

}  // namespace

std::optional<int> prepare_run(int argc, char** argv, const po::options_description& desc,
                               RunRequest& request, RunClaims& claims) {
  try {
    const po::variables_map vm = parse_command_line(argc, argv, desc, request.input);
    if (vm.count("help")) {
      std::cout << desc << RUN_EXIT_CODES;
      return 0;
    }
    read_input_and_resume(request, claims);
    read_run_options(vm, request);
    read_file_options(vm, request);
    plan_checkpoints(vm, request);
    OutputPlan plan;
    list_outputs(request, plan);
    read_animation_options(vm, request);
    list_inputs_and_frames(request, plan, claims);
    claim_outputs(request, plan, claims);
  } catch (const po::error& e) {
    return usage_error("run", e.what());
  } catch (const UsageError& e) {
    return usage_error("run", spell_options(e.what(), OptionSpelling::Cli));
  } catch (const InputError& e) {
    std::cerr << "shellcontract run: " << spell_options(e.what(), OptionSpelling::Cli) << '\n';
    return static_cast<int>(ExitCode::BadInput);
  }
  return std::nullopt;
}

}  // namespace shellcontract::cli
