// shellcontract.MeshError (mesh_error.hpp): a ValueError subclass, so that `except ValueError`
// still catches every refused mesh, with the faces as data for callers that number faces their
// own way (the Blender add-on maps them to its polygons).
#include "mesh_error.hpp"

#include <Python.h>

#include "arrays.hpp"

namespace shellcontract::python {
namespace {

/// The class object, alive as long as the interpreter (the module holds a reference too).
PyObject* mesh_error_type = nullptr;

constexpr const char* MESH_ERROR_DOC =
    "The mesh cannot be used because of some of its faces (a ValueError).\n\n"
    "faces: list of int, the 0-based indices into the faces array the message is about, in the\n"
    "order the message names them (for a non-manifold vertex: the faces around it, by index),\n"
    "all of them even where the message shortens its list with '...'. Other refused meshes (a\n"
    "non-finite coordinate, an isolated vertex, no volume) raise a plain ValueError.";

}  // namespace

void register_mesh_error(py::module_& m) {
  if (mesh_error_type == nullptr) {
    mesh_error_type = PyErr_NewExceptionWithDoc("shellcontract.MeshError", MESH_ERROR_DOC, PyExc_ValueError, nullptr);
    if (mesh_error_type == nullptr) throw py::error_already_set();
  }
  m.attr("MeshError") = py::reinterpret_borrow<py::object>(mesh_error_type);
}

void set_mesh_error(const FaceListError& e, const std::string& message) {
  py::list faces;
  for (const std::size_t f : e.faces()) faces.append(py::int_(f));
  py::object error = py::reinterpret_borrow<py::object>(mesh_error_type)(message_text(message));
  error.attr("faces") = faces;
  PyErr_SetObject(mesh_error_type, error.ptr());
}

}  // namespace shellcontract::python
