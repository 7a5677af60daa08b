// shellcontract.contract: the Python mirror of cli/run.cpp. Options go through the option table
// as text (so the same digits give the same double, hence the same run as the CLI); the run goes
// through run_contraction with one observer that keeps the log, calls the Python callback and
// polls for Ctrl-C.
#include "contract.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <Python.h>

#include <array>
#include <cmath>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <cstdint>
#include <cstdlib>
#include <iomanip>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "arrays.hpp"
#include "checkpointing.hpp"
#include "shellcontract/checkpoint.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/report.hpp"
#include "shellcontract/run.hpp"

namespace shellcontract::python {
namespace {

// ------------------------------------------------------------ runs and the interpreter's exit
// A run executes with the GIL released. Taking the GIL back while the interpreter finalizes ends
// the thread where it stands (pthread_exit), unwinding through C++ frames that cannot be
// unwound: an abort. So at exit (stop_runs_at_exit, an atexit hook, before finalization) every
// run is cancelled and waited for; a run that outlasts the wait never takes the GIL again.

std::atomic<bool> exiting{false};
std::mutex runs_mutex;
std::condition_variable runs_changed;
int active_runs = 0;

/// How long the exit waits for running runs to see the cancel (they check after every step).
constexpr std::chrono::seconds EXIT_WAIT{60};

bool interpreter_finalizing() {
#if PY_VERSION_HEX >= 0x030D0000
  return Py_IsFinalizing() != 0;
#else
  return _Py_IsFinalizing() != 0;
#endif
}

bool interpreter_exiting() { return exiting.load(std::memory_order_acquire) || interpreter_finalizing(); }

/// Counts a run from before the GIL is released until after it is taken back.
struct ActiveRun {
  ActiveRun() {
    std::lock_guard<std::mutex> lock(runs_mutex);
    ++active_runs;
  }
  ~ActiveRun() {
    std::lock_guard<std::mutex> lock(runs_mutex);
    --active_runs;
    runs_changed.notify_all();
  }
  ActiveRun(const ActiveRun&) = delete;
  ActiveRun& operator=(const ActiveRun&) = delete;
};

/// A file name as Python takes one: a str or an os.PathLike (not bytes: a value of an option).
bool is_path(const py::handle& value) {
  return py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__");
}

std::string valid_names() {
  std::string s;
  for (const OptionSpec& o : run_option_table()) s += (s.empty() ? "" : ", ") + python_option_name(o.name);
  return s;
}

/// The text the CLI would receive for a Python value: bool -> on/off, float -> shortest_text (the
/// shortest text that reads back as the same double), int and str as they are, an os.PathLike as
/// its path, a sequence -> "a,b,c" (--fiber X,Y,Z).
std::string option_text(const std::string& name, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "on" : "off";
  // A str may name a file (regions, region_weights): its bytes are the file name's, as for a path.
  if (py::isinstance<py::str>(value)) return file_name_bytes(value);
  if (py::hasattr(value, "__fspath__")) return path_argument(value, "option " + name);  // a file name
  // A numpy array or scalar goes by its Python value (an array also passes PyIndex_Check).
  if (py::hasattr(value, "tolist") && !py::isinstance<py::float_>(value))
    return option_text(name, value.attr("tolist")());
  // The tool's own text (shortest_text: 2e+06, not Python's 2000000.0), so that a refusal quotes
  // the value as the CLI and the summary write it.
  if (py::isinstance<py::float_>(value)) return shortest_text(value.cast<double>());
  if (PyIndex_Check(value.ptr())) return py::str(py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr())));
  // Keyframes as (frame, value) pairs (target_volume=[(0, 1), (60, 0.5)]): the CLI's
  // "0:1, 60:0.5".
  if ((py::isinstance<py::tuple>(value) || py::isinstance<py::list>(value)) && py::len(value) > 0 &&
      (py::isinstance<py::tuple>(value[py::int_(0)]) || py::isinstance<py::list>(value[py::int_(0)]))) {
    std::string s;
    for (const py::handle& key : value) {
      if (!(py::isinstance<py::tuple>(key) || py::isinstance<py::list>(key)) || py::len(key) != 2)
        throw py::value_error("option " + name + ": keyframes are (frame, value) pairs, got " +
                              std::string(py::str(py::repr(key))));
      // A whole float frame (a float array's 15.0) is the integer frame it stands for.
      py::object frame = key[py::int_(0)];
      if (py::isinstance<py::float_>(frame) && std::floor(frame.cast<double>()) == frame.cast<double>() &&
          std::abs(frame.cast<double>()) < 1e15)
        frame = py::int_(static_cast<long long>(frame.cast<double>()));
      s += (s.empty() ? "" : ", ") + option_text(name, frame) + ":" + option_text(name, key[py::int_(1)]);
    }
    return s;
  }
  if (py::isinstance<py::tuple>(value) || py::isinstance<py::list>(value)) {
    std::string s;
    for (const py::handle& item : value) s += (s.empty() ? "" : ",") + option_text(name, item);
    return s;
  }
  throw py::type_error("option " + name + ": expected a number, a string or a bool, got " +
                       std::string(py::str(value.get_type())));
}

}  // namespace

