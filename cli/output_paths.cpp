#include "output_paths.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <filesystem>
#include <optional>
#include <system_error>

#include "export/frame_sequence_writer.hpp"
#include "mesh/file_safety.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract::cli {
namespace {

namespace fs = std::filesystem;

/// Longest name write_file_atomic gives a temporary (file_safety.cpp: "." + 40 characters of
/// the name + ".tmp." + 12 random ones, rounded up): the probe is at least this long.
constexpr std::size_t TEMPORARY_NAME_LENGTH = 60;

/// Where a path leads: the file itself (when it exists) and its directory entry (the folder's
/// identity and the name), so that two spellings of one file compare equal.
struct Identity {
  std::string option, path;
  bool exists = false;  ///< stat (links followed) succeeded
  struct stat file {};
  bool folder_known = false;  ///< the folder exists and is a folder
  struct stat folder {};
  std::string folder_path, name;
};

bool same_file(const struct stat& a, const struct stat& b) {
  return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

bool same(const Identity& a, const Identity& b) {
  if (a.exists && b.exists && same_file(a.file, b.file)) return true;
  return a.folder_known && b.folder_known && same_file(a.folder, b.folder) && a.name == b.name;
}

std::string quoted(const std::string& s) { return "'" + printable(s, 1000) + "'"; }

Identity identify(const std::string& option, const std::string& path) {
  Identity id;
  id.option = option;
  id.path = path;
  const fs::path p(path);
  id.name = p.filename().string();
  id.folder_path = p.has_parent_path() ? p.parent_path().string() : std::string(".");
  id.exists = ::stat(path.c_str(), &id.file) == 0;
  id.folder_known = ::stat(id.folder_path.c_str(), &id.folder) == 0 && S_ISDIR(id.folder.st_mode);
  return id;
}

/// Why `folder` cannot hold new files, or nothing. Probes by creating (exclusively) and removing
/// a file whose name has `name_length` characters.
std::optional<std::string> folder_problem(const std::string& folder, std::size_t name_length) {
  struct stat st {};
  if (::stat(folder.c_str(), &st) != 0) {
    const int e = errno;
    if (e == ENOENT) return "the folder " + quoted(folder) + " does not exist";
    if (e == ENOTDIR) return "the folder " + quoted(folder) + " cannot exist: a part of its path is a file";
    return "the folder " + quoted(folder) + " cannot be used (" + file_error_text(e) + ")";
  }
  if (!S_ISDIR(st.st_mode)) return quoted(folder) + " is a file, not a folder";
  const ExclusiveFile probe =
      create_exclusive_file(folder, "shellcontract-probe", std::max(name_length, TEMPORARY_NAME_LENGTH));
  if (probe.fd < 0) {
    const int e = errno;
    if (e == ENAMETOOLONG)
      return "the file name is too long (" + std::to_string(name_length) + " characters) for the folder " +
             quoted(folder);
    return "cannot create a file in the folder " + quoted(folder) + " (" + file_error_text(e) + ")";
  }
  const int slot = register_temporary(probe.path);  // removed on SIGINT/SIGTERM too
  ::close(probe.fd);
  ::unlink(probe.path.c_str());
  unregister_temporary(slot);
  return std::nullopt;
}

/// Whether `name` is <stem>_<digits>.<ext>, a frame file name of any width.
bool is_frame_name(const std::string& name, const PlannedFrames& f) {
  const std::string head = f.stem + "_", tail = "." + f.ext;
  if (name.size() <= head.size() + tail.size() || name.compare(0, head.size(), head) != 0 ||
      name.compare(name.size() - tail.size(), tail.size(), tail) != 0)
    return false;
  return std::all_of(name.begin() + static_cast<std::ptrdiff_t>(head.size()),
                     name.end() - static_cast<std::ptrdiff_t>(tail.size()),
                     [](unsigned char c) { return std::isdigit(c) != 0; });
}

[[noreturn]] void refuse(const std::string& option, const std::string& path, const std::string& why) {
  throw UsageError(option + " " + quoted(path) + ": " + why);
}

/// An existing output that may be replaced: a writable regular file (or a dangling link).
void check_existing(const Identity& o) {
  if (!o.exists) return;
  if (S_ISDIR(o.file.st_mode)) refuse(o.option, o.path, "is a folder, not a file");
  if (!S_ISREG(o.file.st_mode))
    refuse(o.option, o.path,
           "exists and is not a regular file (a device, FIFO or socket); it is never replaced");
  if (::faccessat(AT_FDCWD, o.path.c_str(), W_OK, AT_EACCESS) != 0) {
    const int e = errno;
    refuse(o.option, o.path, "exists and is not writable (" + file_error_text(e) + ")");
  }
}

/// The export folder: its identity when it exists, else where it will be created.
struct ExportFolder {
  bool exists = false;
  struct stat st {};
  Identity entry;  ///< the folder's own directory entry
};

ExportFolder check_export_folder(const PlannedFrames& f) {
  require_usable_path(f.dir, "--export-dir");
  ExportFolder out;
  out.entry = identify("--export-dir", f.dir);
  const std::size_t longest = frame_file_name("", f.stem, f.ext, f.max_frame, f.max_frame).size();
  if (::stat(f.dir.c_str(), &out.st) == 0) {
    if (!S_ISDIR(out.st.st_mode)) refuse("--export-dir", f.dir, "is a file, not a folder");
    out.exists = true;
    if (const auto why = folder_problem(f.dir, longest)) refuse("--export-dir", f.dir, *why);
    return out;
  }
  const int e = errno;
  if (e != ENOENT) refuse("--export-dir", f.dir, "cannot be used (" + file_error_text(e) + ")");
  // Created later, with its missing parents: the nearest existing folder must take them.
  fs::path missing = fs::path(f.dir).lexically_normal();
  if (missing.filename().empty()) missing = missing.parent_path();  // "dir/"
  fs::path parent = missing.parent_path();
  struct stat st {};
  while (!parent.empty() && ::stat(parent.c_str(), &st) != 0 && errno == ENOENT) {
    missing = parent;
    parent = parent.parent_path();
  }
  const std::string folder = parent.empty() ? std::string(".") : parent.string();
  if (const auto why = folder_problem(folder, std::max(missing.filename().string().size(), longest)))
    refuse("--export-dir", f.dir, *why);
  return out;
}

}  // namespace

void check_planned_outputs(const OutputPlan& plan) {
  std::vector<Identity> outputs, inputs;
  for (const PlannedOutput& in : plan.inputs) {
    if (in.path.empty() || in.path.find('\0') != std::string::npos) continue;  // the reader says why
    Identity id = identify(in.option, in.path);
    if (id.exists || id.folder_known) inputs.push_back(std::move(id));
  }
  for (const PlannedOutput& o : plan.outputs) {
    require_usable_path(o.path, o.option);
    Identity id = identify(o.option, o.path);
    if (id.name.empty() || id.name == "." || id.name == "..")
      refuse(o.option, o.path, "names a folder, not a file");
    for (const Identity& in : inputs)
      if (same(id, in))
        refuse(o.option, o.path,
               (in.option == "INPUT" ? std::string("is the input file") : "is the file of " + in.option) +
                   (in.path == o.path ? "" : " (" + quoted(in.path) + ")") + "; choose another name");
    for (const Identity& other : outputs)
      if (same(id, other))
        refuse(o.option, o.path,
               "is also the file of " + other.option + " (" + quoted(other.path) + "); each output needs its own file");
    check_existing(id);
    if (const auto why = folder_problem(id.folder_path, id.name.size())) refuse(o.option, o.path, *why);
    outputs.push_back(std::move(id));
  }
  if (plan.frames.dir.empty()) return;
  const PlannedFrames& f = plan.frames;
  const ExportFolder folder = check_export_folder(f);
  for (const std::vector<Identity>* group : {&outputs, &inputs})
    for (const Identity& id : *group) {
      if (!folder.exists && same(id, folder.entry))
        refuse(id.option, id.path, "is also the --export-dir folder " + quoted(f.dir));
      if (folder.exists && id.folder_known && same_file(id.folder, folder.st) && is_frame_name(id.name, f))
        refuse(id.option, id.path,
               "has the name of an exported frame in --export-dir " + quoted(f.dir) +
                   " (<output name>_<frame>." + f.ext + "); choose another name or folder");
    }
}

ExportFolderLock::~ExportFolderLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

std::unique_ptr<ExportFolderLock> prepare_export_folder(const PlannedFrames& f) {
  if (f.dir.empty()) return nullptr;
  std::error_code ec;
  const bool created = fs::create_directories(f.dir, ec);
  if (ec)
    refuse("--export-dir", f.dir, "cannot create the folder (" + file_error_text(ec.value()) + ")");
  const auto undo = [&] {
    if (created) fs::remove(f.dir, ec);  // only the (empty) folder made here
  };
  const int fd = ::open(f.dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) {
    const int e = errno;
    undo();
    refuse("--export-dir", f.dir, "cannot open the folder (" + file_error_text(e) + ")");
  }
  auto lock = std::make_unique<ExportFolderLock>(fd);
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0)
    refuse("--export-dir", f.dir,
           "another shellcontract run is writing its frames into this folder; choose another --export-dir");
  for (const auto& e : fs::directory_iterator(f.dir, ec)) {
    const std::string name = e.path().filename().string();
    if (is_frame_name(name, f))
      refuse("--export-dir", f.dir,
             "already holds frame files of another run (" + quoted(name) +
                 "); remove them or choose another --export-dir, so that two runs' frames never mix");
  }
  if (ec) refuse("--export-dir", f.dir, "cannot list the folder (" + file_error_text(ec.value()) + ")");
  return lock;
}

}  // namespace shellcontract::cli
