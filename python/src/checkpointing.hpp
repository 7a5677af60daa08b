// contract(checkpoint=FILE, checkpoint_every=N, resume=FILE): the Python module's side of
// shellcontract/checkpoint.hpp, as cli/run_checkpoint.hpp is the CLI's, and behaving as it does:
// the state is saved every N frames and when the run is cancelled by a signal (Ctrl-C:
// KeyboardInterrupt); resume= without checkpoint= goes on saving to the file it resumed from, as
// often as the interrupted run did; a run holds the checkpoints' lock (checkpoint_lock.hpp), so
// that a second run with one of them, Python's or the CLI's, is refused. The log travels as the
// CLI's CSV text, so that either front resumes the other's checkpoints.
#pragma once

#include <pybind11/pybind11.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "shellcontract/checkpoint.hpp"
#include "shellcontract/checkpoint_lock.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract::python {

namespace py = pybind11;

/// contract()'s own checkpoint arguments.
struct CheckpointArguments {
  std::string checkpoint;  ///< "" : none
  std::string resume;      ///< "" : none
  int every = 0;           ///< 0: not given
  /// The package's flag (__init__.py): its `regions` face-list file is the arrays it was given,
  /// written to a temporary file.
  bool regions_from_arrays = false;
};

/// Takes checkpoint, resume, checkpoint_every and _regions_from_arrays out of `kwargs`; the
/// others go to `options`. A path is a str or an os.PathLike; None is "not given".
/// @throws py::type_error, py::value_error for a bad path or checkpoint_every
CheckpointArguments take_checkpoint_arguments(const py::kwargs& kwargs, py::kwargs& options);

/// What a run needs of its checkpoint arguments, prepared before the mesh is read.
struct PreparedCheckpoint {
  std::shared_ptr<const Checkpoint> resume;  ///< nullptr without resume=
  std::vector<RunInput> inputs;               ///< the face list or weights, as the run starts
  /// Where the run saves: checkpoint=, else resume= where it can be written, else "" (nowhere).
  std::string save_path;
  /// checkpoint_every=, else the resumed run's interval (0: only when cancelled).
  int save_every = 0;
  /// Held until the run ends; released (the lock files removed) when this is destroyed.
  CheckpointLocks locks;
};

/// With resume=: reads the checkpoint, sets `options` to the resumed run's (options_for_resume)
/// and refuses a face list or weights other than its run's (check_checkpoint_files). Checks now,
/// as the CLI checks its outputs, that the file saved to can be written, so that a missing
/// folder is not found at the first save, after the frames before it (resume= without
/// checkpoint= that cannot be written: a warning, and the run saves nothing, as the CLI's). Then
/// locks the checkpoints, before the mesh is read: that is before any work.
/// @throws InputError, UsageError (ValueError in Python; another run holding a lock among them)
PreparedCheckpoint prepare_checkpoint(const CheckpointArguments& args, RunOptions& options);

class PythonCheckpointer final : public RunCheckpointer {
 public:
  /// @param log        the log so far as the CLI's CSV text, which grows as the run goes on; it
  ///                   is kept beside the checkpoint with the volume history (CheckpointLogFile),
  ///                   each save appending what is new, as the CLI's saves do
  /// @param cancelled  whether the run is being cancelled (then it saves first)
  PythonCheckpointer(const PreparedCheckpoint& prepared, std::uint64_t mesh_hash,
                     const RunOptions& options, const std::string& log,
                     std::function<bool()> cancelled);
  const Checkpoint* resume_from() const override { return resume_.get(); }
  bool save_due(int frame) override;
  /// A save that fails (a full disk) is recorded, not raised: the run goes on without it, as the
  /// CLI's does, and contract() warns afterwards (failure_warning).
  void save(const SavedRun& run) override;
  /// "" when every save was written; else the warning for the caller: how many saves failed,
  /// the first one's reason, and what the file holds now.
  std::string failure_warning() const;

 private:
  std::string path_;
  int every_;
  std::shared_ptr<const Checkpoint> resume_;
  std::uint64_t hash_;
  std::vector<RunInput> inputs_;
  RunOptions options_;
  CheckpointLogFile log_file_;
  std::function<bool()> cancelled_;
  int frame_ = 0;         ///< the frame of the last save_due, which save() saves
  int saved_frame_ = -1;  ///< the frame of the last checkpoint written
  int failures_ = 0;
  int first_failed_frame_ = -1;
  std::string first_failure_;
};

}  // namespace shellcontract::python
