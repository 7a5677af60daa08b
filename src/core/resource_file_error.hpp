// An input the system had no resource to open (private: the readers throw it, the CLI and the
// Python module see a std::runtime_error that is a FileSystemFailure).
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

#include "shellcontract/file_error.hpp"

namespace shellcontract {

/// An input that could not be opened for want of a resource, not for anything about the file:
/// the process's or the system's limit of open files (EMFILE, ENFILE: `ulimit -n`) or kernel
/// memory (ENOMEM). A runtime_error, not an InputError: exit code 3, as a thread or memory the
/// system refused (docs/cli.md "Exit codes"), where 2 would tell a script to fix the file; Python
/// raises the OSError of its errno, as for any file the system would not open. A checkpoint's
/// readers turn it into an InputFileError (exit code 2, a checkpoint not read: sim/checkpoint.cpp).
class ResourceFileError : public std::runtime_error, public FileSystemFailure {
 public:
  ResourceFileError(const std::string& message, int error_number, std::string path)
      : std::runtime_error(message), FileSystemFailure(error_number, std::move(path)) {}
};

}  // namespace shellcontract
