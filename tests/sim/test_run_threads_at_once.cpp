// Runs on several threads of one process at once (core/arena_threads.hpp): each run's observer
// is called on the run's own caller's thread, and each run gets the arena of its thread count
// for itself. Before, the runs of a thread count shared one arena: while one run held its
// reserved slot, TBB ran another run's preparation, with its stage() and cancelled(), on a TBB
// worker or on the first run's thread (Python's Ctrl-C check then answered for the wrong run).
#include <gtest/gtest.h>

#include <atomic>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "shellcontract/observer.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

RunOptions options_of(const std::string& threads, const std::string& order) {
  RunOptions o;
  set_run_option(o, "frames", "2");
  set_run_option(o, "threads", threads);
  set_run_option(o, "order", order);
  set_run_option(o, "regions", "auto");
  resolve_run_options(o);
  return o;
}

/// Counts the callbacks that came on a thread other than the one that made it (the caller's).
class ThreadChecker : public RunObserver {
 public:
  void warning(const std::string&) override { check(); }
  void stage(const std::string&) override {
    check();
    ++stages;
  }
  void started(const FrameView&) override { check(); }
  void frame(const FrameView&, const FrameMetrics&) override { check(); }
  void finished(const FrameView&, const RunResult&) override { check(); }
  bool cancelled() override {
    check();
    return false;
  }
  int stages = 0;
  int foreign = 0;

 private:
  void check() {
    if (std::this_thread::get_id() != caller_) ++foreign;
  }
  std::thread::id caller_ = std::this_thread::get_id();
};

// Each thread runs short runs back to back, so that their preparations overlap: several runs
// of the same thread count (and of another) at once. On the old shared arenas (one per thread
// count, for every run) some callbacks ran on another run's thread or on a TBB worker.
TEST(RunThreadsAtOnce, EveryCallbackRunsOnItsCallersThread) {
  const Mesh mesh = test::to_surface_mesh(test::icosphere(3));
  const std::vector<RunOptions> options = {options_of("2", "coloured"),
                                           options_of("2", "sequential"),
                                           options_of("1", "coloured"), options_of("0", "auto")};
  constexpr int RUNS = 8;
  std::vector<int> foreign(options.size() * RUNS, -1), stages(options.size() * RUNS, 0);
  std::vector<std::thread> threads;
  for (std::size_t k = 0; k < options.size() * 2; ++k)
    threads.emplace_back([&, k] {
      for (int i = 0; i < RUNS / 2; ++i) {
        ThreadChecker checker;
        const RunResult r = run_contraction(mesh, options[k % options.size()], &checker);
        EXPECT_EQ(r.status, RunStatus::Completed);
        foreign[k * (RUNS / 2) + static_cast<std::size_t>(i)] = checker.foreign;
        stages[k * (RUNS / 2) + static_cast<std::size_t>(i)] = checker.stages;
      }
    });
  for (std::thread& t : threads) t.join();
  for (std::size_t i = 0; i < foreign.size(); ++i) {
    EXPECT_EQ(foreign[i], 0) << "run " << i << ": callbacks on another thread";
    EXPECT_GT(stages[i], 0) << "run " << i;
  }
}

/// A stage() that starts a run of its own on the same thread, once.
class NestingObserver : public ThreadChecker {
 public:
  NestingObserver(const Mesh& mesh, const RunOptions& options) : mesh_(mesh), options_(options) {}
  void stage(const std::string& what) override {
    ThreadChecker::stage(what);
    if (nested.has_value()) return;
    ThreadChecker inner;
    nested = run_contraction(mesh_, options_, &inner).status;
    inner_foreign = inner.foreign;
  }
  std::optional<RunStatus> nested;
  int inner_foreign = -1;

 private:
  const Mesh& mesh_;
  const RunOptions& options_;
};

// A callback that runs the library again on its thread, inside the run's arena, gets an arena of
// its own: the nested run completes (it must not wait for the slot its caller holds), on the
// caller's thread, and the outer run then completes too.
TEST(RunThreadsAtOnce, ARunStartedFromACallbackGetsAnArenaOfItsOwn) {
  const Mesh mesh = test::to_surface_mesh(test::icosphere(2));
  for (const char* threads : {"1", "2"}) {
    const RunOptions o = options_of(threads, "coloured");
    NestingObserver outer(mesh, o);
    EXPECT_EQ(run_contraction(mesh, o, &outer).status, RunStatus::Completed) << threads;
    ASSERT_TRUE(outer.nested.has_value()) << threads;
    EXPECT_EQ(*outer.nested, RunStatus::Completed) << threads;
    EXPECT_EQ(outer.inner_foreign, 0) << threads;
    EXPECT_EQ(outer.foreign, 0) << threads;
  }
}

}  // namespace
}  // namespace shellcontract
