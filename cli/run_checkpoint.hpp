// `run --checkpoint FILE [--checkpoint-every N]` and `run --resume FILE`: the CLI's side of
// shellcontract/checkpoint.hpp. The state is saved every N frames and when a stop signal
// arrives (the handler only sets a flag; the run saves and stops after the step it is in). Without
// --checkpoint a signal stops the run the same way, with nothing saved.
#pragma once

#include <atomic>
#include <csignal>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/signal_repeat.hpp"
#include "mesh/file_safety.hpp"
#include "output_paths.hpp"
#include "run_observers.hpp"
#include "run_second_signal.hpp"
#include "shellcontract/checkpoint.hpp"
#include "shellcontract/checkpoint_lock.hpp"
#include "shellcontract/error.hpp"
#include "sim/checkpoint.hpp"

namespace shellcontract::cli {

namespace checkpoint_signal {
inline volatile std::sig_atomic_t received = 0;
/// When the first signal arrived (CLOCK_MONOTONIC, ns): written by the handler only, with the
/// stop signals masked while it runs, so never twice at once.
inline std::atomic<std::int64_t> first_ns{0};
static_assert(std::atomic<std::int64_t>::is_always_lock_free,
              "first_ns is written in a signal handler");
inline std::int64_t monotonic_ns() {
  timespec t{};
  ::clock_gettime(CLOCK_MONOTONIC, &t);  // async-signal-safe (POSIX.1-2008)
  return static_cast<std::int64_t>(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}
extern "C" inline void on_signal(int sig) {
  const std::int64_t now = monotonic_ns();
  if (received == 0) {
    first_ns.store(now, std::memory_order_relaxed);
    received = sig;
    if (second_signal::phase.load() == second_signal::Outputs)
      second_signal::acknowledge_late_stop();
    return;
  }
  // The same request again (a wrapper's forward, timeout's second send, a sweep's SIGTERM after
  // the batch system's SIGUSR1, however late): core/signal_repeat.hpp.
  if (!ends_at_once(sig, first_ns.load(std::memory_order_relaxed), now)) return;
  // A person's second Ctrl-C ends the process at once, removing the temporary of a checkpoint it
  // cuts short (the save after the first one is the likely place for it): the library's ending,
  // raised again now that it is this signal's handler. First one line of what that leaves
  // (run_second_signal.hpp), which holds once the end is on the run's own thread: there the save
  // in progress goes no further.
  second_signal::say();
  if (second_signal::on_another_thread()) {
    second_signal::forward_to_run_thread(sig);
    return;
  }
  end_on_next_signal(sig);
  ::raise(sig);
}
}  // namespace checkpoint_signal

/// The input of `run --resume PATH` without INPUT: the checkpoint's.
/// @throws UsageError for a checkpoint of a mesh given as arrays (Python), which names no file
inline std::string checkpoint_input(const Checkpoint& c, const std::string& path) {
  if (c.input == ARRAYS_INPUT)
    throw UsageError("checkpoint " + path +
                     " was written by a run of a mesh given as arrays (Python), with no file to resume it "
                     "from: give the mesh as INPUT (shellcontract run INPUT --resume " + path + " -o OUTPUT)");
  // The path is the one the interrupted run was given, relative to the folder it started in:
  // from another folder it names nothing, and the user must learn where it came from.
  std::error_code ec;
  if (!std::filesystem::exists(c.input, ec))
    throw InputError("the input mesh '" + printable(c.input) + "' recorded in checkpoint " + path +
                     " cannot be opened: no such file (a relative path is relative to the folder the "
                     "interrupted run started in); run from that folder, or give the mesh as INPUT "
                     "(shellcontract run INPUT --resume " + path + " -o OUTPUT)");
  return c.input;
}

/// Where `run --resume FILE` without --checkpoint saves: into FILE, as the interrupted run did
/// (a job that is preempted again must not lose what it did since), when FILE can be written
/// (check_planned_outputs); otherwise "" after a warning, and the run saves nothing, as before.
inline std::string resumed_run_checkpoint(const std::string& resume_path,
                                          const std::vector<PlannedOutput>& inputs) {
  try {
    check_planned_outputs(
        OutputPlan{{{"--resume", resume_path},
                    {"--resume's log", checkpoint_log_path(resume_path)},
                    {"--resume's volume history", checkpoint_history_path(resume_path)}},
                   inputs,
                   {}});
    return resume_path;
  } catch (const UsageError& e) {
    std::cerr << "warning: this run saves no checkpoint (give --checkpoint FILE): " << e.what()
              << '\n';
    return "";
  }
}

/// The locks of a run (shellcontract/checkpoint_lock.hpp), its warnings printed.
/// After check_planned_outputs. @param held  lock_resumed_checkpoint's, taken before the read
/// @throws UsageError (exit code 1) naming the checkpoint held
inline CheckpointLocks lock_run_checkpoints(const std::string& checkpoint,
                                            const std::string& resume, bool saves_to_resumed,
                                            CheckpointLocks held) {
  CheckpointLocks locks = shellcontract::lock_run_checkpoints(checkpoint, resume, saves_to_resumed,
                                                              OptionSpelling::Cli, std::move(held));
  for (const std::string& w : locks.warnings) std::cerr << "warning: " << w << '\n';
  return locks;
}

/// What a resumed run that saves to the file it resumed from says of it (the user did not ask).
inline std::string resumed_saving_note(const std::string& path, int every) {
  return "saving the state to " + path + ", the checkpoint resumed, " +
         (every > 0 ? "every " + std::to_string(every) + " frames and " : std::string()) +
         "on SIGINT, SIGTERM, SIGHUP or SIGUSR1 (--checkpoint FILE saves elsewhere)";
}

class CliCheckpointer final : public RunCheckpointer {
 public:
  /// @param path    where to save ("" : never; a signal still stops the run after its step)
  /// @param every   frames between saves (0: only on a signal)
  /// @param resume  the checkpoint the run continues from, or nullptr
  /// @param inputs  run_inputs of the run (its face list or weights file), for the checkpoint
  /// @param log     the CSV log, whose text each save appends to beside the checkpoint
  CliCheckpointer(std::string path, int every, const Checkpoint* resume, std::string input,
                  std::uint64_t input_hash, std::vector<RunInput> inputs, const RunOptions& options,
                  const CsvLog& log)
      : path_(std::move(path)),
        every_(every),
        resume_(resume),
        input_(std::move(input)),
        hash_(input_hash),
        inputs_(std::move(inputs)),
        options_(options),
        log_file_(path_, log.text(), resume) {
    // What the handler's line of a second Ctrl-C says is in the file now (second_signal::describe
    // gave it the paths): the checkpoint resumed from, when this run saves over it.
    second_signal::checkpoint_in_place(resumed_frame(), false);
    // With or without a checkpoint: the run stops after its step and says at which frame, and
    // what it leaves (run_interrupt.hpp); the default ending (entry.cpp) exited 130 without a
    // word. A signal ignored (a background job of a script) stays ignored. SIGHUP and SIGUSR1
    // (Slurm's warning) too: INTERRUPT_SIGNALS.
    for (const int sig : INTERRUPT_SIGNALS) {
      struct sigaction current {};
      if (sigaction(sig, nullptr, &current) != 0 ||
          (!(current.sa_flags & SA_SIGINFO) && current.sa_handler == SIG_IGN))
        continue;
      struct sigaction sa {};
      sa.sa_handler = checkpoint_signal::on_signal;
      sigemptyset(&sa.sa_mask);
      for (const int other : INTERRUPT_SIGNALS) sigaddset(&sa.sa_mask, other);
      sigaction(sig, &sa, nullptr);
    }
  }

