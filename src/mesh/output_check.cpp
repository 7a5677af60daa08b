#include "mesh/output_check.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <filesystem>

#include "mesh/file_safety.hpp"
#include "mesh/input_dependencies.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/file_error.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// The length of the name write_file_atomic gives the temporary of a file whose name has
/// `name_length` characters (create_exclusive_file: "." + the first 40 characters of
/// "<name>.tmp" + "." + 12 random ones). The probe has exactly the longer of the two, so that a
/// folder whose path is near PATH_MAX is refused only where the write would fail (a probe
/// padded to 60 refused folders that took the file, naming the file's name as too long).
std::size_t temporary_name_length(std::size_t name_length) {
  return 1 + std::min<std::size_t>(name_length + 4, 40) + 1 + 12;
}

/// The probe's hint, "shellcontract-probe", cut so that its name has `length` characters when
/// that is less than the whole hint's.
constexpr char PROBE_HINT[] = "shellcontract-probe";

/// Why a name of `name_length` characters, whose temporary's has `probe_length`, does not fit in
/// `folder` (ENAMETOOLONG): the name beyond the file system's NAME_MAX, or the path beyond
/// PATH_MAX.
std::string name_too_long(const std::string& folder, std::size_t name_length,
                          std::size_t probe_length) {
  const long name_max = ::pathconf(folder.c_str(), _PC_NAME_MAX);
  if (name_max > 0 && name_length > static_cast<std::size_t>(name_max))
    return "the file name is too long (" + std::to_string(name_length) +
           " bytes; the folder's file system allows " + std::to_string(name_max) + ")";
  const std::size_t needed = folder.size() + 1 + probe_length;
  if (needed >= PATH_MAX)
    return "the path is too long: the folder's path has " + std::to_string(folder.size()) +
           " bytes, and the file's temporary beside the file (" + std::to_string(probe_length) +
           " bytes of name) needs a path of " + std::to_string(needed) +
           ", over the system's limit (" + std::to_string(PATH_MAX - 1) +
           " bytes, PATH_MAX); give a shorter path, such as a relative "
           "one from a folder nearer the file";
  return "the name is too long for the folder " + quoted_path(folder) + " (" +
         file_error_text(ENAMETOOLONG) + ")";
}

/// "--checkpoint", "--resume", Python's "checkpoint", "resume", and their files' ("--checkpoint's
/// log").
bool is_checkpoint_option(const std::string& option) {
  std::string o = option;
  o.erase(0, o.find_first_not_of('-'));
  for (const std::string name : {"checkpoint", "resume"})
    if (o.compare(0, name.size(), name) == 0 && (o.size() == name.size() || o[name.size()] == '\''))
      return true;
  return false;
}

/// refuse_file's message.
std::string refusal(const std::string& option, const std::string& path, const std::string& why) {
  return option + " " + quoted_path(path) + ": " + why;
}

/// An existing output that may be replaced: a writable regular file (or a dangling link).
void check_existing(const FileIdentity& o) {
  if (!o.exists) return;
  if (S_ISDIR(o.file.st_mode)) refuse_file(o.option, o.path, "is a folder, not a file", EISDIR);
  // Refused for what it is, not by a failed call: a file error without an errno.
  if (!S_ISREG(o.file.st_mode))
    throw OutputFileError(
        refusal(
            o.option, o.path,
            "exists and is not a regular file (a device, FIFO or socket); it is never replaced"),
        FileSystemFailure::NO_ERRNO, o.path);
  if (::faccessat(AT_FDCWD, o.path.c_str(), W_OK, AT_EACCESS) != 0) {
    const int e = errno;
    refuse_file(o.option, o.path, "exists and is not writable (" + file_error_text(e) + ")", e);
  }
  // The rename that replaces it is refused in a sticky folder for a file that is neither the
  // caller's nor the folder owner's, writable or not: found here, not after the run.
  if (o.folder_known) {
    const std::string why = sticky_problem(o.file, o.folder);
    if (!why.empty()) refuse_file(o.option, o.path, why, EPERM);
  }
  // A file with no write permission bit at all is write-protected by its owner: refused for
  // every user, root too, for whom the access check above always succeeds (as `rm -i` and
  // `cp -i` ask before they replace one).
  if ((o.file.st_mode & (S_IWUSR | S_IWGRP | S_IWOTH)) == 0)
    refuse_file(o.option, o.path,
                "exists and is not writable (write-protected: no write permission is set)", EACCES);
}

}  // namespace

