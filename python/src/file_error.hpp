// shellcontract.FileError and its subclasses: the Python face of the library's file errors
// (shellcontract/file_error.hpp), each the OSError subclass Python's own open() would raise for
// its errno and a ValueError as well, the class these errors had before.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

#include "shellcontract/file_error.hpp"

namespace shellcontract::python {

namespace py = pybind11;

/// Creates the classes and adds them to `m` (_core): FileError (OSError and ValueError; the
/// package re-exports it), and FileNotFoundError, PermissionError, IsADirectoryError,
/// NotADirectoryError, FileExistsError and BlockingIOError, each a FileError and the builtin
/// class of its name.
/// Once, at the module's import.
void register_file_errors(py::module_& m);

/// Sets the pending Python error to the class of e.error_number() (FileError for an errno none
/// of the subclasses stands for) with errno (None for NO_ERRNO), strerror = `message` and
/// filename = e.path() (the exception translator's part; the GIL is held there).
void set_file_error(const FileSystemFailure& e, const std::string& message);

}  // namespace shellcontract::python
