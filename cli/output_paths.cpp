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
#include <system_error>

#include "command_line.hpp"
#include "export/frame_sequence_writer.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/formats.hpp"
#include "mesh/output_check.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract::cli {

void check_result_format(const std::string& input, const std::string& output, bool frames_dir,
                         bool gltf_option) {
  // An existing -o that is no regular file (/dev/null, a FIFO, a folder) is refused for what it
  // is, with check_planned_outputs' words, before its name is read: /dev/null has no extension,
  // and "no file extension" would send the user looking in the wrong place.
  struct stat st {};
  if (output.find('\0') == std::string::npos && ::stat(output.c_str(), &st) == 0 &&
      !S_ISREG(st.st_mode)) {
    std::vector<FileIdentity> output_ids, input_ids;
    check_output_identities({{"-o", output}}, {}, output_ids, input_ids);
  }
  const std::string ext = lower_extension(output);
  const bool gltf_output = is_mesh_format(ext, &MeshFormat::gltf);
  if (!is_mesh_format(ext, &MeshFormat::plain_writer) && !gltf_output)
    throw UsageError("-o " + quoted_path(output) +
                     (ext.empty() ? std::string(": no file extension to name the mesh format")
                                  : ": unknown mesh format '." + printable(ext) + "'") +
                     " (expected " + extension_list(&MeshFormat::plain_writer, ".", ", ") +
                     ", or " + extension_list(&MeshFormat::gltf, ".", " / ") +
                     " for an input of that format)");
  // A glTF result is the input glTF with new positions (its document): there is no glTF writer
  // of a bare mesh, and frames would be one whole file each (--gltf animates the run instead).
  if (gltf_output && lower_extension(input) != ext)
    throw UsageError("-o " + quoted_path(output) + ": a ." + ext +
                     " result is written only for a ." + ext +
                     " input (the input with new positions)" +
                     (gltf_option ? "; for a glTF of the run, use --gltf FILE.glb" : ""));
  if (gltf_output && frames_dir)
    throw UsageError("--export-dir: frames are not written as ." + ext +
                     " files; use --gltf FILE.glb for the frames");
}

namespace {

namespace fs = std::filesystem;

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

/// The export folder: its identity when it exists, else where it will be created.
struct ExportFolder {
  bool exists = false;
  struct stat st {};
  FileIdentity entry;  ///< the folder's own directory entry
};

ExportFolder check_export_folder(const PlannedFrames& f) {
  require_usable_path(f.dir, "--export-dir");
  ExportFolder out;
  out.entry = identify_file("--export-dir", f.dir);
  const std::size_t longest = frame_file_name("", f.stem, f.ext, f.max_frame, f.max_frame).size();
  if (::stat(f.dir.c_str(), &out.st) == 0) {
    if (!S_ISDIR(out.st.st_mode)) refuse_file("--export-dir", f.dir, "is a file, not a folder");
    out.exists = true;
    if (const auto why = folder_problem(f.dir, longest)) refuse_file("--export-dir", f.dir, *why);
    return out;
  }
  const int e = errno;
  if (e != ENOENT) refuse_file("--export-dir", f.dir, "cannot be used (" + file_error_text(e) + ")");
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
    refuse_file("--export-dir", f.dir, *why);
  return out;
}

}  // namespace

void check_planned_outputs(const OutputPlan& plan) {
  std::vector<FileIdentity> outputs, inputs;
  check_output_identities(plan.outputs, plan.inputs, outputs, inputs);
  if (plan.frames.dir.empty()) return;
  const PlannedFrames& f = plan.frames;
  const ExportFolder folder = check_export_folder(f);
  for (const std::vector<FileIdentity>* group : {&outputs, &inputs})
    for (const FileIdentity& id : *group) {
      if (!id.role.empty() && ((!folder.exists && same_file(id, folder.entry)) ||
                               (folder.exists && id.folder_known &&
                                same_inode(id.folder, folder.st) && is_frame_name(id.name, f))))
        refuse_file("--export-dir", f.dir,
                    "a frame (or the folder) would be " + quoted_path(id.path) + ", " + id.role +
                        "; the input needs this file: choose another name or folder");
      if (!folder.exists && same_file(id, folder.entry))
        refuse_file(id.option, id.path, "is also the --export-dir folder " + quoted_path(f.dir));
      if (folder.exists && id.folder_known && same_inode(id.folder, folder.st) && is_frame_name(id.name, f))
        refuse_file(id.option, id.path,
               "has the name of an exported frame in --export-dir " + quoted_path(f.dir) +
                   " (<output name>_<frame>." + f.ext + "); choose another name or folder");
    }
}

ExportFolderLock::~ExportFolderLock() {
  // Removed while still locked, so that no second run takes the folder in between.
  std::error_code ec;
  if (created_ && fs::is_empty(dir_, ec) && !ec) fs::remove(dir_, ec);  // removes only an empty folder
  if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

std::unique_ptr<ExportFolderLock> prepare_export_folder(const PlannedFrames& f) {
  if (f.dir.empty()) return nullptr;
  std::error_code ec;
  const bool created = fs::create_directories(f.dir, ec);
  if (ec)
    refuse_file("--export-dir", f.dir, "cannot create the folder (" + file_error_text(ec.value()) + ")");
  const int fd = ::open(f.dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) {
    const int e = errno;
    if (created) fs::remove(f.dir, ec);  // only the (empty) folder made here
    refuse_file("--export-dir", f.dir, "cannot open the folder (" + file_error_text(e) + ")");
  }
  // From here a refusal below ends the lock, which removes the folder again if it made it.
  auto lock = std::make_unique<ExportFolderLock>(fd, f.dir, created);
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0)
    refuse_file("--export-dir", f.dir,
           "another shellcontract run is writing its frames into this folder; choose another --export-dir");
  for (const auto& e : fs::directory_iterator(f.dir, ec)) {
    const std::string name = e.path().filename().string();
    if (is_frame_name(name, f))
      refuse_file("--export-dir", f.dir,
             "already holds frame files of another run (" + quoted_path(name) +
                 "; an interrupted run leaves the frames it finished); remove them or choose another "
                 "--export-dir, so that two runs' frames never mix");
  }
  if (ec) refuse_file("--export-dir", f.dir, "cannot list the folder (" + file_error_text(ec.value()) + ")");
  return lock;
}

std::size_t count_frame_files(const PlannedFrames& f) {
  if (f.dir.empty()) return 0;
  std::size_t n = 0;
  try {  // called when memory ran out: what was counted, should it run out again
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(f.dir, ec))
      n += is_frame_name(e.path().filename().string(), f);
  } catch (const std::exception&) {
  }
  return n;
}

}  // namespace shellcontract::cli
