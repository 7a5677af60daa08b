// Runs that resume to the same bytes (docs/design/sweeps.md, "Checkpoints"): a run's whole state
// between two steps saved to one file, atomically, and a run continued from that file that takes
// the same steps as the run that wrote it. A checkpoint names the tool's version, a hash of the
// input mesh, a hash of every other file the run reads (a face list, a weights file) and the
// run's options; one of another version, input or options is refused, saying which. The file's
// contents are the library's own: a caller reads and writes them only here.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract {

struct Checkpoint;  ///< a saved run, read by load_checkpoint
struct SavedRun;    ///< a run's state at a step boundary, handed to RunCheckpointer::save

/// CheckpointInfo::input of a run of a mesh given as arrays (Python's vertices and faces): there
/// is no file to resume it from, so a resumed run must be given the mesh.
inline constexpr const char* ARRAYS_INPUT = "<arrays>";

/// A 64-bit hash of a mesh's vertex positions (their bits) and faces (vertex ids in order): what
/// a checkpoint records of its input.
std::uint64_t mesh_hash(const Mesh& mesh);

/// Reads a checkpoint file.
/// @throws InputError naming the file for a missing, truncated or corrupted checkpoint, or one
///         whose log or volume history beside it (formats 4 and 5, CheckpointLogFile) is
///         missing, shorter than recorded or not the one it was saved with
std::shared_ptr<const Checkpoint> load_checkpoint(const std::string& path);

/// The frame the checkpoint was saved at (the resumed run goes on with the next one).
int checkpoint_frame(const Checkpoint& c);
/// The caller's log of the frames so far, as the saving run gave it (CheckpointInfo::log).
const std::string& checkpoint_log(const Checkpoint& c);
/// CheckpointInfo::save_every of the saving run (0: only on a signal, or a checkpoint written
/// before it was recorded).
int checkpoint_save_every(const Checkpoint& c);

/// The options a resumed run runs with: the checkpoint's given options, then `command_line`'s
/// given ones on top (its threads, or the same values again). A face-list or weights file is
/// compared by its contents (check_checkpoint_files), not by its path, as the mesh is.
/// @throws UsageError naming every option whose value differs from the checkpoint's, or one the
///         checkpoint's run was given as arrays (RunInput::arrays) that `command_line` lacks
RunOptions options_for_resume(const Checkpoint& c, const RunOptions& command_line);

/// Refuses a checkpoint of another version or another input, saying which.
/// @param input_name  how the message names `mesh` (a path, "the vertices and faces given")
/// @throws InputError
void check_checkpoint_input(const Checkpoint& c, const std::string& input_name, const Mesh& mesh);

/// A file a run reads besides the mesh (--regions FILE, --region-weights FILE), or the numbers
/// given in its place (Python's arrays), with a hash of its contents: what a checkpoint records
/// of it, so that a resumed run refuses a file changed in between.
struct RunInput {
  std::string option;      ///< the option's field: "regions" or "region_weights"
  std::string file;        ///< the file the run reads ("" for weights given as numbers)
  bool arrays = false;     ///< given as arrays (Python): `file`, if any, is a temporary copy
  std::uint64_t hash = 0;  ///< FNV-1a of the file's bytes, or of the numbers' bits
};

/// The inputs of a run with `options` (resolved) besides its mesh: the face-list file, the
/// weights file or the weights given as numbers (arrays set for the latter). A caller that
/// wrote arrays into a temporary face-list file (Python) sets `arrays` on that entry itself.
/// @throws InputError naming a file that cannot be read
std::vector<RunInput> run_inputs(const RunOptions& options);

/// Refuses a checkpoint whose run read other contents than `inputs` (run_inputs of the resumed
/// run, after options_for_resume), naming the file or the option given as arrays; and one
/// written before checkpoints recorded their inputs (format 1) when `inputs` is not empty,
/// since those files cannot be checked.
/// @throws InputError
void check_checkpoint_files(const Checkpoint& c, const std::vector<RunInput>& inputs);

/// The options that do not change a run's result (the library's guarantee: the same bytes at
/// any thread count), by their table names: a run may resume with other values, and a front end
/// that keys runs by their options (the Python sweep) leaves them out of the key.
const std::vector<std::string>& result_neutral_options();

/// What a checkpoint records besides the run's state and options.
struct CheckpointInfo {
  std::string input;             ///< the input as the saving run names it (its path, ARRAYS_INPUT)
  std::uint64_t input_hash = 0;  ///< mesh_hash of the mesh it runs
  std::string log;               ///< the caller's log of the frames so far (the CLI: its CSV)
  std::vector<RunInput> inputs;  ///< run_inputs of the run, taken before it started
  /// Frames between the run's periodic saves (0: only when it is stopped): recorded so that a
  /// run resumed without being told how often to save goes on as the interrupted one did.
  int save_every = 0;
};

