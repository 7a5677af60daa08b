// Two runs and one checkpoint (docs/design/output-safety.md): a run that saves to a checkpoint,
// or resumes from one, holds a lock for that path, so that a second run naming it is refused
// before any work. Without it two runs saved their states into one file in turn, and resuming
// one of them silently continued the other (its options, its result). One lock for both front
// ends: the CLI's `run --checkpoint/--resume` and Python's contract(checkpoint=, resume=) meet
// it alike, in one process or in two.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "shellcontract/options.hpp"

namespace shellcontract {

/// The file a lock for `checkpoint` is taken on: ".<its name>.lock" in its folder (a symbolic
/// link's target's name and folder: the file a save replaces). The
/// checkpoint itself is replaced by a rename at every save, so a lock on it would stay with the
/// old file; the lock file is stable, and a lock on it is seen by every run that reaches that
/// folder, whatever path it is spelled with (a symbolic link to the folder, a bind mount, another
/// node's NFS mount where the file system passes flock on).
std::string checkpoint_lock_path(const std::string& checkpoint);

/// Held while a run saves to or resumes from a checkpoint; on release the lock file is removed
/// (still locked, so that no second run takes it in between). A process ended by SIGKILL leaves
/// the lock file, unlocked: the next run takes it.
class CheckpointLock {
 public:
  CheckpointLock(int fd, std::string path, int slot)
      : fd_(fd), path_(std::move(path)), slot_(slot) {}
  ~CheckpointLock();
  CheckpointLock(const CheckpointLock&) = delete;
  CheckpointLock& operator=(const CheckpointLock&) = delete;
  /// Whether this is the lock of `checkpoint`: its lock file is the one held.
  bool locks(const std::string& checkpoint) const;
  /// Whether the lock file was opened for writing (not a read-only folder's, taken to resume).
  bool writable() const;

 private:
  int fd_;
  std::string path_;
  int slot_;
};

/// Locks `checkpoint` (after its outputs are checked: its folder exists and takes new files).
/// The lock file is a registered temporary (mesh/file_safety.hpp): the interrupt handler removes
/// it too, so a signal that ends the process at once (the CLI's second Ctrl-C; in a Python
/// process, a SIGTERM, SIGHUP or SIGUSR1 left at its default action) leaves none. On a file
/// system without locks (flock fails with other than EWOULDBLOCK) the run goes on unlocked, and
/// `warnings` says so.
/// @param option  how messages name the path: "--checkpoint" or "--resume" (Python:
///                "checkpoint", "resume")
/// @param saves   whether the run saves to it; a checkpoint only resumed from whose folder this
///                run cannot write is locked only if a lock file is there (else nullptr)
/// @return nullptr when the file system takes no locks
/// @throws OutputFileError (exit code 1, as any UsageError) with errno EWOULDBLOCK when another
///         run holds the lock (Python's BlockingIOError), with the errno of open() when the lock
///         file cannot be made
std::unique_ptr<CheckpointLock> lock_checkpoint(const std::string& checkpoint,
                                                const std::string& option, bool saves,
                                                std::vector<std::string>& warnings);

/// The locks a run holds: on the checkpoint it saves to and on the one it resumes from, if
/// another file; a second run with either is refused.
struct CheckpointLocks {
  std::unique_ptr<CheckpointLock> saved, resumed;
  std::vector<std::string> warnings;  ///< a file system that takes no locks
};

/// The lock of the checkpoint a run resumes from, taken before the run reads it, so that it is
/// read under the lock: a run that holds it may be saving there, and a save that holds its log
/// itself (format 3) removes the files beside; read first, a resume could meet them missing and
/// say so as bad input (exit code 2) instead of "another run holds this checkpoint" (exit code 1).
/// Named as lock_run_checkpoints names it: by the option that saves to it when that is
/// `checkpoint` (the same lock file), else by the resume option; taken as a lock only resumed
/// from (lock_checkpoint's `saves` false: in a folder this run cannot write, the lock file there
/// read-only). Only a run holding the lock is refused here; any other failure to take it (no
/// such file, a lock file that cannot be made) is left to the read and to lock_run_checkpoints,
/// which refuse as they did before.
/// @param checkpoint  where the run saves, as given ("" : not given)
/// @return `resumed` holding the lock, or nullptr (not taken; `warnings`: a file system that
///         takes no locks), for lock_run_checkpoints
/// @throws OutputFileError (a UsageError) with errno EWOULDBLOCK when another run holds it
CheckpointLocks lock_resumed_checkpoint(const std::string& resume, const std::string& checkpoint,
                                        OptionSpelling spelling);

/// Takes both locks of a run, by the front end's option names (spelling).
/// @param checkpoint        where the run saves ("" : nowhere)
/// @param resume            the checkpoint it resumes from ("" : none)
/// @param saves_to_resumed  `checkpoint` is `resume`, not given by its own option (a resumed run
///                          that goes on saving where it resumed from): named as the latter
/// @param held              lock_resumed_checkpoint's answer for `resume`: its lock is kept (as
///                          the lock of `checkpoint` when that is its lock file, unless locked
///                          read-only: then taken again to save), not taken again
/// @throws UsageError naming the checkpoint held
CheckpointLocks lock_run_checkpoints(const std::string& checkpoint, const std::string& resume,
                                     bool saves_to_resumed, OptionSpelling spelling,
                                     CheckpointLocks held = {});

}  // namespace shellcontract
