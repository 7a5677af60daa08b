// shellcontract.contract and shellcontract.options: a run through run_contraction
// (shellcontract/run.hpp) with the options of the one option table (shellcontract/options.hpp), as
// the CLI's `run` does.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "shellcontract/types.hpp"

namespace shellcontract::python {

namespace py = pybind11;

/// Contracts the mesh (vertices N by 3, faces M by 3) with the keyword options (the table's names
/// with underscores; values as numbers, strings or bools, turned into the text the CLI would get).
/// The GIL is released during the run; `callback(frame, vertices, metrics)` runs after each step
/// with the GIL held, and returning a false value (False, numpy's False_, 0; not None) cancels
/// the run. A KeyboardInterrupt cancels the run and is raised when it has returned.
/// @return dict with vertices, faces, log (column -> array), summary (dict), status
py::dict contract(const py::handle& vertices, const py::handle& faces, const py::object& callback,
                  const py::kwargs& options);

/// Registered with Python's atexit when the module loads: cancels every run still going (in a
/// daemon thread, say) and waits for it to leave the library, so that no thread takes the GIL
/// while the interpreter finalizes (it would be ended inside C++ frames: an abort).
void stop_runs_at_exit();

/// Checks keyword options as contract() does (TypeError for an unknown name, ValueError naming
/// the option and its range) without running anything: the sweep's validation of every job. The
/// sweep is a command of the CLI: its ValueError names the options by their flags (--damping).
/// @return dict: "resolved" (python name -> the table's text of every option after
///         resolve_run_options) and "args" (the `shellcontract run` arguments of the given ones)
py::dict resolve_options(const py::kwargs& options);

/// region_at's value as the option table's text ("x,y,z;x,y,z"): a str as it is; a point
/// (x, y, z) or a list or array of points as their shortest round-trip digits. TypeError for
/// None or a value that is no sequence; ValueError for no point, a point without three
/// coordinates, or a coordinate that is not finite (named region_at[i], Python's index).
std::string region_at_text(const py::handle& value);

/// region_at's points, parsed as contract() parses them (region_at_text, then the option table's
/// own parser: the same forms, the same errors), for regions().
std::vector<Vec3> region_at_points(const py::handle& value);

/// The option table: one (python_name, default, help, cli_name) tuple per option, in --help order
/// (option_table.cpp), the help naming the other options as Python does.
py::list option_table();

/// An option's Python name: the table's CLI name with '_' for '-' (k-b -> k_b).
std::string python_option_name(std::string cli_name);

}  // namespace shellcontract::python
