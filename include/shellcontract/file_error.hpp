// Errors of the file system, with the errno of the call that failed: a front end that reports
// them in its own terms (the Python module raises the matching OSError: FileNotFoundError,
// PermissionError, ...) reads the number and the file instead of parsing the message. The CLI
// prints what() and exits with the code of the error each one is, as before. Thrown by the
// readers (read_input_mesh, read_mesh_document, load_checkpoint, read_region_file: an
// InputFileError) and the writers and checks of outputs (write_mesh_atomic, write_file_atomic,
// check_output_files, lock_checkpoint: an OutputFileError); any of them may throw a plain
// InputError or UsageError for a file that can be opened but not used.
#pragma once

#include <string>
#include <utility>

#include "shellcontract/error.hpp"

namespace shellcontract {

/// What a file error carries besides its message: the errno of the call that failed (EISDIR
/// for a folder where a file is needed, as open() says) and the path it was about, as the caller
/// gave it. Where no call failed, the errno the OS would give for the same refusal: EFBIG for an
/// input over its size limit, EWOULDBLOCK for a checkpoint whose lock another run holds; and
/// NO_ERRNO for a path refused for what it is (a device, a FIFO or a socket: open() would take
/// it, so no errno says why; Python's shutil refuses a FIFO with an OSError without one too).
class FileSystemFailure {
 public:
  static constexpr int NO_ERRNO = 0;

  FileSystemFailure(int error_number, std::string path)
      : error_number_(error_number), path_(std::move(path)) {}

  int error_number() const { return error_number_; }
  const std::string& path() const { return path_; }

 private:
  int error_number_;
  std::string path_;
};

/// An input that cannot be read: missing, a folder, a device, FIFO or socket, not permitted, too
/// large, a read error (exit code 2, as any InputError; a file that can be read but is malformed
/// is a plain InputError).
class InputFileError : public InputError, public FileSystemFailure {
 public:
  InputFileError(const std::string& message, int error_number, std::string path)
      : InputError(message), FileSystemFailure(error_number, std::move(path)) {}
};

/// An output that cannot be written: its folder missing or not writable, a folder, device, FIFO
/// or socket in its place, the disk full, a checkpoint locked by another run (exit code 1, as any
/// UsageError).
class OutputFileError : public UsageError, public FileSystemFailure {
 public:
  OutputFileError(const std::string& message, int error_number, std::string path)
      : UsageError(message), FileSystemFailure(error_number, std::move(path)) {}
};

/// Throws an InputError with `message` about the same problem as `cause`: an InputFileError
/// keeps its errno and path (for a caller that puts its own words around a reader's message).
[[noreturn]] inline void rethrow_input_error_as(const InputError& cause,
                                                const std::string& message) {
  if (const auto* f = dynamic_cast<const FileSystemFailure*>(&cause))
    throw InputFileError(message, f->error_number(), f->path());
  throw InputError(message);
}

}  // namespace shellcontract
