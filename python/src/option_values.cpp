// Python values of the run's options, turned into the option table's text (the text the CLI
// would receive, so that the same digits give the same double, hence the same run): contract()'s
// keyword arguments, region_at's points, and the sweep's check of its jobs (resolve_options).
#include "option_values.hpp"

#include <Python.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "contract.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract::python {
namespace {

std::string valid_names() {
  std::string s;
  for (const OptionSpec& o : run_option_table()) s += (s.empty() ? "" : ", ") + python_option_name(o.name);
  return s;
}

/// The text the CLI would receive for a Python value: bool -> on/off, float -> shortest_text (the
/// shortest text that reads back as the same double; a whole float for an integer option, N in
/// the table, the integer's digits), int and str as they are, an os.PathLike as its path, a
/// sequence -> "a,b,c" (--fiber X,Y,Z).
std::string option_text(const std::string& name, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "on" : "off";
  // A str may name a file (regions, region_weights): its bytes are the file name's, as for a path.
  if (py::isinstance<py::str>(value)) return file_name_bytes(value);
  if (py::hasattr(value, "__fspath__")) return path_argument(value, "option " + name);  // a file name
  // A numpy array or scalar goes by its Python value (an array also passes PyIndex_Check).
  if (py::hasattr(value, "tolist") && !py::isinstance<py::float_>(value))
    return option_text(name, value.attr("tolist")());
  if (py::isinstance<py::float_>(value)) {
    // A whole float for an integer option (a JSON file's 1e5, a float array's item) is that
    // integer: shortest_text writes 100000.0 as 1e+05, which the integer parser refuses.
    const OptionSpec* spec = find_run_option(name);
    if (spec && spec->value_name == "N")
      if (const std::optional<py::int_> whole = whole_number(value))
        return std::string(py::str(py::handle(*whole)));
    // Else the tool's own text (shortest_text: 2e+06, not Python's 2000000.0), so that a refusal
    // quotes the value as the CLI and the summary write it.
    return shortest_text(value.cast<double>());
  }
  if (PyIndex_Check(value.ptr())) return py::str(py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr())));
  // Keyframes as (frame, value) pairs (target_volume=[(0, 1), (60, 0.5)]): the CLI's
  // "0:1, 60:0.5".
  if ((py::isinstance<py::tuple>(value) || py::isinstance<py::list>(value)) && py::len(value) > 0 &&
      (py::isinstance<py::tuple>(value[py::int_(0)]) || py::isinstance<py::list>(value[py::int_(0)]))) {
    std::string s;
    int keys = 0;
    for (const py::handle& key : value) {
      if (!(py::isinstance<py::tuple>(key) || py::isinstance<py::list>(key)) || py::len(key) != 2)
        throw py::value_error("option " + name + ": keyframes are (frame, value) pairs, got " +
                              std::string(py::str(py::repr(key))));
      // True would reach the table as the frame 'on'.
      for (int i = 0; i < 2; ++i)
        if (is_bool(key[py::int_(i)]))
          throw py::type_error("option " + name + ": key " + std::to_string(keys + 1) + " = " +
                               std::string(py::str(py::repr(key))) + ": its " +
                               (i == 0 ? "frame" : "value") +
                               " is a bool; keyframes are (frame, value) pairs of numbers");
      ++keys;
      // A whole float frame (a float array's 15.0) is the integer frame it stands for.
      py::object frame = key[py::int_(0)];
      if (py::isinstance<py::float_>(frame))
        if (const std::optional<py::int_> whole = whole_number(frame)) frame = *whole;
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

/// A list, a tuple or an array that is not 0-dimensional (a numpy scalar is one value).
bool is_sequence(const py::handle& value) {
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) return true;
  return py::hasattr(value, "tolist") && py::hasattr(value, "ndim") && value.attr("ndim").cast<int>() > 0;
}

/// The keyframe options, by the table's own value names (pressure, target_volume: "P|KEYS").
bool takes_keyframes(const OptionSpec& spec) {
  return spec.value_name.find("KEYS") != std::string::npos;
}

/// The options whose text may be a list: keyframes and a direction (fiber: "centre|X,Y,Z");
/// region_at and region_weights are read before the table.
bool takes_sequence(const OptionSpec& spec) {
  return takes_keyframes(spec) || spec.value_name.find(',') != std::string::npos;
}

/// A list of keyframes: a sequence (an array by its tolist) of at least one item, every item a
/// list or a tuple; option_text checks each for a pair.
bool is_keyframe_list(const py::handle& value) {
  const py::object items = py::hasattr(value, "tolist") ? value.attr("tolist")()
                                                        : py::reinterpret_borrow<py::object>(value);
  if (py::len(items) == 0) return false;
  for (const py::handle& item : items)
    if (!(py::isinstance<py::tuple>(item) || py::isinstance<py::list>(item))) return false;
  return true;
}

}  // namespace