  const Checkpoint* resume_from() const override { return resume_; }

  bool save_due(int frame) override {
    if (path_.empty()) return false;
    frame_ = frame;
    return interrupted() || (every_ > 0 && frame % every_ == 0);
  }

  void save(const SavedRun& run) override {
    try {
      // The log and history beside the checkpoint, appended to: each save writes what is new.
      write_checkpoint(path_, run, options_, CheckpointInfo{input_, hash_, {}, inputs_, every_},
                       log_file_);
      saved_frame_ = frame_;
      second_signal::checkpoint_in_place(frame_, interrupted());
    } catch (const UsageError& e) {
      // The run goes on without it (a full disk should not cost the run); said once here, and
      // at the end in the summary (failure_report) and the message of an interrupted run.
      if (failures_ == 0) {
        std::cerr << "warning: checkpoint not written: " << e.what() << '\n';
        first_failure_ = e.what();
        first_failed_frame_ = frame_;
      }
      ++failures_;
    }
  }

  bool stop() override { return interrupted(); }

  /// A SIGINT or SIGTERM arrived (the run stops, or stopped, after its step).
  bool interrupted() const { return checkpoint_signal::received != 0; }
  /// The frame of the last checkpoint written (-1: none).
  int saved_frame() const { return saved_frame_; }
  const std::string& path() const { return path_; }
  /// The frame of the checkpoint in path() that this run did not write, and that a failed save
  /// left in place: the one it resumed from when it saves to that file (-1: none).
  int resumed_frame() const {
    std::error_code ec;
    return resume_ && !path_.empty() && std::filesystem::equivalent(path_, resume_->path, ec)
               ? resume_->sim.frame
               : -1;
  }
  /// The frame of the checkpoint in path() now: the last one this run saved, else the one it
  /// resumed from when it saves to that file (-1: none of this run's).
  int frame_in_place() const { return saved_frame_ >= 0 ? saved_frame_ : resumed_frame(); }
  /// What is in path() now, after a save that failed: "the one of frame N is still there", or
  /// that there is none.
  std::string left_in_place() const {
    const int frame = frame_in_place();
    return frame >= 0 ? "the checkpoint of frame " + std::to_string(frame) + " is still in " +
                            printable(path_)
                      : "no checkpoint was saved";
  }
  /// For the summary's "outputs": "" when every save was written; else how many failed, the
  /// first one's reason, and what is in the file now.
  std::string failure_report() const {
    if (failures_ == 0) return "";
    return "not written " + std::to_string(failures_) + (failures_ == 1 ? " time" : " times") +
           " (first at frame " + std::to_string(first_failed_frame_) + ": " + first_failure_ +
           "); " + left_in_place();
  }
  /// The first failed save's reason ("" : none failed).
  const std::string& first_failure() const { return first_failure_; }

 private:
  std::string path_;
  int every_;
  const Checkpoint* resume_;
  std::string input_;
  std::uint64_t hash_;
  std::vector<RunInput> inputs_;
  RunOptions options_;
  CheckpointLogFile log_file_;  ///< CsvLog's text and the V/V0 history, beside the checkpoint
  int frame_ = 0;               ///< the frame of the last save_due, which save() saves
  int saved_frame_ = -1;
  int failures_ = 0;  ///< saves that failed
  int first_failed_frame_ = -1;
  std::string first_failure_;
};

}  // namespace shellcontract::cli
