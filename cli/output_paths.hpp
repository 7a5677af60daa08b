// The one decision, for every command, of which files it may write (docs/design/output-safety.md),
// made before any work: a run must not fail after minutes of simulation because its output
// folder is missing, nor write over its own input, however the two are spelled.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "json_writer.hpp"
#include "mesh/file_safety.hpp"
#include "shellcontract/output_files.hpp"

namespace shellcontract::cli {

/// One file a command reads or writes and the option that names it (check_output_files).
using PlannedOutput = NamedFile;

/// The frame files of --export-dir: DIR/<stem>_<frame>.<ext>, the frame zero-padded to the
/// digits of max_frame (frame_file_name). Any frame from 0 to max_frame may be written (a run
/// that stops early writes its last frame), so every one of those names is checked.
struct PlannedFrames {
  std::string dir;  ///< empty: no frame files
  std::string stem, ext;
  int max_frame = 0;
};

/// What a command will write and what it reads.
struct OutputPlan {
  std::vector<PlannedOutput> outputs;
  std::vector<PlannedOutput> inputs;
  PlannedFrames frames;
};

/// The result's format, from -o's extension: .off, .obj, .ply or .stl for any input; .glb or
/// .gltf only for an input of that format, and then without frames (`frames_dir`: --export-dir).
/// `gltf_option`: the command has --gltf (run), which the refusal of a glTF -o then suggests.
/// @throws UsageError naming -o (or --export-dir) and what is expected (exit code 1)
void check_result_format(const std::string& input, const std::string& output, bool frames_dir,
                         bool gltf_option);

/// check_output_files (the library's, shared with Python) and the export folder's frames: no
/// frame name may be an input or an output, and the folder (or the nearest existing parent that
/// will hold it) must take new files. Creates nothing that stays (the export folder is made by
/// prepare_export_folder).
/// @throws UsageError naming the option, the path and the reason (exit code 1)
void check_planned_outputs(const OutputPlan& plan);

/// Held while a run writes frames into its export folder: a second run with the same folder is
/// refused while the first runs (an advisory lock on the folder). A folder that
/// prepare_export_folder created is removed again when the lock ends if it is still empty: a
/// run refused or failed before its first frame (a bad mesh, a bad face list) creates nothing.
class ExportFolderLock {
 public:
  ExportFolderLock(int fd, std::string dir, bool created)
      : fd_(fd), dir_(std::move(dir)), created_(created) {}
  ~ExportFolderLock();
  ExportFolderLock(const ExportFolderLock&) = delete;
  ExportFolderLock& operator=(const ExportFolderLock&) = delete;

 private:
  int fd_;
  std::string dir_;
  bool created_;
};

/// After check_planned_outputs: creates the export folder if missing, locks it, and refuses it
/// when frame files of this name (<stem>_<digits>.<ext>) are already there, from another run:
/// two runs never mix their frames. Nothing is created when the answer is no (the folder made
/// here is removed again).
/// @throws UsageError (exit code 1)
std::unique_ptr<ExportFolderLock> prepare_export_folder(const PlannedFrames& frames);

/// The frame files of this name in the export folder (0 without one): after
/// prepare_export_folder, all of them this run's, for a run that ends before its outputs are
/// written to say what it leaves (a rerun is refused while they are there).
std::size_t count_frame_files(const PlannedFrames& frames);

/// What became of each output at the end of a run: "written", or "failed: why" (the final
/// message and the summary's "outputs" name each one).
class OutputStatus {
 public:
  void add(std::string option, std::string path, std::string state) {
    if (state.rfind("written", 0) != 0) failed_ = true;
    rows_.push_back({std::move(option), std::move(path), std::move(state)});
  }
  /// A row that does not fail the run: a checkpoint that could not be saved (the run goes on
  /// without it, and its result is whole).
  void note(std::string option, std::string path, std::string state) {
    rows_.push_back({std::move(option), std::move(path), std::move(state)});
  }
  bool failed() const { return failed_; }
  /// One line per output: "  OPTION PATH: STATE".
  std::string text() const {
    std::string t;
    for (const Row& r : rows_) t += "  " + r.option + " " + printable(r.path) + ": " + r.state + "\n";
    return t;
  }
  /// {"OPTION": "STATE", ...}
  JsonObject json() const {
    JsonObject o;
    for (const Row& r : rows_) o.add(r.option, r.state);
    return o;
  }

 private:
  struct Row {
    std::string option, path, state;
  };
  std::vector<Row> rows_;
  bool failed_ = false;
};

}  // namespace shellcontract::cli
