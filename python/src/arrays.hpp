// numpy arrays <-> the library's Mesh and Positions for the Python module, and file names.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>

#include "shellcontract/mesh.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract::python {

namespace py = pybind11;

/// What the messages of a refused array input call it (read_input_mesh names the file there).
inline constexpr const char* ARRAY_INPUT_NAME = "input arrays";

/// Builds a checked mesh from vertices (N by 3, float64 used in place when C-contiguous, other
/// real types converted) and faces (M by 3, int32 or int64 used in place when C-contiguous, other
/// integer types converted), with mesh_from_arrays' checks (shellcontract/mesh_io.hpp).
/// @throws py::type_error / py::value_error for a wrong dtype or shape; InputError for a mesh
///         the library refuses (ValueError in Python)
Mesh mesh_from_numpy(const py::handle& vertices, const py::handle& faces, InputReport* report = nullptr,
                     bool reorient = true);

/// The positions as a new N by 3 float64 array.
py::array_t<double> positions_to_numpy(const Positions& x);

/// The mesh's faces as a new M by 3 int64 array, corners in the mesh's order (as written), by
/// the input's vertices (input_faces: a mesh welded along its seams gives its copies back).
py::array_t<std::int64_t> faces_to_numpy(const Mesh& mesh);

/// The positions of an N by 3 array as the library's Positions (a copy).
Positions positions_from_numpy(const py::handle& vertices);

/// A file path from Python: str or os.PathLike (bytes too), as os.fspath takes it; TypeError for
/// anything else (None must not become a file named "None"), ValueError for a NUL byte. `what`
/// names the argument in the messages ("path", "checkpoint"). The bytes are os.fsencode's, as
/// Python's open() uses them: a name that is not UTF-8 (os.listdir gives it as a str with
/// surrogate escapes) names the same file.
std::string path_argument(const py::handle& path, const std::string& what = "path");

/// A str as the bytes of a file name (os.fsencode): an option's text that may name a file.
std::string file_name_bytes(const py::handle& text);

/// The inverse (os.fsdecode): bytes that are not UTF-8 as surrogate escapes.
py::str file_name_text(const std::string& bytes);

/// A message for a Python exception: UTF-8, a byte that is not (a file name's) as \xNN.
/// PyErr_SetString and py::str decode strictly: the whole message was lost to a
/// UnicodeDecodeError, or became an empty ValueError.
py::str message_text(const std::string& message);

}  // namespace shellcontract::python
