// shellcontract.FileError (file_error.hpp). Each class is an OSError, so that `except OSError`
// and `except FileNotFoundError` catch a missing file as they do from Python's own open(), and
// a ValueError, so that code written when every library error was a ValueError still catches
// it (as io.UnsupportedOperation is both OSError and ValueError).
#include "file_error.hpp"

#include <Python.h>

#include <cerrno>

#include "arrays.hpp"

namespace shellcontract::python {
namespace {

constexpr const char* FILE_ERROR_DOC =
    "A file could not be read or written (an OSError and a ValueError).\n\n"
    "errno: the errno of the call that failed (EISDIR for a folder where a file is needed;\n"
    "EFBIG for an input over its size limit; EWOULDBLOCK for a checkpoint another run holds\n"
    "locked); None for a device, FIFO or socket given as an input or in an output's place,\n"
    "refused for what it is rather than by a failed call.\n"
    "filename: the file (for a glTF's missing external buffer, the buffer); strerror and\n"
    "str(): the library's message, the CLI's. Raised as the subclass for its errno where there\n"
    "is one (FileNotFoundError, PermissionError, IsADirectoryError, NotADirectoryError,\n"
    "FileExistsError, BlockingIOError: each also the builtin class of that name). A file that\n"
    "can be read but whose content is refused is a plain ValueError.";

/// A subclass: the builtin it derives from, by name, and the errno values it stands for
/// (Python's own mapping, Objects/exceptions.c). The class objects live as long as the
/// interpreter.
struct Subclass {
  const char* name;
  int errno_a, errno_b;
  PyObject* type;
};

PyObject* file_error_type = nullptr;
Subclass subclasses[] = {
    {"FileNotFoundError", ENOENT, ENOENT, nullptr},
    {"PermissionError", EACCES, EPERM, nullptr},
    {"IsADirectoryError", EISDIR, EISDIR, nullptr},
    {"NotADirectoryError", ENOTDIR, ENOTDIR, nullptr},
    {"FileExistsError", EEXIST, EEXIST, nullptr},
    {"BlockingIOError", EAGAIN, EWOULDBLOCK, nullptr},  // a lock another run holds
};

/// `qualified_name`: where pickle finds the class again ("module.name").
PyObject* new_class(const std::string& qualified_name, const char* doc, const py::tuple& bases) {
  PyObject* type = PyErr_NewExceptionWithDoc(qualified_name.c_str(), doc, bases.ptr(), nullptr);
  if (type == nullptr) throw py::error_already_set();
  return type;
}

}  // namespace

void register_file_errors(py::module_& m) {
  if (file_error_type == nullptr) {
    file_error_type =
        new_class("shellcontract.FileError", FILE_ERROR_DOC,
                  py::make_tuple(py::handle(PyExc_OSError), py::handle(PyExc_ValueError)));
    py::handle base(file_error_type);
    // The library's message, as str() of its other errors; OSError's "[Errno 2] MESSAGE: 'FILE'"
    // would name the file twice. An instance made without a strerror reads as an OSError.
    base.attr("__str__") = py::cpp_function(
        [](py::handle self) -> py::object {
          const py::object text = self.attr("strerror");
          return text.is_none() ? py::handle(PyExc_OSError).attr("__str__")(self) : py::str(text);
        },
        py::name("__str__"), py::is_method(base));
    const py::dict builtins = py::module_::import("builtins").attr("__dict__");
    for (Subclass& s : subclasses) {
      // FileError first: its __str__ before OSError's. In _core, not the package: there the
      // names would hide the builtins from the package's own code.
      s.type = new_class(std::string("shellcontract._core.") + s.name, nullptr,
                         py::make_tuple(base, builtins[s.name]));
    }
  }
  m.attr("FileError") = py::reinterpret_borrow<py::object>(file_error_type);
  for (const Subclass& s : subclasses) m.attr(s.name) = py::reinterpret_borrow<py::object>(s.type);
}

void set_file_error(const FileSystemFailure& e, const std::string& message) {
  PyObject* type = file_error_type;
  for (const Subclass& s : subclasses)
    if (e.error_number() == s.errno_a || e.error_number() == s.errno_b) type = s.type;
  // No errno (a device, FIFO or socket refused for what it is): None, as OSError's own
  // errno when no call failed.
  const py::object error_number = e.error_number() == FileSystemFailure::NO_ERRNO
                                      ? py::object(py::none())
                                      : py::object(py::int_(e.error_number()));
  const py::object error = py::reinterpret_borrow<py::object>(type)(
      error_number, message_text(message), file_name_text(e.path()));
  PyErr_SetObject(type, error.ptr());
}

}  // namespace shellcontract::python
