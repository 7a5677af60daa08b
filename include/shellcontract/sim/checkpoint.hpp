// Runs that resume to the same bytes (docs/design/sweeps.md, "Checkpoints"): the whole state of
// a run between two steps (the Simulator's, the run loop's and the caller's log so far) in one
// file, written atomically, and a run continued from it that takes the same steps as the run
// that wrote it. A checkpoint names the tool's version, a hash of the input mesh and the run's
// options; one of another version, input or options is refused, saying which.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "shellcontract/mesh/surface_mesh.hpp"
#include "shellcontract/sim/run.hpp"
#include "shellcontract/sim/run_options.hpp"
#include "shellcontract/sim/simulator_state.hpp"

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
  OptionValues given;        ///< the options given (RunOptions::given), less the threads
  OptionValues resolved;     ///< every option's value after resolving, less the threads
  SimulatorState sim;
  RunProgress progress;
  std::string log;           ///< the caller's log of the frames so far (the CLI: its CSV text)
};

/// A 64-bit hash of a mesh's vertex positions (their bits) and faces (vertex ids in order).
std::uint64_t mesh_hash(const Mesh& mesh);

/// The given options of `options` (their values as the table prints them), less the threads.
OptionValues given_options(const RunOptions& options);
/// Every option's value (the table's text) after resolve_run_options, less the threads, which
/// do not change a run's result.
OptionValues resolved_options(RunOptions options);

/// The options a resumed run runs with: the checkpoint's given options, then `command_line`'s
/// given ones on top (its threads, or the same values again).
/// @throws UsageError naming every option whose value differs from the checkpoint's
RunOptions options_for_resume(const Checkpoint& c, const RunOptions& command_line);

/// Refuses a checkpoint of another version or another input, saying which.
/// @throws InputError
void check_checkpoint_input(const Checkpoint& c, const std::string& path, const Mesh& mesh);

/// Writes `c` to `path` whole or not at all (a temporary file renamed).
/// @throws UsageError if the file cannot be written
void write_checkpoint(const std::string& path, const Checkpoint& c);
/// @throws InputError naming the file for a missing, truncated or corrupted checkpoint
Checkpoint read_checkpoint(const std::string& path);

/// Checkpointing a run (run_contraction's last argument).
class RunCheckpointer {
 public:
  virtual ~RunCheckpointer() = default;
  /// The state to continue from (restored after the Simulator is built), or nullptr.
  virtual const Checkpoint* resume_from() const { return nullptr; }
  /// After every frame that the run goes on from (after the observers): whether to save now.
  virtual bool save_due(const Simulator& sim) = 0;
  /// Saves: `sim` and `progress` are the whole state, and the run would continue with the next
  /// frame.
  virtual void save(const Simulator& sim, const RunProgress& progress) = 0;
  /// After save_due (and save): true stops the run here with RunStatus::Cancelled (a signal
  /// asked for it; its state is saved).
  virtual bool stop() { return false; }
};

}  // namespace shellcontract
