// The run's options from Python values (option_values.cpp): keyword arguments as the option
// table's text, as the CLI would receive them, for contract(), regions() and the sweep.
#pragma once

#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <vector>

#include "shellcontract/options.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract::python {

namespace py = pybind11;

/// A file name as Python takes one: a str or an os.PathLike (not bytes: a value of an option).
bool is_path(const py::handle& value);

/// A bool as Python code passes one: a bool, numpy's bool_, or a 0-dimensional array of bools.
/// Only the on/off options take one; for a number it is a TypeError, whichever kind it is.
bool is_bool(const py::handle& value);

/// An option's value as option_text reads it: a numpy scalar or 0-d array by its Python value
/// (tolist), so that an array of one element is a list, not the number, and numpy's complex a
/// complex; anything else as it is.
py::object python_value(const py::handle& value);

/// The one rule by which the module reads an integer argument (contract()'s and the sweep's
/// integer options, regions()'s min_faces, checkpoint_every): an int (numpy's too) or a float
/// whose value is whole (3.0; a JSON file's 1e5; numpy's too) is that integer, exactly; anything
/// else (3.5, NaN, inf, a bool or numpy's bool, a str, None) is std::nullopt, for the caller's
/// message. A str is the CLI's text, which each caller reads with the CLI's parser.
std::optional<py::int_> whole_number(const py::handle& value);

/// The options by their Python names: an option is also taken as the CLI spells it ("k-b" for
/// k_b, as regions() takes them), once (TypeError for one given both ways). Unknown names are
/// kept as given, for options_from_kwargs's message.
py::dict canonical_kwargs(const py::kwargs& kwargs);

/// The run's options from canonical keyword arguments, resolved (resolve_run_options), with the
/// log's energies on. TypeError for an unknown name (listing the table's names, then
/// `also_valid`: the caller's own arguments), a list for an option of one value, or a bool for
/// an option that is not on/off; ValueError (UsageError) for a bad value.
RunOptions options_from_kwargs(const py::dict& kwargs, const std::string& also_valid = "");

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

}  // namespace shellcontract::python