std::string region_at_text(const py::handle& value) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();  // the CLI's text, parsed by the table
  const auto type_name = [&] { return std::string(py::str(value.get_type().attr("__name__"))); };
  const std::string forms = "region_at: expected a point (x, y, z), a list of points or the text 'X,Y,Z'";
  // Sequences and arrays only: numpy would read None as NaN, bytes or a dict as one object.
  if (value.is_none() || py::isinstance<py::bytes>(value) || py::isinstance<py::dict>(value) ||
      !(PySequence_Check(value.ptr()) || py::hasattr(value, "__array__")))
    throw py::type_error(forms + ", got " + type_name());
  py::array_t<double, py::array::c_style> points;
  try {
    points = py::module_::import("numpy").attr("ascontiguousarray")(value, "float64")
                 .cast<py::array_t<double, py::array::c_style>>();
  } catch (const py::error_already_set&) {  // ragged, or an item that is not a number
    throw py::value_error(forms + ", got " + std::string(py::repr(value)));
  }
  if (points.size() == 0) throw py::value_error("region_at: expected at least one point (x, y, z), got none");
  const bool one = points.ndim() == 1;  // region_at=(x, y, z)
  if (!((one && points.shape(0) == 3) || (points.ndim() == 2 && points.shape(1) == 3)))
    throw py::value_error(forms + ", got " + std::string(py::repr(value)));
  const py::ssize_t n = one ? 1 : points.shape(0);
  const double* xyz = points.data();
  std::string text;
  for (py::ssize_t i = 0; i < n; ++i, xyz += 3) {
    const auto digits = [](double c) { return py::repr(py::float_(c)).cast<std::string>(); };
    // By Python's index here, before the table's message (which quotes the text only).
    if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
      throw py::value_error("region_at" + (one ? std::string() : "[" + std::to_string(i) + "]") + " = (" +
                            digits(xyz[0]) + ", " + digits(xyz[1]) + ", " + digits(xyz[2]) +
                            ") is not a point of three finite numbers");
    text += (text.empty() ? "" : ";") + digits(xyz[0]) + "," + digits(xyz[1]) + "," + digits(xyz[2]);
  }
  return text;
}

std::vector<Vec3> region_at_points(const py::handle& value) {
  RunOptions options;
  find_run_option("region_at")->set(options, region_at_text(value));
  return options.region_points;
}

namespace {

/// A list, a tuple or an array that is not 0-dimensional (a numpy scalar is one value).
bool is_sequence(const py::handle& value) {
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) return true;
  return py::hasattr(value, "tolist") && py::hasattr(value, "ndim") && value.attr("ndim").cast<int>() > 0;
}

/// The options whose text may be a list, by the table's own value names: keyframes (pressure,
/// target_volume: "P|KEYS") and a direction (fiber: "centre|X,Y,Z"); region_at and
/// region_weights are read before the table.
bool takes_sequence(const OptionSpec& spec) {
  return spec.value_name.find("KEYS") != std::string::npos || spec.value_name.find(',') != std::string::npos;
}

/// The options by their Python names: an option is also taken as the CLI spells it ("k-b" for
/// k_b, as regions() takes them), once. Given both ways, the later spelling had silently won, and
/// resolve_options left a dashed name out of the sweep's command line while recording its value.
/// Unknown names are kept as given, for options_from_kwargs's message.
py::dict canonical_kwargs(const py::kwargs& kwargs) {
  py::dict out;
  for (const auto& [key, value] : kwargs) {
    const std::string given = key.cast<std::string>();
    const OptionSpec* spec = find_run_option(given);
    const std::string name = spec ? python_option_name(spec->name) : given;
    if (out.contains(name))
      throw py::type_error("contract() got the option '" + name + "' twice (as '-' and as '_')");
    out[py::str(name)] = value;
  }
  return out;
}

