// A run checkpointer that keeps its checkpoint in memory: saves at frame `at` (and stops there
// when asked), or resumes from a given checkpoint. For tests of what a checkpoint holds and of
// how a resume treats it (test_checkpoint.cpp, test_checkpoint_fields.cpp).
#pragma once

#include <optional>
#include <string>

#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "sim/checkpoint.hpp"
#include "sim/simulator.hpp"

namespace shellcontract::test {

/// Saves at frame `at` (and stops there when asked), or resumes from `resume`.
class MemoryCheckpointer final : public RunCheckpointer {
 public:
  MemoryCheckpointer(const Mesh& mesh, const RunOptions& options, int at, bool stop)
      : mesh_(&mesh), options_(&options), at_(at), stop_(stop) {}
  explicit MemoryCheckpointer(const Checkpoint* resume) : resume_(resume) {}
  const Checkpoint* resume_from() const override { return resume_; }
  bool save_due(int frame) override { return at_ > 0 && frame == at_; }
  void save(const SavedRun& run) override {
    const Simulator& sim = run.sim;
    Checkpoint c;
    c.version = checkpoint_tool_version();
    c.input = "test";
    c.input_hash = mesh_hash(*mesh_);
    c.given = given_options(*options_);
    c.resolved = resolved_options(*options_);
    c.sim = sim.state();
    c.progress = run.progress;
    c.log = "log up to " + std::to_string(sim.frame());
    saved = c;
  }
  bool stop() override { return stop_ && saved.has_value(); }
  std::optional<Checkpoint> saved;

 private:
  const Mesh* mesh_ = nullptr;
  const RunOptions* options_ = nullptr;
  const Checkpoint* resume_ = nullptr;
  int at_ = 0;
  bool stop_ = false;
};

}  // namespace shellcontract::test