/// Writes `run` with the options it runs with and `info`, whole or not at all (a temporary file
/// renamed).
/// @throws UsageError if the file cannot be written
void write_checkpoint(const std::string& path, const SavedRun& run, const RunOptions& options,
                      const CheckpointInfo& info);

/// The file beside a checkpoint that holds its caller's log when the caller keeps it there
/// (CheckpointLogFile): "PATH.log" (PATH a symbolic link's target). A checkpoint saved so is
/// resumed only with that file.
std::string checkpoint_log_path(const std::string& checkpoint);
/// The file beside a checkpoint that holds the run's volume history (V/V0 after each frame so
/// far, a double each) when the caller keeps its log beside (CheckpointLogFile): "PATH.history".
/// A checkpoint saved so is resumed only with that file and the log's.
std::string checkpoint_history_path(const std::string& checkpoint);

/// A caller's log and the run's volume history kept beside the checkpoint (checkpoint_log_path,
/// checkpoint_history_path), not in it: each save appends what was added since the last one to
/// those files, and the checkpoint records the length of each that it goes with and a hash of
/// it (format 5). Both held in every checkpoint made each save as large as the run so far (a
/// log line and 8 bytes a frame), and a long run's saves cost the square of its frames.
/// The three files are consistent at every moment: a file beside is only appended to (after
/// cutting it back to the length the checkpoint in place records), before the checkpoint is
/// renamed into place, so a process ending between the two leaves a file longer than recorded,
/// which the reader cuts. A file beside that this run has not written (another run's, or one the
/// checkpoint in place may still need) is never changed: the first save then holds the log and
/// history itself (as formats 1 to 3 did), and only the next one starts the files beside anew.
class CheckpointLogFile {
 public:
  /// @param checkpoint  where the run saves
  /// @param log         the caller's whole log, which only grows while the run lasts (lines
  ///                    appended); read at each save
  /// @param resumed     the checkpoint the run continues from (nullptr: none); when it is the
  ///                    file `checkpoint` with its log beside, the first save appends to that
  ///                    log (and to its history, when that is beside too)
  CheckpointLogFile(const std::string& checkpoint, const std::string& log,
                    const Checkpoint* resumed);

  // For write_checkpoint: whether this save puts the log and history beside; append() makes the
  // file beside hold the whole log, append_history(h) the other one the whole history h (each
  // returns the length, bytes or values, and the FNV-1a of the bytes); committed() after the
  // checkpoint was renamed into place.
  bool beside() const {
    return log_file_.state != State::Unknown && history_file_.state != State::Unknown;
  }
  const std::string& log() const { return log_; }
  std::pair<std::uint64_t, std::uint64_t> append();
  std::pair<std::uint64_t, std::uint64_t> append_history(const std::vector<double>& history);
  void committed();

 private:
  enum class State {
    Unknown,  ///< the checkpoint in place may need the file beside as it is: not touched
    Free,     ///< the checkpoint in place does not need the file beside: it is started anew
    Ours      ///< the checkpoint in place needs the first `synced` bytes of the file beside
  };
  /// One file beside, appended to.
  struct Stream {
    std::string path;
    State state = State::Unknown;
    std::uint64_t synced = 0, hash = 0;  ///< length and FNV-1a of the bytes the checkpoint needs
    std::uint64_t pending = 0, pending_hash = 0;  ///< those of the save under way
  };
  /// Makes `s`'s file hold `bytes` (`size` of them): cut back to s.synced, the rest appended.
  static void append(Stream& s, const char* bytes, std::uint64_t size);
  const std::string& log_;
  Stream log_file_, history_file_;
};

/// write_checkpoint with the caller's log in `log` (its CheckpointInfo::log is not read).
/// @throws UsageError if the checkpoint or a file beside it cannot be written (the checkpoint
///         in place and its files beside are then still consistent)
void write_checkpoint(const std::string& path, const SavedRun& run, const RunOptions& options,
                      const CheckpointInfo& info, CheckpointLogFile& log);

/// Checkpointing a run (run_contraction's last argument).
class RunCheckpointer {
 public:
  virtual ~RunCheckpointer() = default;
  /// The state to continue from (restored after the run is prepared), or nullptr.
  virtual const Checkpoint* resume_from() const { return nullptr; }
  /// After every frame that the run goes on from (after the observers): whether to save now.
  virtual bool save_due(int frame) = 0;
  /// Saves (write_checkpoint): `run` is the whole state, and the run would continue with the
  /// next frame.
  virtual void save(const SavedRun& run) = 0;
  /// After save_due (and save): true stops the run here with RunStatus::Cancelled (a signal
  /// asked for it; its state is saved).
  virtual bool stop() { return false; }
};

}  // namespace shellcontract
