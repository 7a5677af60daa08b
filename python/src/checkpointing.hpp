// contract(checkpoint=FILE, checkpoint_every=N, resume=FILE): the Python module's side of
// shellcontract/checkpoint.hpp, as cli/run_checkpoint.hpp is the CLI's. The state is saved every
// N frames and when the run is cancelled by a signal (Ctrl-C: KeyboardInterrupt); the log
// travels as the CLI's CSV text, so that either front resumes the other's checkpoints.
#pragma once

#include <pybind11/pybind11.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "shellcontract/checkpoint.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract::python {

namespace py = pybind11;

/// contract()'s own checkpoint arguments.
struct CheckpointArguments {
  std::string checkpoint;  ///< "" : none
  std::string resume;      ///< "" : none
  int every = 0;
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
};

/// With resume=: reads the checkpoint, sets `options` to the resumed run's (options_for_resume)
/// and refuses a face list or weights other than its run's (check_checkpoint_files). With
/// checkpoint=: checks now, as the CLI checks its outputs, that the file can be written, so that
/// a missing folder is not found at the first save, after the frames before it.
/// @throws InputError, UsageError (ValueError in Python)
PreparedCheckpoint prepare_checkpoint(const CheckpointArguments& args, RunOptions& options);

class PythonCheckpointer final : public RunCheckpointer {
 public:
  /// @param log        the log so far as the CLI's CSV text
  /// @param cancelled  whether the run is being cancelled (then it saves first)
  PythonCheckpointer(const CheckpointArguments& args, const PreparedCheckpoint& prepared,
                     std::uint64_t mesh_hash, const RunOptions& options, std::function<std::string()> log,
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
  std::function<std::string()> log_;
  std::function<bool()> cancelled_;
  int frame_ = 0;         ///< the frame of the last save_due, which save() saves
  int saved_frame_ = -1;  ///< the frame of the last checkpoint written
  int failures_ = 0;
  int first_failed_frame_ = -1;
  std::string first_failure_;
};

}  // namespace shellcontract::python
