// shellcontract.MeshError: the Python face of the library's FaceListError (a mesh refused because
// of particular faces), a ValueError whose `faces` lists their triangle indices.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

#include "shellcontract/face_error.hpp"

namespace shellcontract::python {

namespace py = pybind11;

/// Creates the exception class and adds it to `m` as MeshError (named shellcontract.MeshError,
/// the package re-exports it). Once, at the module's import.
void register_mesh_error(py::module_& m);

/// Sets the pending Python error to a MeshError with `message` and e.faces() (the exception
/// translator's part for a FaceListError; the GIL is held there).
void set_mesh_error(const FaceListError& e, const std::string& message);

}  // namespace shellcontract::python
