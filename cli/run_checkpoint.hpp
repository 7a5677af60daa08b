// `run --checkpoint FILE [--checkpoint-every N]` and `run --resume FILE`: the CLI's side of
// sim/checkpoint.hpp. The state is saved every N frames and when SIGINT or SIGTERM arrives (the
// handler only sets a flag; the run saves and stops after the step it is in).
#pragma once

#include <csignal>
#include <cstdint>
#include <iostream>
#include <string>
#include <utility>

#include "run_observers.hpp"
#include "shellcontract/core/error.hpp"
#include "shellcontract/sim/checkpoint.hpp"
#include "shellcontract/sim/simulator.hpp"

namespace shellcontract::cli {

namespace checkpoint_signal {
inline volatile std::sig_atomic_t received = 0;
extern "C" inline void on_signal(int sig) {
  received = sig;
  std::signal(sig, SIG_DFL);  // a second Ctrl-C ends the process at once
}
}  // namespace checkpoint_signal

class CliCheckpointer final : public RunCheckpointer {
 public:
  /// @param path    where to save ("" : never; then signals keep their default action)
  /// @param every   frames between saves (0: only on a signal)
  /// @param resume  the checkpoint the run continues from, or nullptr
  CliCheckpointer(std::string path, int every, const Checkpoint* resume, std::string input,
                  std::uint64_t input_hash, const RunOptions& options, const CsvLog& log)
      : path_(std::move(path)),
        every_(every),
        resume_(resume),
        input_(std::move(input)),
        hash_(input_hash),
        given_(given_options(options)),
        resolved_(resolved_options(options)),
        log_(log) {
    if (path_.empty()) return;
    struct sigaction sa {};
    sa.sa_handler = checkpoint_signal::on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
  }

  const Checkpoint* resume_from() const override { return resume_; }

  bool save_due(const Simulator& sim) override {
    if (path_.empty()) return false;
    return interrupted() || (every_ > 0 && sim.frame() % every_ == 0);
  }

  void save(const Simulator& sim, const RunProgress& progress) override {
    Checkpoint c;
    c.version = checkpoint_tool_version();
    c.input = input_;
    c.input_hash = hash_;
    c.given = given_;
    c.resolved = resolved_;
    c.sim = sim.state();
    c.progress = progress;
    c.log = log_.text();
    try {
      write_checkpoint(path_, c);
      saved_frame_ = sim.frame();
    } catch (const UsageError& e) {
      // The run goes on without it (a full disk should not cost the run); said once.
      if (!warned_) std::cerr << "warning: checkpoint not written: " << e.what() << '\n';
      warned_ = true;
    }
  }

  bool stop() override { return interrupted(); }

  bool interrupted() const { return !path_.empty() && checkpoint_signal::received != 0; }
  /// The frame of the last checkpoint written (-1: none).
  int saved_frame() const { return saved_frame_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int every_;
  const Checkpoint* resume_;
  std::string input_;
  std::uint64_t hash_;
  OptionValues given_, resolved_;
  const CsvLog& log_;
  int saved_frame_ = -1;
  bool warned_ = false;
};

}  // namespace shellcontract::cli