/// also_valid: the caller's own arguments, listed after the table's in the unknown-option error.
RunOptions options_from_kwargs(const py::dict& kwargs, const std::string& also_valid = "") {
  RunOptions options;
  for (const auto& [key, value] : kwargs) {
    const std::string name = key.cast<std::string>();
    // region_weights=W: the weights themselves (a file name goes through the table as text).
    if (find_run_option(name) && find_run_option(name)->name == "region-weights" && !is_path(value)) {
      options.vertex_weights = py::cast<std::vector<double>>(
          py::module_::import("numpy").attr("asarray")(value, "float64").attr("ravel")().attr("tolist")());
      // No weights would read as no option at all: the run went on without regions, silently.
      if (options.vertex_weights.empty())
        throw py::value_error(name + ": no weights; one weight in [0, 1] per vertex");
      options.given.insert("region_weights");
      continue;
    }
    const OptionSpec* spec = find_run_option(name);
    if (spec && spec->name == "region-at") {
      spec->set(options, region_at_text(value));  // UsageError (ValueError) for bad text
      continue;
    }
    if (!spec)
      throw py::type_error("contract() got an unknown option '" + name + "'; valid options: " + valid_names() +
                           also_valid);
    // A list for an option of one value would reach the table as its items' text: frames=[2]
    // ran 2 frames, and a sweep file's "frames": [5] read as 5, where a list of values was meant.
    if (is_sequence(value) && !takes_sequence(*spec))
      throw py::type_error(name + ": got " + std::string(py::str(py::repr(value))) +
                           "; it takes one value, not a list");
    try {
      spec->set(options, option_text(name, value));  // UsageError (ValueError) for a bad value
    } catch (const UsageError& e) {
      // A bool reaches the table as on/off, which only the on/off options take: a number's
      // refusal would otherwise read "frames: 'on' is not an integer".
      if (py::isinstance<py::bool_>(value))
        throw py::type_error(name + ": got the bool " + std::string(value.cast<bool>() ? "True" : "False") +
                             ", which only on/off options take (" +
                             spell_options(e.what(), OptionSpelling::Python) + ")");
      throw;
    }
  }
  resolve_run_options(options);
  // The log always carries the energies (the CLI computes them when --log is given).
  options.sim.frame_energies = true;
  return options;
}

py::object column_value(std::size_t c, double v) {
  if (LOG_INTEGER[c]) return py::int_(static_cast<std::int64_t>(v));
  return py::float_(v);
}

/// Keeps the log, calls the callback, polls for signals. Python objects are touched only with
/// the GIL held: the run itself executes with the GIL released.
class PythonObserver final : public RunObserver {
 public:
  /// @param mesh the run's input mesh: the callback gets the input's vertices (a mesh welded
  ///             along its seams gives every copy its vertex's position)
  PythonObserver(py::object callback, const Mesh& mesh)
      : callback_(std::move(callback)), has_callback_(!callback_.is_none()), mesh_(mesh) {}

  ~PythonObserver() override {
    // A pending error is only dropped when contract() itself throws before taking it.
    if (error_type_) {
      Py_XDECREF(error_type_);
      Py_XDECREF(error_value_);
      Py_XDECREF(error_trace_);
    }
  }

  void frame(const FrameView& view, const FrameMetrics& m) override {
    rows_.push_back(log_row(m));
    csv_ += log_csv_line(rows_.back());
    if (!has_callback_ || stop_) return;
    if (interpreter_exiting()) {  // no GIL for a callback while the interpreter exits
      stop_ = true;
      return;
    }
    py::gil_scoped_acquire gil;
    try {
      py::dict metrics;
      for (std::size_t c = 0; c < LOG_COLUMN_COUNT; ++c) metrics[LOG_COLUMNS[c]] = column_value(c, rows_.back()[c]);
      const py::object answer = callback_(m.frame, positions_to_numpy(input_positions(mesh_, view.positions())), metrics);
      // A false value stops: False, numpy's False_ (a comparison's result), 0. None, what a
      // callback without a return gives, goes on. A value with no truth value (a numpy array of
      // several elements) raises, as `if answer:` would.
      if (!answer.is_none()) {
        const int truth = PyObject_IsTrue(answer.ptr());
        if (truth < 0) throw py::error_already_set();
        if (truth == 0) stop_ = true;
      }
    } catch (py::error_already_set& e) {
      e.restore();  // back into the interpreter's error indicator, then kept for after the run
      keep_error();
    }
  }

  /// The rows so far as the CLI's --log CSV text (a checkpoint's log: the CLI and Python resume
  /// each other's checkpoints), kept as the rows come, so that a save reads it without
  /// formatting every row so far again.
  const std::string& csv_text() const { return csv_; }

