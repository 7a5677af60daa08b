// What a checkpoint holds (shellcontract/checkpoint.hpp is the caller's side): the Simulator's
// state, the run loop's and the caller's log so far, and the file's format.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "shellcontract/checkpoint.hpp"
#include "shellcontract/mesh.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"
#include "sim/simulator_state.hpp"

namespace shellcontract {

/// The version a checkpoint is written with and must be read by (the project's version).
const char* checkpoint_tool_version();

/// The run loop's own state at a step boundary (run_contraction): what its stop criteria and
/// its result depend on besides the Simulator.
struct RunProgress {
  std::vector<double> history{1.0};  ///< V/V0 after each frame so far, frame 0 first
  double min_volume_ratio = 1.0;
  RunTotals totals;
  long new_intersections = -1;
  RunStatus status = RunStatus::Completed;  ///< NewIntersections once a frame found some
  std::string message;
  int frame_target_reached = -1;
  std::int64_t last_pairs = 0;
};

/// Option name (CLI spelling) and value (the table's text).
using OptionValues = std::vector<std::pair<std::string, std::string>>;

/// Everything a resumed run needs besides the input mesh itself.
struct Checkpoint {
  std::string version;       ///< checkpoint_tool_version() of the writer
  std::string input;         ///< the input's path as the saving run was given it
  std::uint64_t input_hash = 0;  ///< mesh_hash of the mesh it ran
  std::vector<RunInput> inputs;  ///< the other files it read (run_inputs)
  /// False for a checkpoint of format 1, which did not record `inputs` (check_checkpoint_files).
  bool inputs_recorded = true;
  OptionValues given;        ///< the options given (RunOptions::given), less the threads
  OptionValues resolved;     ///< every option's value after resolving, less the threads
  SimulatorState sim;
  RunProgress progress;
  std::string log;           ///< the caller's log of the frames so far (the CLI: its CSV text)
  /// Read from the file beside the checkpoint (formats 4 and 5, CheckpointLogFile), not from
  /// the file.
  bool log_beside = false;
  /// progress.history read from its own file beside the checkpoint (format 5,
  /// checkpoint_history_path), not from the file.
  bool history_beside = false;
  /// Frames between the saving run's periodic saves (0: only on a signal, or not recorded: format
  /// 1 and 2); a resumed run that is not told otherwise saves as often
  /// (CheckpointInfo::save_every).
  int save_every = 0;
  /// The file read_checkpoint read it from (not saved), for the messages of a refusal that
  /// needs the mesh (Simulator::restore); empty for one made in memory.
  std::string path;
};

/// The given options of `options` (their values as the table prints them), less the threads.
OptionValues given_options(const RunOptions& options);
/// Every option's value (the table's text) after resolve_run_options, less the threads, which
/// do not change a run's result.
OptionValues resolved_options(RunOptions options);

/// FNV-1a over `n` bytes, continuing from `h`: the checkpoint's checksum and its inputs' hashes.
std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h = 1469598103934665603ull);

/// Where a checkpoint of format 4 or 5 has its log: the first `size` bytes of the file beside it
/// (checkpoint_log_path), whose FNV-1a is `hash`; and where one of format 5 has its volume
/// history: the first `size` values (8 bytes each, the machine's doubles) of its own file beside
/// it (checkpoint_history_path), whose bytes' FNV-1a is `hash`.
struct LogBeside {
  std::uint64_t size = 0;
  std::uint64_t hash = 0;
};

/// Writes `c` to `path` whole or not at all (a temporary file renamed): its log and volume
/// history in the file (format 3); with `log` only, the log's place beside instead of the log
/// (format 4); with both, the history's place too instead of the history (format 5; c.log and
/// c.progress.history are not written).
/// @throws UsageError if the file cannot be written
void write_checkpoint(const std::string& path, const Checkpoint& c, const LogBeside* log = nullptr,
                      const LogBeside* history = nullptr);
/// Reads formats 5 to 1 (format 3: the log and history in the file; format 2: written before the
/// interval between saves was recorded, format 1: before the inputs were).
/// @throws InputError naming the file for a missing, truncated or corrupted checkpoint, or a
///         folder, device or FIFO in its place, or one whose fields no run could have saved
///         (check_checkpoint_fields); for formats 4 and 5, naming the file beside it too
///         (read_log_beside, read_history_beside)
Checkpoint read_checkpoint(const std::string& path);
/// The log of the checkpoint `path` of format 4 or 5: the first beside.size bytes of the file
/// beside it (more are left by a save that ended between the append and the rename).
/// @throws InputError naming both files when that file is missing, shorter, or its bytes do
///         not hash to beside.hash (damaged, or another run's)
std::string read_log_beside(const std::string& path, const LogBeside& beside);
/// The volume history of the checkpoint `path` of format 5, from checkpoint_history_path: as
/// read_log_beside, beside.size values.
/// @throws InputError as read_log_beside
std::vector<double> read_history_beside(const std::string& path, const LogBeside& beside);

/// What read_checkpoint checks of the fields themselves, without the mesh: each option recorded
/// is one the table knows with a value it accepts; positions, velocities, volumes and every
/// other number finite; the per-vertex arrays one per vertex (or empty where a run may leave
/// them so); contact kinds known and ids not negative; the volume history one value per frame.
/// The checksum only finds damage: anyone can recompute it after an edit, so what the file holds
/// is checked as any other input is (Simulator::restore checks the rest against the mesh).
/// @throws InputError "checkpoint PATH: FIELD ..." naming the first field that is not so
void check_checkpoint_fields(const Checkpoint& c, const std::string& path);

/// What run_contraction checks of the checkpoint it resumes from: check_checkpoint_input, and
/// that `options` resolve to the checkpoint's options (as options_for_resume compares them: the
/// threads aside, a face-list or weights file by its contents, check_checkpoint_files).
/// Without it a checkpoint of another mesh with as many vertices, or of other options, was
/// continued into a result that is neither run's.
/// @throws InputError naming what differs; UsageError for options that do not resolve
void check_checkpoint_fits(const Checkpoint& c, const Mesh& mesh, const RunOptions& options);

/// A run's state at a step boundary: the Simulator's and the run loop's.
class Simulator;

struct SavedRun {
  const Simulator& sim;
  const RunProgress& progress;
};

}  // namespace shellcontract