bool same_inode(const struct stat& a, const struct stat& b) {
  return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

bool same_file(const FileIdentity& a, const FileIdentity& b) {
  if (a.exists && b.exists && same_inode(a.file, b.file)) return true;
  return a.folder_known && b.folder_known && same_inode(a.folder, b.folder) && a.name == b.name;
}

std::string quoted_path(const std::string& s) { return "'" + printable(s, 1000) + "'"; }

FileIdentity identify_file(const std::string& option, const std::string& path) {
  FileIdentity id;
  id.option = option;
  id.path = path;
  id.target = resolve_output(path);
  const fs::path p(id.target.path);
  id.name = p.filename().string();
  id.folder_path = p.has_parent_path() ? p.parent_path().string() : std::string(".");
  id.exists = ::stat(path.c_str(), &id.file) == 0;
  id.folder_known = id.target.kind == OutputTarget::Kind::FILE &&
                    ::stat(id.folder_path.c_str(), &id.folder) == 0 && S_ISDIR(id.folder.st_mode);
  return id;
}

std::optional<std::string> folder_problem(const std::string& folder, std::size_t name_length,
                                          int* error_number) {
  int unused = 0;
  int& error = error_number ? *error_number : unused;
  struct stat st {};
  if (::stat(folder.c_str(), &st) != 0) {
    const int e = error = errno;
    if (e == ENOENT) return "the folder " + quoted_path(folder) + " does not exist";
    if (e == ENOTDIR) return "the folder " + quoted_path(folder) + " cannot exist: a part of its path is a file";
    return "the folder " + quoted_path(folder) + " cannot be used (" + file_error_text(e) + ")";
  }
  if (!S_ISDIR(st.st_mode)) {
    error = ENOTDIR;
    return quoted_path(folder) + " is a file, not a folder";
  }
  const std::size_t length = std::max(name_length, temporary_name_length(name_length));
  const std::size_t whole = 1 + (sizeof PROBE_HINT - 1) + 1 + 12;
  const std::string hint(PROBE_HINT, length < whole ? length - 14 : sizeof PROBE_HINT - 1);
  const RegisteredTemporary probe =
      create_registered_temporary(folder, hint, length);  // removed on SIGINT/SIGTERM too
  if (probe.fd < 0) {
    const int e = error = errno;
    if (e == ENAMETOOLONG) return name_too_long(folder, name_length, length);
    return "cannot create a file in the folder " + quoted_path(folder) + " (" + file_error_text(e) + ")";
  }
  ::close(probe.fd);
  ::unlink(probe.path.c_str());
  unregister_temporary(probe.slot);
  return std::nullopt;
}

void refuse_file(const std::string& option, const std::string& path, const std::string& why,
                 int error_number) {
  const std::string message = refusal(option, path, why);
  if (error_number != 0) throw OutputFileError(message, error_number, path);
  throw UsageError(message);
}

void check_output_identities(const std::vector<NamedFile>& outputs, const std::vector<NamedFile>& inputs,
                             std::vector<FileIdentity>& output_ids, std::vector<FileIdentity>& input_ids) {
  for (const NamedFile& in : inputs) {
    if (in.path.empty() || in.path.find('\0') != std::string::npos) continue;  // the reader says why
    FileIdentity id = identify_file(in.option, in.path);
    if (id.exists || id.folder_known) input_ids.push_back(std::move(id));
    if (in.option != "INPUT") continue;
    // The mesh's own files (a .mtl, a texture, a buffer): an output over one damages the input as
    // surely as one over the input, and one that creates a missing one changes what it means.
    for (const InputDependency& d : input_dependencies(in.path)) {
      if (d.path.empty() || d.path.find('\0') != std::string::npos) continue;
      FileIdentity dep = identify_file(in.option, d.path);
      dep.role = d.role;
      if (dep.exists || dep.folder_known) input_ids.push_back(std::move(dep));
    }
  }
  for (const NamedFile& o : outputs) {
    require_usable_path(o.path, o.option);
    FileIdentity id = identify_file(o.option, o.path);
    const std::string given_name = fs::path(o.path).filename().string();
    if (given_name.empty() || given_name == "." || given_name == ".." ||
        (id.target.kind == OutputTarget::Kind::FILE &&
         (id.name.empty() || id.name == "." || id.name == "..")))
      refuse_file(o.option, o.path, "names a folder, not a file");
    if (!id.target.problem.empty())
      refuse_file(o.option, o.path, id.target.problem, id.target.error);
    const bool stream = id.target.kind == OutputTarget::Kind::STREAM;
    // A checkpoint is read back (--resume) and has files beside it (FILE.log, .FILE.lock), which
    // beside /dev/stdout would be made in /dev.
    if (stream && is_checkpoint_option(o.option))
      refuse_file(
          o.option, o.path,
          "names a descriptor (standard output or error, /dev/fd/N); a checkpoint must be a "
          "file that a run can resume from");
    for (const FileIdentity& in : input_ids) {
      if (!same_file(id, in)) continue;
      if (!in.role.empty())
        refuse_file(o.option, o.path,
                    "is " + in.role + (in.path == o.path ? "" : " (" + quoted_path(in.path) + ")") +
                        "; the input needs this file, so it is never written: choose another name");
      refuse_file(o.option, o.path,
                  (in.option == "INPUT" ? std::string("is the input file")
                                        : "is the file of " + in.option) +
                      (in.path == o.path ? "" : " (" + quoted_path(in.path) + ")") +
                      "; choose another name");
    }
    for (const FileIdentity& other : output_ids)
      if (same_file(id, other))
        refuse_file(o.option, o.path,
                    "is also the file of " + other.option + " (" + quoted_path(other.path) +
                        "); each output needs its own file");
    if (stream) {
      // Written into, never replaced: nothing is created, so no folder to probe.
      int error = 0;
      const std::string why = stream_problem(id.target.fd, error);
      if (!why.empty()) refuse_file(o.option, o.path, why, error);
      output_ids.push_back(std::move(id));
      continue;
    }
    check_existing(id);
    int error = 0;
    if (const auto why = folder_problem(id.folder_path, id.name.size(), &error))
      refuse_file(o.option, o.path, *why, error);
    output_ids.push_back(std::move(id));
  }
}

void check_output_files(const std::vector<NamedFile>& outputs, const std::vector<NamedFile>& inputs) {
  std::vector<FileIdentity> output_ids, input_ids;
  check_output_identities(outputs, inputs, output_ids, input_ids);
}

}  // namespace shellcontract
