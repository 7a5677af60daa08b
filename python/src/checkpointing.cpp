#include "checkpointing.hpp"

#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "arrays.hpp"
#include "option_values.hpp"
#include "shellcontract/checkpoint_lock.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/output_files.hpp"

namespace shellcontract::python {

namespace {

/// checkpoint_every as an int >= 1 (None: not given), read as contract()'s integer options are
/// (whole_number: 2, numpy's int, a whole float 2.0; the package reads a str, "2", as the CLI's
/// --checkpoint-every text first), refused with the option's words otherwise: pybind11's cast
/// said only "Unable to cast Python instance to C++ type", took True for 1 and 2**40 failed the
/// same way.
int every_argument(const py::handle& value) {
  if (value.is_none()) return 0;
  const std::string expected =
      "checkpoint_every: expected an integer >= 1, with checkpoint=FILE or resume=FILE, got " +
      std::string(py::str(py::repr(value)));
  const py::object v = python_value(value);
  if (is_bool(value) || py::isinstance<py::bool_>(v) ||
      !(PyFloat_Check(v.ptr()) || PyIndex_Check(v.ptr())))
    throw py::type_error(expected);
  const std::optional<py::int_> whole = whole_number(value);
  if (!whole) throw py::value_error(expected);  // 2.5, NaN
  int overflow = 0;
  const long long n = PyLong_AsLongLongAndOverflow(whole->ptr(), &overflow);
  if (overflow != 0 || n < 1 || n > std::numeric_limits<int>::max())
    throw py::value_error(expected);
  return static_cast<int>(n);
}

/// The files a save to `path` writes, named after `option`: the checkpoint, and its log and
/// volume history beside it (CheckpointLogFile), as the CLI checks them.
std::vector<NamedFile> saved_files(const std::string& option, const std::string& path) {
  return {{option, path},
          {option + "'s log", checkpoint_log_path(path)},
          {option + "'s volume history", checkpoint_history_path(path)}};
}

void warn(const std::string& text) {
  // stacklevel 2: the caller of shellcontract.contract (this function has no Python frame).
  py::module_::import("warnings")
      .attr("warn")(text, py::module_::import("builtins").attr("UserWarning"), 2);
}

}  // namespace

CheckpointArguments take_checkpoint_arguments(const py::kwargs& kwargs, py::kwargs& options) {
  CheckpointArguments a;
  for (const auto& [key, value] : kwargs) {
    const std::string name = key.cast<std::string>();
    // None: not given, as for regions.
    if (name == "checkpoint") a.checkpoint = value.is_none() ? "" : path_argument(value, "checkpoint");
    else if (name == "resume") a.resume = value.is_none() ? "" : path_argument(value, "resume");
    else if (name == "checkpoint_every") a.every = every_argument(value);
    else if (name == "_regions_from_arrays") a.regions_from_arrays = PyObject_IsTrue(value.ptr()) == 1;
    else options[key] = value;
  }
  if (a.every < 0 || (a.every > 0 && a.checkpoint.empty() && a.resume.empty()))
    throw py::value_error(
        "checkpoint_every: expected an integer >= 1, with checkpoint=FILE or resume=FILE");
  return a;
}

PreparedCheckpoint prepare_checkpoint(const CheckpointArguments& args, RunOptions& options) {
  PreparedCheckpoint p;
  // The checkpoint resumed is read under its lock: a run that holds it may be saving there, and
  // it is refused as held (BlockingIOError), not as a checkpoint whose files beside are missing.
  CheckpointLocks resumed_lock =
      lock_resumed_checkpoint(args.resume, args.checkpoint, OptionSpelling::Python);
  if (!args.resume.empty()) {
    p.resume = load_checkpoint(args.resume);
    options = options_for_resume(*p.resume, options);
    resolve_run_options(options);
    options.sim.frame_energies = true;  // the log always carries them (contract())
  }
  if (args.checkpoint.empty() && args.resume.empty()) return p;
  p.inputs = run_inputs(options);
  for (RunInput& in : p.inputs)
    if (in.option == "regions" && args.regions_from_arrays) in.arrays = true;
  if (p.resume) check_checkpoint_files(*p.resume, p.inputs);
  // The files the run reads are run_inputs' (one list, which tests/sim holds to the option
  // table); regions or weights given as arrays are no file of the caller's.
  std::vector<NamedFile> read;
  for (const RunInput& in : p.inputs)
    if (!in.arrays) read.push_back({in.option, in.file});
  // A resumed run saves as the interrupted one did (the CLI's `run --resume`): into the file it
  // resumed from unless checkpoint= names another, and as often unless checkpoint_every= is
  // given. Before, it saved nothing: a run interrupted again lost every frame since the resume.
  const bool saves_to_resumed = args.checkpoint.empty() && p.resume;
  p.save_path = args.checkpoint;
  p.save_every = args.every > 0 || !p.resume ? args.every : checkpoint_save_every(*p.resume);
  if (saves_to_resumed) {
    try {
      check_output_files(saved_files("resume", args.resume), read);
      p.save_path = args.resume;
    } catch (const UsageError& e) {
      // A read-only copy resumes, as before, saving nothing; the caller learns why.
      warn(std::string("this run saves no checkpoint (give checkpoint=FILE): ") + e.what());
    }
  } else if (!args.checkpoint.empty()) {
    check_output_files(saved_files("checkpoint", args.checkpoint), read);
  }
  p.locks = lock_run_checkpoints(p.save_path, args.resume, saves_to_resumed && !p.save_path.empty(),
                                 OptionSpelling::Python, std::move(resumed_lock));
  for (const std::string& w : p.locks.warnings) warn(w);
  return p;
}

PythonCheckpointer::PythonCheckpointer(const PreparedCheckpoint& prepared, std::uint64_t mesh_hash,
                                       const RunOptions& options, const std::string& log,
                                       std::function<bool()> cancelled)
    : path_(prepared.save_path),
      every_(prepared.save_every),
      resume_(prepared.resume),
      hash_(mesh_hash),
      inputs_(prepared.inputs),
      options_(options),
      log_file_(prepared.save_path, log, prepared.resume.get()),
      cancelled_(std::move(cancelled)) {}

bool PythonCheckpointer::save_due(int frame) {
  if (path_.empty()) return false;
  frame_ = frame;
  return (every_ > 0 && frame % every_ == 0) || cancelled_();
}

void PythonCheckpointer::save(const SavedRun& run) {
  try {
    // The log and history beside the checkpoint, appended to: each save writes what is new.
    write_checkpoint(path_, run, options_, CheckpointInfo{ARRAYS_INPUT, hash_, {}, inputs_, every_},
                     log_file_);
    saved_frame_ = frame_;
  } catch (const UsageError& e) {
    // Raised, it threw away the whole run at the first full disk (ValueError, no result); the
    // CLI warns and goes on, and so does this (the GIL is not held here: warned afterwards).
    if (failures_ == 0) {
      first_failure_ = e.what();
      first_failed_frame_ = frame_;
    }
    ++failures_;
  }
}

std::string PythonCheckpointer::failure_warning() const {
  if (failures_ == 0) return "";
  return "checkpoint not written " + std::to_string(failures_) +
         (failures_ == 1 ? " time" : " times") + " (first at frame " +
         std::to_string(first_failed_frame_) + ": " + first_failure_ + "); " +
         (saved_frame_ >= 0
              ? "the checkpoint of frame " + std::to_string(saved_frame_) + " is still in " + path_
              : "no checkpoint was saved");
}

}  // namespace shellcontract::python
