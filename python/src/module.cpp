// The compiled part of the `shellcontract` Python package (shellcontract._core): contract and
// options (contract.cpp), and the mesh helpers that mirror the CLI's check, regions and the
// library's reader and writer. python/shellcontract/__init__.py wraps them.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "contract.hpp"
#include "file_error.hpp"
#include "mesh_error.hpp"
#include "option_values.hpp"
#include "shellcontract/checkpoint.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/output_files.hpp"
#include "shellcontract/regions.hpp"
#include "shellcontract/validation.hpp"
#include "shellcontract/version.hpp"

namespace shellcontract::python {
namespace {

bool path_has_extension(const std::string& path, const std::string& ext) {
  const std::string e = std::filesystem::path(path).extension().string();
  return e.size() == ext.size() + 1 &&
         std::equal(ext.begin(), ext.end(), e.begin() + 1, [](char a, char b) { return a == std::tolower(static_cast<unsigned char>(b)); });
}

/// What `shellcontract check` reports, for a mesh that passed the input checks.
py::dict check(const py::handle& vertices, const py::handle& faces) {
  InputReport report;
  const Mesh mesh = mesh_from_numpy(vertices, faces, &report);
  const Positions x = positions_from_mesh(mesh);
  // As `check --json`: all the pairs counted, the first CHECK_LISTED_PAIRS (face order) returned; a
  // mesh whose parts pass through each other has pairs in the square of its faces.
  SelfIntersectionCount counted;
  without_gil([&] { counted = count_self_intersections(mesh, x, CHECK_LISTED_PAIRS); });
  const std::vector<FacePair>& pairs = counted.first;
  const SurfaceTopology topology = surface_topology(mesh, report.components);  // as `check`
  py::array_t<std::int64_t> pair_array({static_cast<py::ssize_t>(pairs.size()), py::ssize_t{2}});
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    pair_array.mutable_at(i, 0) = static_cast<std::int64_t>(pairs[i].first.idx());
    pair_array.mutable_at(i, 1) = static_cast<std::int64_t>(pairs[i].second.idx());
  }
  py::dict d;
  d["vertices"] = report.vertices;
  d["faces"] = report.faces;
  d["edges"] = static_cast<std::size_t>(mesh.number_of_edges());
  d["components"] = report.components;
  d["euler_characteristic"] = topology.euler_characteristic;
  d["genus"] = topology.genus;
  d["volume"] = report.volume;
  d["bounding_box_diagonal"] = (x.colwise().maxCoeff() - x.colwise().minCoeff()).norm();
  d["reoriented"] = report.reoriented;
  d["welded_vertices"] = report.welded_vertices;
  d["zero_area_faces"] = report.zero_area_faces;
  d["self_intersecting_pairs"] = counted.count;
  d["self_intersections"] = pair_array;
  d["self_intersections_truncated"] = pairs.size() < counted.count;
  d["warnings"] = report.warnings;
  return d;
}

std::string type_name(const py::handle& value) {
  return std::string(py::str(value.get_type().attr("__name__")));
}

/// A real option of regions(): an int or a float (numpy's too), as contract() takes its numbers;
/// TypeError for anything else (a bool, numpy's too; a string: the package's regions() reads a
/// str as the CLI's text first; an array, a complex), ValueError naming the option's range for a
/// value outside it (NaN and infinities too).
double real_option(const std::string& name, const py::handle& value) {
  const py::object v = python_value(value);
  if (is_bool(value) || py::isinstance<py::bool_>(v) ||
      !(PyFloat_Check(v.ptr()) || PyIndex_Check(v.ptr())))
    throw py::type_error("regions() option " + name + ": expected a real number, got " +
                         type_name(value));
  const double d = PyFloat_AsDouble(v.ptr());
  if (d == -1.0 && PyErr_Occurred()) throw py::error_already_set();
  // The library's range of the option, in its words (check_region_options): a fraction's
  // [0, 1] also for NaN, which is out of every range.
  std::string field = name;
  std::replace(field.begin(), field.end(), '-', '_');
  if (!in_region_option_range(field, d))
    throw py::value_error("regions() option " + name + ": expected " + region_option_range(field) +
                          ", got " + std::string(py::repr(value)));
  return d;
}

/// A positive integer option of regions(): min_faces, whose range is the library's
/// (check_region_options: >= 1) and the CLI's (--min-faces reads an int). As contract()'s
/// integers (whole_number): an int (numpy's too) or a float whose value is whole (3.0; 3.5 is a
/// ValueError); TypeError for a bool (numpy's too) or anything else.
int int_option(const std::string& name, const py::handle& value) {
  constexpr long long most = std::numeric_limits<int>::max();
  const auto out_of_range = [&] {
    return py::value_error("regions() option " + name + ": expected an integer from 1 to " +
                           std::to_string(most) + ", got " + std::string(py::repr(value)));
  };
  const py::object v = python_value(value);
  if (is_bool(value) || py::isinstance<py::bool_>(v) ||
      !(PyFloat_Check(v.ptr()) || PyIndex_Check(v.ptr())))
    throw py::type_error("regions() option " + name + ": expected an integer, got " +
                         type_name(value));
  const std::optional<py::int_> whole = whole_number(value);
  if (!whole) throw out_of_range();  // 3.5, NaN
  int overflow = 0;
  const long long n = PyLong_AsLongLongAndOverflow(whole->ptr(), &overflow);
  if (overflow != 0 || n < 1 || n > most) throw out_of_range();
  return static_cast<int>(n);
}

/// The method option of regions(): one of the library's names, "caps", "tips" or "parts"
/// (TypeError for a non-str, ValueError naming the allowed values otherwise), as the CLI's
/// --method.
RegionMethod method_option(const py::handle& value) {
  if (!py::isinstance<py::str>(value))
    throw py::type_error("regions() option method: expected a str (" + region_method_names("'") +
                         "), got " + type_name(value));
  if (const std::optional<RegionMethod> m = region_method_named(value.cast<std::string>()))
    return *m;
  throw py::value_error("regions() option method: expected " + region_method_names("'") + ", got " +
                        std::string(py::repr(value)));
}

/// The regions `run --regions auto` would choose: one ascending face-index array per region.
/// The options are the CLI's (`shellcontract regions --help`), with '_' or '-':
/// regions(V, F, max_area_fraction=0.1), regions(V, F, method="tips") (opt-in: the tip finder),
/// method="parts" (opt-in: the tip finder's ends with the cap finder's heads and bumps) or
/// regions(V, F, **{"region-at": [(x, y, z)]}) (region_at in contract()'s forms: region_at_points).
py::list regions(const py::handle& vertices, const py::handle& faces, const py::kwargs& kwargs) {
  RegionOptions o;
  std::vector<Vec3> at;
  std::set<std::string> seen;  // one option by both spellings: refused, not the last one taken
  for (const auto& [key, value] : kwargs) {
    const std::string given = key.cast<std::string>();  // messages name the option as the caller spelt it
    std::string name = given;
    std::replace(name.begin(), name.end(), '_', '-');
    if (!seen.insert(name).second)
      throw py::type_error("regions() got the option '" + given + "' twice (as '-' and as '_')");
    if (name == "method") o.method = method_option(value);
    else if (name == "fit-tolerance") o.fit_tolerance = real_option(given, value);
    else if (name == "max-concave-fraction") o.max_concave_fraction = real_option(given, value);
    else if (name == "min-cap-angle") o.min_cap_angle_deg = real_option(given, value);
    else if (name == "contrast") o.min_curvature_contrast = real_option(given, value);
    else if (name == "max-compactness") o.max_compactness = real_option(given, value);
    else if (name == "min-faces") o.min_faces = int_option(given, value);
    else if (name == "min-area-fraction") o.min_area_fraction = real_option(given, value);
    else if (name == "max-area-fraction") o.max_area_fraction = real_option(given, value);
    else if (name == "region-at") at = region_at_points(value);  // contract()'s forms and checks
    else
      throw py::type_error("regions() got an unknown option '" + key.cast<std::string>() +
                           "'; valid options (those of `shellcontract regions`, '-' or '_'): fit_tolerance, "
                           "max_concave_fraction, min_cap_angle, contrast, max_compactness, min_faces, "
                           "min_area_fraction, max_area_fraction, region_at, method");
  }
  // The cap finder's shape tests, as the CLI refuses them with the tip finder (they would do
  // nothing there).
  for (const char* name : {"fit-tolerance", "min-cap-angle", "contrast"})
    if (o.method == RegionMethod::Tips && seen.count(name)) {
      std::string spelt = name;
      std::replace(spelt.begin(), spelt.end(), '-', '_');
      throw py::value_error("regions(): " + spelt +
                            " shapes the cap finder's caps; it does not apply with method='tips'");
    }
  if (o.method != RegionMethod::Caps && !at.empty())
    throw py::value_error(std::string("regions(): region_at grows caps; it does not apply with method='") +
                          (o.method == RegionMethod::Tips ? "tips" : "parts") + "'");
  const Mesh mesh = mesh_from_numpy(vertices, faces);
  std::vector<int> ids;
  RegionReport report;
  // The search reads only the mesh made above: other Python threads (Blender's interface) go on
  // meanwhile, as during contract(); it asks for Ctrl-C as a run does (KeyboardInterrupt).
  run_released([&](const std::function<bool()>& cancelled) {
    o.cancelled = cancelled;
    ids = at.empty() ? select_spherical_regions(mesh, positions_from_mesh(mesh), o)
                     : select_regions_at(mesh, positions_from_mesh(mesh), at, o, &report);
  });
  // A region_at point far from the surface: a UserWarning at the caller's line, as the CLI's
  // "warning:" (the list holds only face ids).
  for (const std::string& w : report.warnings)
    py::module_::import("warnings")
        .attr("warn")(spell_options(w, OptionSpelling::Python),
                      py::module_::import("builtins").attr("UserWarning"), 2);
  py::list out;
  for (const std::vector<int>& r : regions_from_face_ids(ids)) {
    py::array_t<std::int64_t> a(static_cast<py::ssize_t>(r.size()));
    for (std::size_t i = 0; i < r.size(); ++i) a.mutable_at(i) = r[i];
    out.append(a);
  }
  return out;
}

py::tuple read_mesh(const py::handle& path_arg) {
  const std::string path = path_argument(path_arg);
  Mesh mesh;
  Positions x;
  // Reading and checking touch no Python object: other Python threads go on meanwhile (a
  // program reading several files in threads, a user interface).
  InputReport report;
  without_gil([&] {
    mesh = read_input_mesh(path, &report);
    // The file's vertices, a mesh welded along its seams included: contract() welds them again.
    x = input_positions(mesh, positions_from_mesh(mesh));
  });
  // What the reader changed or found (polygons split, an inside-out mesh flipped, zero-area
  // faces): a UserWarning each, as the CLI's "warning:" lines.
  for (const std::string& w : report.warnings)
    py::module_::import("warnings")
        .attr("warn")(w, py::module_::import("builtins").attr("UserWarning"), 2);
  return py::make_tuple(positions_to_numpy(x), faces_to_numpy(mesh));
}

void write_mesh(const py::handle& path_arg, const py::handle& vertices, const py::handle& faces,
                const py::handle& like_arg) {
  const std::string path = path_argument(path_arg);
  // A device, FIFO or folder in the output's place is refused for what it is, as the CLI's
  // check of its outputs does, before its name is checked (/dev/null has no extension, and with
  // like= the name must have like's).
  refuse_special_output(path);
  const std::string like = like_arg.is_none() ? std::string() : path_argument(like_arg, "like");
  // The faces are written as given (no reorientation): this writes a result back.
  const Mesh mesh = mesh_from_numpy(vertices, faces, nullptr, /*reorient=*/false);
  const Positions x = positions_from_numpy(vertices);
  if (!like.empty()) {
    // The file `like` kept whole with these positions (docs/design/attributes.md): only for the
    // mesh read_mesh(like) gives, written in like's format. Read and checked first, so that a bad
    // file gets the reader's message and the document parses only bytes the reader accepted.
    Mesh read;
    std::unique_ptr<MeshDocument> doc;
    without_gil([&] {  // the arrays are compared below, with the GIL
      read = read_input_mesh(like);
      doc = read_mesh_document(like);
    });
    // The formats with a document are the format table's (read_mesh_document): OBJ, PLY and glTF.
    if (!doc)
      throw UsageError("write_mesh: like=" + like +
                       ": only an OBJ, PLY, .glb or .gltf file (OFF and STL keep nothing besides "
                       "the mesh: write without like=), written to a file of its format");
    if (!path_has_extension(path, doc->format()))
      throw UsageError("write_mesh: like=" + like + ": written to a file of its format (." +
                       doc->format() + "), not " + path);
    // C order, so that faces equal to read_mesh's in another layout compare equal element by
    // element (a Fortran or strided array was compared in memory order, and refused).
    const auto f = faces_to_numpy(read);
    const auto g =
        py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(faces);
    if (!g || g.size() != f.size() || !std::equal(f.data(), f.data() + f.size(), g.data()) || !doc->matches(read))
      throw UsageError("write_mesh: like=" + like + ": the faces are not those read_mesh gives for it");
    std::vector<std::string> warnings;  // a material library of like's that does not exist
    without_gil([&] { write_mesh_document_atomic(path, *doc, x, &warnings); });
    for (const std::string& w : warnings)
      py::module_::import("warnings").attr("warn")(w, py::module_::import("builtins").attr("UserWarning"), 2);
    return;
  }
  // A glTF holds a scene, which only the file read (like=) can give; the writers' own message
  // ("unknown extension") would hide that it is written that way.
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".glb" || ext == ".gltf")
    throw UsageError("write_mesh: cannot write '" + path + "': a " + ext +
                     " is written only with like= (the glTF file read_mesh read these faces from: "
                     "it keeps the scene, with these positions); without like=, write .off, .obj, "
                     ".ply or .stl");
  // Only C++ objects from here: other Python threads go on while the file is written.
  without_gil([&] { write_mesh_atomic(path, mesh, x); });
}

}  // namespace
}  // namespace shellcontract::python

