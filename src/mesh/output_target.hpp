// Where a write to an output path lands (docs/design/output-safety.md, "Symbolic links and
// streams"): the check before a run (output_check.cpp) and every writer (write_file_atomic) ask
// this one function, so a command, the library and the Python module treat a link alike.
#pragma once

#include <sys/stat.h>

#include <string>

namespace shellcontract {

struct OutputTarget {
  /// FILE: a file replaced atomically (`path`). STREAM: a descriptor of this process, written
  /// straight into and never replaced (`fd`).
  enum class Kind { FILE, STREAM } kind = Kind::FILE;
  /// FILE: the file to replace: the path as given, or where its chain of symbolic links ends
  /// (the link is kept, its target replaced; the target may not exist yet).
  std::string path;
  int fd = -1;
  /// Why the path is not written at all (a link of another user in a sticky folder, a loop of
  /// links), with its errno; empty when it may be.
  std::string problem;
  int error = 0;
};

/// Follows the symbolic links of `path`'s last component, one at a time (nothing is opened):
/// a link in this process's /proc/PID/fd (or /proc/PID/task/TID/fd) folder is the descriptor it
/// names, reached through /dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N or a link of the
/// user's to one of them: a STREAM. Any other chain ends at the file it names (FILE). A link
/// that the kernel's fs.protected_symlinks would not follow (in a sticky, world-writable folder,
/// owned neither by the caller nor by the folder's owner) is not followed here either: problem.
OutputTarget resolve_output(const std::string& path);

/// The file a write to `path` replaces: resolve_output's FILE path (a link's target), else `path`
/// itself (a stream, a refused link: the writer says why). Files named after an output (a
/// checkpoint's lock, log and history) are named after this one.
std::string replaced_file(const std::string& path);

/// Why a STREAM's descriptor cannot take a write (not open, open for reading only), or empty.
std::string stream_problem(int fd, int& error_number);

/// Why the file `st` in the folder `folder` (both stat results) cannot be replaced by a rename
/// even though it may be writable: the folder is sticky (/tmp, a shared scratch folder) and
/// neither the file nor the folder is the caller's, who lacks CAP_FOWNER (root has it). Empty
/// when it can.
std::string sticky_problem(const struct stat& st, const struct stat& folder);

}  // namespace shellcontract
