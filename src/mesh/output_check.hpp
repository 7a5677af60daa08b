// The pieces of check_output_files (shellcontract/output_files.hpp) that the CLI's check of its
// export folder uses too (cli/output_paths.cpp): file identities and the folder probe.
#pragma once

#include <sys/stat.h>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "mesh/output_target.hpp"
#include "shellcontract/output_files.hpp"

namespace shellcontract {

/// Where a path leads: the file itself (when it exists) and its directory entry (the folder's
/// identity and the name), so that two spellings of one file compare equal.
struct FileIdentity {
  std::string option, path;
  bool exists = false;  ///< stat (links followed) succeeded
  struct stat file {};
  bool folder_known = false;  ///< the folder exists and is a folder
  struct stat folder {};
  std::string folder_path, name;
  /// For a file the input needs (input_dependencies.hpp): what it is to the input; else empty.
  std::string role;
  /// Where a write would land (output_target.hpp): `folder_path` and `name` are those of the
  /// link's target for a symbolic link; a descriptor (/dev/stderr) has no folder to compare.
  OutputTarget target;
};

FileIdentity identify_file(const std::string& option, const std::string& path);

/// The same device and inode.
bool same_inode(const struct stat& a, const struct stat& b);
/// The same file, or the same name in the same folder.
bool same_file(const FileIdentity& a, const FileIdentity& b);

/// `s` in single quotes, printable.
std::string quoted_path(const std::string& s);

/// Why `folder` cannot hold new files, or nothing. Probes by creating (exclusively) and removing
/// a file whose name has `name_length` characters (at least a temporary's). `error_number`, when
/// given, gets the errno of the call that failed (ENOTDIR for a file in the folder's place).
std::optional<std::string> folder_problem(const std::string& folder, std::size_t name_length,
                                          int* error_number = nullptr);

/// @throws UsageError "OPTION 'PATH': WHY"; an OutputFileError about `path` with a nonzero
///         `error_number` (the errno of the file system's refusal)
[[noreturn]] void refuse_file(const std::string& option, const std::string& path,
                              const std::string& why, int error_number = 0);

/// check_output_files, keeping the identities of the outputs and of the inputs that exist (or
/// whose folder does) for a caller's own checks. The files an input named "INPUT" needs (its
/// input_dependencies, with their role) are among the inputs.
void check_output_identities(const std::vector<NamedFile>& outputs, const std::vector<NamedFile>& inputs,
                             std::vector<FileIdentity>& output_ids, std::vector<FileIdentity>& input_ids);

}  // namespace shellcontract