  /// A resumed run's rows so far, from its checkpoint's CSV text (whatever locale the host
  /// program set: std::strtod read "0.99" as 0 under a decimal comma).
  void restore_csv(const std::string& text) {
    const std::vector<LogRow> rows = log_csv_rows(text, "the checkpoint's log");
    rows_.insert(rows_.end(), rows.begin(), rows.end());
    for (const LogRow& row : rows) csv_ += log_csv_line(row);
  }

  bool cancelled() override {
    if (stop_) return true;
    if (interpreter_exiting()) return stop_ = true;  // checked without the GIL
    // Taking the GIL can wait for another Python thread's switch interval (5 ms): poll a few
    // times a second, not after every step.
    const auto now = std::chrono::steady_clock::now();
    if (now - last_poll_ < SIGNAL_POLL_INTERVAL) return false;
    last_poll_ = now;
    py::gil_scoped_acquire gil;
    // Runs the Python signal handlers (main thread only): Ctrl-C raises KeyboardInterrupt here.
    if (PyErr_CheckSignals() != 0) keep_error();
    return stop_;
  }

  /// Raises the error the callback or a signal handler raised, if any (GIL held).
  void raise_if_error() {
    if (!error_type_) return;
    PyErr_Restore(error_type_, error_value_, error_trace_);
    error_type_ = error_value_ = error_trace_ = nullptr;
    throw py::error_already_set();
  }

  py::dict log() const {
    py::dict out;
    for (std::size_t c = 0; c < LOG_COLUMNS.size(); ++c) {
      if (LOG_INTEGER[c]) {
        py::array_t<std::int64_t> a(static_cast<py::ssize_t>(rows_.size()));
        for (std::size_t i = 0; i < rows_.size(); ++i) a.mutable_at(i) = static_cast<std::int64_t>(rows_[i][c]);
        out[LOG_COLUMNS[c]] = a;
      } else {
        py::array_t<double> a(static_cast<py::ssize_t>(rows_.size()));
        for (std::size_t i = 0; i < rows_.size(); ++i) a.mutable_at(i) = rows_[i][c];
        out[LOG_COLUMNS[c]] = a;
      }
    }
    return out;
  }

 private:
  void keep_error() {
    PyErr_Fetch(&error_type_, &error_value_, &error_trace_);
    stop_ = true;
  }

  static constexpr std::chrono::milliseconds SIGNAL_POLL_INTERVAL{100};

  py::object callback_;
  bool has_callback_;
  const Mesh& mesh_;
  std::chrono::steady_clock::time_point last_poll_{};
  bool stop_ = false;
  PyObject* error_type_ = nullptr;
  PyObject* error_value_ = nullptr;
  PyObject* error_trace_ = nullptr;
  std::vector<LogRow> rows_;  // doubles hold the integer columns exactly (< 2^53)
  std::string csv_ = log_csv_header();  ///< rows_ as CSV text (csv_text)
};

/// The library's summary (write_run_summary) into a dict.
class DictSummary final : public SummaryWriter {
 public:
  explicit DictSummary(py::dict& d) : d_(d) {}
  void add_bool(const std::string& key, bool v) override { d_[py::str(key)] = py::bool_(v); }
  void add_null(const std::string& key) override { d_[py::str(key)] = py::none(); }
  void add_integer(const std::string& key, long long v) override { d_[py::str(key)] = py::int_(v); }
  void add_number(const std::string& key, double v) override { d_[py::str(key)] = py::float_(v); }
  // os.fsdecode's str: an option's file name that is not UTF-8 (given as surrogate escapes)
  // comes back as the str the caller gave; other texts are UTF-8 and decode as py::str would.
  void add_text(const std::string& key, const std::string& v) override {
    d_[py::str(key)] = file_name_text(v);
  }
  void add_texts(const std::string& key, const std::vector<std::string>& v) override {
    py::list l;
    for (const std::string& t : v) l.append(file_name_text(t));
    d_[py::str(key)] = l;
  }
  void add_numbers(const std::string& key, const std::vector<double>& v) override {
    d_[py::str(key)] = py::cast(v);
  }
  void add_object(const std::string& key, const std::function<void(SummaryWriter&)>& fill) override {
    py::dict inner;
    DictSummary w(inner);
    fill(w);
    d_[py::str(key)] = inner;
  }

 private:
  py::dict& d_;
};

/// The summary's keys and values as the CLI writes them to JSON, without the file names.
py::dict summary(const InputReport& report, const RunOptions& options, const RunResult& r) {
  py::dict s;
  DictSummary w(s);
  write_run_summary(w, report, options, r, OptionSpelling::Python);
  return s;
}

}  // namespace

