// shellcontract.contract: the Python mirror of cli/run.cpp. Options go through the option table
// as text (option_values.cpp: the same digits give the same double, hence the same run as the
// CLI); the run goes through run_contraction with one observer that keeps the log, calls the
// Python callback and polls for Ctrl-C.
#include "contract.hpp"

#include <Python.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <typeinfo>
#include <utility>
#include <vector>

#include "arrays.hpp"
#include "checkpointing.hpp"
#include "option_values.hpp"
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
  ~ActiveRun() { leave(); }
  ActiveRun(const ActiveRun&) = delete;
  ActiveRun& operator=(const ActiveRun&) = delete;

  /// Counted no more from now on (once only).
  void leave() {
    if (left_) return;
    left_ = true;
    std::lock_guard<std::mutex> lock(runs_mutex);
    --active_runs;
    runs_changed.notify_all();
  }

 private:
  bool left_ = false;
};

/// Runs work with the GIL released, counted for the interpreter's exit, and returns what it
/// threw, for the caller to raise with the GIL (after a pending Python error of its own, if it
/// has one). Past the exit's wait the interpreter is going away, and taking the GIL back would
/// end this thread inside C++ frames (an abort): the thread leaves the exit's count and sleeps
/// until the process ends around it. So does work that threw when park_on_error says so.
std::exception_ptr released(const std::function<void()>& work,
                            const std::function<bool()>& park_on_error = {}) {
  std::exception_ptr error;
  // Called while the interpreter finalizes (a __del__ run then): this thread holds the GIL, so it
  // is the one finalizing (no other may take the GIL any more). It keeps the GIL for the work:
  // parked below, it would hang the exit for ever.
  if (interpreter_finalizing()) {
    try {
      work();
    } catch (...) {
      error = std::current_exception();
    }
    return error;
  }
  ActiveRun active;  // destroyed after the GIL is taken back
  py::gil_scoped_release release;
  try {
    work();
  } catch (...) {  // rethrown by the caller with the GIL: taking it back may never return (below)
    error = std::current_exception();
  }
  if (interpreter_finalizing() || (error && park_on_error && park_on_error())) {
    active.leave();
    for (;;) std::this_thread::sleep_for(std::chrono::hours(1));
  }
  return error;
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
  PythonObserver(py::object callback, py::object stage, const Mesh& mesh)
      : callback_(std::move(callback)),
        has_callback_(!callback_.is_none()),
        stage_(std::move(stage)),
        has_stage_(!stage_.is_none()),
        mesh_(mesh) {}

  ~PythonObserver() override {
    // A pending error is only dropped when contract() itself throws before taking it.
    if (error_type_) {
      Py_XDECREF(error_type_);
      Py_XDECREF(error_value_);
      Py_XDECREF(error_trace_);
    }
  }

  /// On the caller's thread (each run has an arena of its own: core/arena_threads.hpp), the GIL
  /// released: taken for the call, as in frame().
  void stage(const std::string& what) override {
    doing_ = what;
    if (!has_stage_ || stop_) return;
    if (interpreter_exiting()) {
      stop_ = true;
      return;
    }
    py::gil_scoped_acquire gil;
    try {
      stage_(py::str(what));
    } catch (py::error_already_set& e) {
      e.restore();
      keep_error();  // stop_: the preparation's next cancellation point ends the run
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

  /// The run's last stage (for a message on memory running out before the first frame; after
  /// it, the run ends "failed" with its last good state instead).
  const std::string& doing() const { return doing_; }

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

  std::string doing_ = "setting up the run";
  py::object callback_;
  bool has_callback_;
  py::object stage_;
  bool has_stage_;
  const Mesh& mesh_;
  std::chrono::steady_clock::time_point last_poll_{};
  bool stop_ = false;
  PyObject* error_type_ = nullptr;
  PyObject* error_value_ = nullptr;
  PyObject* error_trace_ = nullptr;
  std::vector<LogRow> rows_;  // doubles hold the integer columns exactly (< 2^53)
  std::string csv_ = log_csv_header();  ///< rows_ as CSV text (csv_text)
};

/// run_released's cancel hook: Python's signal handlers asked from the thread that released the
/// GIL, as PythonObserver::cancelled asks them for a run.
class SignalPoll {
 public:
  SignalPoll() = default;
  SignalPoll(const SignalPoll&) = delete;
  SignalPoll& operator=(const SignalPoll&) = delete;
  ~SignalPoll() {
    // Only dropped when the caller throws before taking it.
    if (error_type_) {
      Py_XDECREF(error_type_);
      Py_XDECREF(error_value_);
      Py_XDECREF(error_trace_);
    }
  }

  /// Called without the GIL, on the thread that released it.
  bool cancelled() {
    if (stop_) return true;
    if (interpreter_exiting()) return stop_ = true;  // checked without the GIL
    // As PythonObserver::cancelled: a few times a second, the GIL can take a switch interval.
    const auto now = std::chrono::steady_clock::now();
    if (now - last_poll_ < POLL_INTERVAL) return false;
    last_poll_ = now;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {  // Ctrl-C: the default handler raised KeyboardInterrupt
      PyErr_Fetch(&error_type_, &error_value_, &error_trace_);
      stop_ = true;
    }
    return stop_;
  }

  /// Raises the error a signal handler raised, if any (GIL held).
  void raise_if_error() {
    if (!error_type_) return;
    PyErr_Restore(error_type_, error_value_, error_trace_);
    error_type_ = error_value_ = error_trace_ = nullptr;
    throw py::error_already_set();
  }

  /// Whether it said stop for the interpreter's exit, no signal handler having raised.
  bool stopped_by_exit() const { return stop_ && !error_type_; }

 private:
  static constexpr std::chrono::milliseconds POLL_INTERVAL{100};

  std::chrono::steady_clock::time_point last_poll_{};
  bool stop_ = false;
  PyObject* error_type_ = nullptr;
  PyObject* error_value_ = nullptr;
  PyObject* error_trace_ = nullptr;
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

/// Rethrows the run's error; memory running out (before the first frame) becomes a MemoryError that
/// says what the run was doing and on how large a mesh (pybind11's own said only "std::bad_alloc"),
/// as the CLI's exit 3 does. A reader's out-of-memory error already names its file and passes
/// unchanged.
[[noreturn]] void raise_with_stage(const std::exception_ptr& error, const std::string& doing,
                                   const Mesh& mesh) {
  try {
    std::rethrow_exception(error);
  } catch (const std::bad_alloc& e) {
    if (typeid(e) != typeid(std::bad_alloc)) throw;  // a message of its own (OutOfMemoryError)
    const std::string message = "out of memory while " + doing + " (" +
                                std::to_string(mesh.number_of_vertices()) + " vertices, " +
                                std::to_string(mesh.number_of_faces()) + " faces)";
    PyErr_SetString(PyExc_MemoryError, message.c_str());
    throw py::error_already_set();
  }
}

}  // namespace

py::dict contract(const py::handle& vertices, const py::handle& faces, const py::object& callback,
                  const py::object& stage, const py::kwargs& all_kwargs) {
  if (!callback.is_none() && !PyCallable_Check(callback.ptr()))
    throw py::type_error("callback must be callable(frame, vertices, metrics) or None");
  if (!stage.is_none() && !PyCallable_Check(stage.ptr()))
    throw py::type_error("stage must be callable(what) or None");
  py::kwargs kwargs;
  const CheckpointArguments checkpoint = take_checkpoint_arguments(all_kwargs, kwargs);
  RunOptions options = options_from_kwargs(
      canonical_kwargs(kwargs),
      ", checkpoint, checkpoint_every, resume, region_strengths, callback, stage, lambda_");
  const PreparedCheckpoint prepared = prepare_checkpoint(checkpoint, options);  // before the mesh
  InputReport report;
  const Mesh mesh = [&] {
    try {
      return mesh_from_numpy(vertices, faces, &report);
    } catch (const std::bad_alloc& e) {
      if (typeid(e) != typeid(std::bad_alloc)) throw;
      PyErr_SetString(PyExc_MemoryError,
                      "out of memory while building the mesh from the vertices and faces given");
      throw py::error_already_set();
    }
  }();
  PythonObserver observer(callback, stage, mesh);
  if (prepared.resume) {
    check_checkpoint_input(*prepared.resume, "the vertices and faces given", mesh);
    observer.restore_csv(checkpoint_log(*prepared.resume));
  }
  PythonCheckpointer checkpointer(prepared, mesh_hash(mesh), options, observer.csv_text(),
                                  [&observer] { return observer.cancelled(); });
  RunResult r;
  const std::exception_ptr error =
      released([&] { r = run_contraction(mesh, options, &observer, &checkpointer); });
  if (error) raise_with_stage(error, observer.doing(), mesh);
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

void run_released(const std::function<void(const std::function<bool()>& cancelled)>& work) {
  SignalPoll poll;
  // Work the exit stopped (a daemon thread's: the others were joined before the exit's hooks)
  // has no result to return, and raising there printed "Exception in thread" as the interpreter
  // went away: it stays off the GIL too.
  const std::exception_ptr error = released([&] { work([&poll] { return poll.cancelled(); }); },
                                            [&poll] { return poll.stopped_by_exit(); });
  poll.raise_if_error();  // Ctrl-C's KeyboardInterrupt, not the RegionSearchCancelled it caused
  if (error) std::rethrow_exception(error);
}

void without_gil(const std::function<void()>& work) {
  const std::exception_ptr error = released(work);
  if (error) std::rethrow_exception(error);
}

void stop_runs_at_exit() {
  exiting.store(true, std::memory_order_release);
  py::gil_scoped_release release;  // the runs take the GIL to finish
  std::unique_lock<std::mutex> lock(runs_mutex);
  runs_changed.wait_for(lock, EXIT_WAIT, [] { return active_runs == 0; });
}

}  // namespace shellcontract::python
