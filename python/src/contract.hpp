// shellcontract.contract and shellcontract.options: a run through run_contraction
// (shellcontract/run.hpp) with the options of the one option table (shellcontract/options.hpp), as
// the CLI's `run` does.
#pragma once

#include <pybind11/pybind11.h>

#include <functional>
#include <string>

namespace shellcontract::python {

namespace py = pybind11;

/// Contracts the mesh (vertices N by 3, faces M by 3) with the keyword options (the table's names
/// with underscores; values as numbers, strings or bools, turned into the text the CLI would get).
/// The GIL is released during the run; `callback(frame, vertices, metrics)` runs after each step
/// with the GIL held, and returning a false value (False, numpy's False_, 0; not None) cancels
/// the run. A KeyboardInterrupt cancels the run and is raised when it has returned.
/// `stage(what)` (None: not called) runs with the GIL held as the run enters a stage of its
/// preparation, or the last step's check (RunObserver::stage); an error it raises cancels the run
/// and is raised when it has returned.
/// @return dict with vertices, faces, log (column -> array), summary (dict), status
py::dict contract(const py::handle& vertices, const py::handle& faces, const py::object& callback,
                  const py::object& stage, const py::kwargs& options);

/// Runs `work` with the GIL released, as contract() runs its run: counted for the interpreter's
/// exit (stop_runs_at_exit), and handed a cancel hook for the library (RegionOptions::cancelled)
/// that asks Python's signal handlers a few times a second and says stop once one has raised
/// (Ctrl-C: KeyboardInterrupt) or the interpreter exits. With the GIL back, the handler's
/// exception is raised if there was one (rather than the RegionSearchCancelled it caused), else
/// work's own, if any.
void run_released(const std::function<void(const std::function<bool()>& cancelled)>& work);

/// Runs `work` with the GIL released, counted for the interpreter's exit as a run is, and
/// rethrows what it threw with the GIL back: for the module's other work without Python objects
/// (reading, writing, checking a mesh). A daemon thread's check of a large mesh that took the
/// GIL back while the interpreter finalized aborted the process ("terminate called without an
/// active exception"); the exit now waits for it as for a run.
void without_gil(const std::function<void()>& work);

/// Registered with Python's atexit when the module loads: cancels every run still going (in a
/// daemon thread, say; run_released's work too) and waits for it to leave the library, so that
/// no thread takes the GIL while the interpreter finalizes (it would be ended inside C++ frames:
/// an abort).
void stop_runs_at_exit();

/// The option table: one (python_name, default, help, cli_name) tuple per option, in --help order
/// (option_table.cpp), the help naming the other options as Python does.
py::list option_table();

/// An option's Python name: the table's CLI name with '_' for '-' (k-b -> k_b).
std::string python_option_name(std::string cli_name);

}  // namespace shellcontract::python