py::dict contract(const py::handle& vertices, const py::handle& faces, const py::object& callback,
                  const py::kwargs& all_kwargs) {
  if (!callback.is_none() && !PyCallable_Check(callback.ptr()))
    throw py::type_error("callback must be callable(frame, vertices, metrics) or None");
  py::kwargs kwargs;
  const CheckpointArguments checkpoint = take_checkpoint_arguments(all_kwargs, kwargs);
  RunOptions options = options_from_kwargs(canonical_kwargs(kwargs), ", checkpoint, checkpoint_every, resume");
  const PreparedCheckpoint prepared = prepare_checkpoint(checkpoint, options);  // before the mesh
  InputReport report;
  const Mesh mesh = mesh_from_numpy(vertices, faces, &report);
  PythonObserver observer(callback, mesh);
  if (prepared.resume) {
    check_checkpoint_input(*prepared.resume, "the vertices and faces given", mesh);
    observer.restore_csv(checkpoint_log(*prepared.resume));
  }
  PythonCheckpointer checkpointer(prepared, mesh_hash(mesh), options, observer.csv_text(),
                                  [&observer] { return observer.cancelled(); });
  RunResult r;
  {
    const ActiveRun active;  // destroyed after the GIL is taken back
    py::gil_scoped_release release;
    r = run_contraction(mesh, options, &observer, &checkpointer);
    // Past the exit's wait, the interpreter is going away: this thread never takes the GIL
    // again and sleeps until the process ends around it.
    if (interpreter_finalizing())
      for (;;) std::this_thread::sleep_for(std::chrono::hours(1));
  }
  observer.raise_if_error();
  py::dict out;
  out["vertices"] = positions_to_numpy(input_positions(mesh, r.positions));  // the input's, copies too
  out["faces"] = faces_to_numpy(mesh);
  out["log"] = observer.log();
  out["summary"] = summary(report, options, r);
  out["status"] = out["summary"]["status"];
  // A checkpoint that could not be saved costs the run nothing (its result is here), but the
  // caller relying on it must learn: a warning, and in the summary's warnings.
  const std::string failed_saves = checkpointer.failure_warning();
  if (!failed_saves.empty()) {
    py::dict s = out["summary"];
    if (!s.contains("warnings")) s["warnings"] = py::list();
    s["warnings"].cast<py::list>().append(failed_saves);
    py::module_::import("warnings")
        .attr("warn")(failed_saves, py::module_::import("builtins").attr("UserWarning"), 2);
  }
  return out;
}

void stop_runs_at_exit() {
  exiting.store(true, std::memory_order_release);
  py::gil_scoped_release release;  // the runs take the GIL to finish
  std::unique_lock<std::mutex> lock(runs_mutex);
  runs_changed.wait_for(lock, EXIT_WAIT, [] { return active_runs == 0; });
}

py::dict resolve_options(const py::kwargs& given) {
  const py::dict kwargs = canonical_kwargs(given);
  // The arguments are a command line, whose --region-weights is a file: weights given as an
  // array would be written as the file name "0.5,0.5,...".
  if (kwargs.contains("region_weights") && !is_path(kwargs["region_weights"]))
    throw py::type_error("region_weights: a command line takes the weights' file name, not the weights");
  RunOptions options;
  try {
    options = options_from_kwargs(kwargs);
  } catch (const UsageError& e) {
    // The sweep's check of its jobs: a command of the CLI, so the options go by their flags.
    throw py::value_error(spell_options(e.what(), OptionSpelling::Cli));
  }
  // The arguments in table order (the CLI parses them in that order whatever the order given),
  // each value as the table writes it back (get): numbers in the tool's shortest form (1e+06,
  // not Python's 1000000.0), as --help, the summary and the sweep's results write them.
  py::list args;
  for (const OptionSpec& o : run_option_table()) {
    const std::string name = python_option_name(o.name);
    if (!kwargs.contains(name)) continue;
    const std::string text = o.name == "region-at" ? region_at_text(kwargs[py::str(name)])
                                                   : option_text(name, kwargs[py::str(name)]);
    RunOptions probe;
    o.set(probe, text);  // the option's own parse (a switch's on/off/true/false/1/0)
    if (o.is_switch) {
      if (o.get(probe) == o.get(RunOptions{})) continue;  // off: the flag is left out
      args.append("--" + o.name);
      continue;
    }
    args.append("--" + o.name);
    args.append(o.get(probe));
  }
  py::dict resolved;
  for (const OptionSpec& o : run_option_table()) resolved[py::str(python_option_name(o.name))] = o.get(options);
  py::dict out;
  out["resolved"] = resolved;
  out["args"] = args;
  return out;
}

}  // namespace shellcontract::python