py::object python_value(const py::handle& value) {
  if (py::hasattr(value, "tolist") && !py::isinstance<py::float_>(value))
    return value.attr("tolist")();
  return py::reinterpret_borrow<py::object>(value);
}

std::optional<py::int_> whole_number(const py::handle& value) {
  const py::object v = python_value(value);
  if (is_bool(value) || py::isinstance<py::bool_>(v)) return std::nullopt;
  if (PyFloat_Check(v.ptr())) {
    const double d = PyFloat_AsDouble(v.ptr());
    if (!std::isfinite(d) || std::floor(d) != d) return std::nullopt;
    return py::reinterpret_steal<py::int_>(PyLong_FromDouble(d));  // exact, whatever its size
  }
  if (!PyIndex_Check(v.ptr())) return std::nullopt;
  const py::int_ n = py::reinterpret_steal<py::int_>(PyNumber_Index(v.ptr()));
  if (!n) throw py::error_already_set();
  return n;
}

bool is_bool(const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return true;
  if (!py::hasattr(value, "dtype") || !py::hasattr(value, "ndim")) return false;
  return value.attr("ndim").cast<int>() == 0 &&
         value.attr("dtype").attr("kind").cast<std::string>() == "b";
}

bool is_path(const py::handle& value) {
  return py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__");
}

namespace {

/// region_at's coordinates are real numbers, as contract()'s numbers are: numpy's conversion
/// would read True as 1 and the strings "1e3" or " 1_0 " (its grammar, not the CLI's) as numbers.
/// `depth`: 0 for region_at itself, 1 for a point of a list, 2 for a coordinate.
void refuse_unreal_items(const py::handle& value, const std::string& forms, int depth) {
  if (py::hasattr(value, "dtype") && py::hasattr(value, "ndim")) {  // an array or a numpy scalar
    const std::string kind = value.attr("dtype").attr("kind").cast<std::string>();
    if (kind != "i" && kind != "u" && kind != "f")
      throw py::type_error("region_at: coordinates are real numbers, got " +
                           std::string(py::str(py::repr(value))) + " of dtype " +
                           std::string(py::str(value.attr("dtype"))));
    return;
  }
  if (is_bool(value) || py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) ||
      PyComplex_Check(value.ptr()))
    throw py::type_error("region_at: coordinates are real numbers, got " +
                         std::string(py::str(py::repr(value))));
  // Nested deeper than a list of points: not a form of region_at, whatever numpy makes of it.
  if (depth < 2 && PySequence_Check(value.ptr()) && !py::isinstance<py::dict>(value))
    for (const py::handle& item : py::reinterpret_borrow<py::sequence>(value))
      refuse_unreal_items(item, forms, depth + 1);
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
  refuse_unreal_items(value, forms, 0);
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

// Given both ways, the later spelling had silently won, and resolve_options left a dashed name
// out of the sweep's command line while recording its value.
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

RunOptions options_from_kwargs(const py::dict& kwargs, const std::string& also_valid) {
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
    // A list of numbers for a keyframe option had its one item taken as the value (pressure=[1]
    // ran as 1, a sweep file's "pressure": [0.5] as 0.5) and two refused as the number '1,2'.
    if (is_sequence(value) && takes_keyframes(*spec) && !is_keyframe_list(value))
      throw py::type_error(
          name + ": got " + std::string(py::str(py::repr(value))) +
          "; it takes one value, or keyframes: a list of (frame, value) pairs, an N by 2 "
          "array or the text \"F:V, F:V\", not a list of values");
    try {
      spec->set(options, option_text(name, value));  // UsageError (ValueError) for a bad value
    } catch (const UsageError& e) {
      // A bool reaches the table as on/off, which only the on/off options take: a number's
      // refusal would otherwise read "frames: 'on' is not an integer".
      if (is_bool(value))
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
    o.set(probe, text);  // the option's own parse (a switch's on or off)
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