PYBIND11_MODULE(_core, m) {
  // The build and this machine's kernels (shellcontract/version.hpp); a mistyped
  // SHELLCONTRACT_KERNELS fails the import with its message.
  m.attr("__version__") = shellcontract::build_version();
  m.attr("kernels") = shellcontract::kernel_class();
  namespace py = pybind11;
  using namespace shellcontract;
  using namespace shellcontract::python;
  m.doc() = "ShellContract's compiled core; use the shellcontract package";
  // The library's errors as Python's: a bad mesh or a bad option value is a ValueError with the
  // library's message (what the CLI prints before exiting with 2 or 1).
  // A mesh refused for particular faces is a MeshError, a ValueError with their indices as
  // `faces` (mesh_error.hpp).
  register_mesh_error(m);
  // A file that cannot be read or written is a FileError: the OSError subclass of its errno
  // (FileNotFoundError, PermissionError, ...) and a ValueError as before (file_error.hpp).
  register_file_errors(m);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const FaceListError& e) {
      set_mesh_error(e, spell_options(e.what(), OptionSpelling::Python));
    } catch (const InputFileError& e) {
      set_file_error(e, spell_options(e.what(), OptionSpelling::Python));
    } catch (const OutputFileError& e) {
      set_file_error(e, spell_options(e.what(), OptionSpelling::Python));

    } catch (const InputError& e) {
      // An input's option by Python's name too (a changed face-list file of `regions`).
      PyErr_SetObject(PyExc_ValueError,
                      message_text(spell_options(e.what(), OptionSpelling::Python)).ptr());
    } catch (const UsageError& e) {
      // Options by Python's names (the library names them by field, option_table.hpp).
      PyErr_SetObject(PyExc_ValueError,
                      message_text(spell_options(e.what(), OptionSpelling::Python)).ptr());
    } catch (const SimulationError& e) {
      PyErr_SetObject(PyExc_RuntimeError, message_text(e.what()).ptr());
    } catch (const std::runtime_error& e) {
      // An input the system had no resource to open (the limit of open files): the OSError of
      // its errno, as any file the system would not open; any other error to pybind11's own.
      const auto* file = dynamic_cast<const FileSystemFailure*>(&e);
      if (!file) throw;
      set_file_error(*file, e.what());
    }
  });
  // At the interpreter's exit, before it finalizes: cancel and wait for runs in other threads.
  py::module_::import("atexit").attr("register")(py::cpp_function(&stop_runs_at_exit));
  m.def("contract", &contract, py::arg("vertices"), py::arg("faces"), py::kw_only(),
        py::arg("callback") = py::none(), py::arg("stage") = py::none());
  m.def("option_table", &option_table);
  // The options a sweep leaves out of a job's id: the checkpoint's own list
  // (shellcontract/checkpoint.hpp).
  m.def("result_neutral_options", [] {
    std::vector<std::string> out;
    for (const std::string& name : result_neutral_options())
      out.push_back(python_option_name(name));
    return out;
  });
  m.def("resolve_options", &resolve_options);
  m.def("check", &check, py::arg("vertices"), py::arg("faces"));
  m.def("regions", &regions, py::arg("vertices"), py::arg("faces"));
  m.def("read_mesh", &read_mesh, py::arg("path"));
  // What `run` checks of an input before its run, for a result in the input's format: the
  // sweep's check of each mesh before any job runs, so that a job is not refused after the
  // sweep started for what run refuses of its mesh (a glTF's value float32 cannot hold).
  m.def(
      "check_run_input",
      [](const py::handle& path_arg) {
        const std::string path = path_argument(path_arg);
        without_gil([&] { check_run_input(path); });
      },
      py::arg("path"));
  // The library's list of the files a mesh file needs besides itself, for the sweep's output
  // check (sweep_needs.py), so that the sweep holds the rule the commands hold, not a copy of it.
  m.def(
      "input_dependencies",
      [](const std::string& path) {
        std::vector<std::pair<std::string, std::string>> out;
        for (const InputDependency& d : input_dependencies(path)) out.emplace_back(d.path, d.role);
        return out;
      },
      py::arg("path"));
  m.def("write_mesh", &write_mesh, py::arg("path"), py::arg("vertices"), py::arg("faces"), py::arg("like") = py::none());
}
