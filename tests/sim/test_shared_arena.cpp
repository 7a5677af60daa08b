// The runs' task arenas (core/arena_threads.hpp): one per thread count for the whole process, so
// that a program calling the library many times does not grow (oneTBB 2021.8 keeps some kilobytes
// of every arena that ran parallel work after the arena is destroyed).
#include <gtest/gtest.h>
#include <malloc.h>
#include <tbb/info.h>

#include <chrono>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "core/arena_threads.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"
#include "support/cgal_mesh.hpp"
#include "support/child_process.hpp"
#include "support/mesh_fixtures.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

TEST(SharedArena, OneArenaPerThreadCount) {
  EXPECT_EQ(&shared_arena(1), &shared_arena(1));
  EXPECT_EQ(&shared_arena(0), &shared_arena(-3));  // both TBB's automatic count
  const int machine = tbb::info::default_concurrency();
  // A count above the machine's is the machine's (arena_threads).
  EXPECT_EQ(&shared_arena(machine + 5), &shared_arena(machine));
  EXPECT_EQ(shared_arena(1).max_concurrency(), 1);
}

/// The process's resident memory in KiB (Linux), after giving freed heap pages back.
long resident_kib() {
  malloc_trim(0);
  std::ifstream status("/proc/self/status");
  std::string key;
  long value = -1;
  while (status >> key) {
    if (key == "VmRSS:") {
      status >> value;
      break;
    }
    status.ignore(1 << 20, '\n');
  }
  return value;
}

// Before: each run made three arenas of its own (solver, collision, step) and destroyed them; a
// loop of short threaded runs (Python's contract() in a loop) grew by about 16 KiB per run on
// two threads, 8 MB per 500 runs. The threshold leaves room for the allocator's own noise and is
// a quarter of that growth.
TEST(SharedArena, ManyThreadedRunsDoNotGrowTheProcess) {
  if (tbb::info::default_concurrency() < 2) GTEST_SKIP() << "one core: the runs use no arena threads";
  if (resident_kib() < 0) GTEST_SKIP() << "no /proc/self/status";
  const Mesh mesh = test::to_surface_mesh(test::icosphere(2));
  RunOptions o;
  set_run_option(o, "frames", "2");
  set_run_option(o, "threads", "2");
  set_run_option(o, "order", "coloured");
  resolve_run_options(o);
  for (int i = 0; i < 50; ++i) ASSERT_EQ(run_contraction(mesh, o).status, RunStatus::Completed);  // warm up
  const long before = resident_kib();
  for (int i = 0; i < 500; ++i) ASSERT_EQ(run_contraction(mesh, o).status, RunStatus::Completed);
  const long grown = resident_kib() - before;
  EXPECT_LT(grown, 2048) << "KiB grown over 500 runs";
}

// Runs on several threads at once share the arena of their thread count; each must still give
// the bytes it gives alone (the coloured order's results do not depend on which thread runs
// which chunk, and the collision step's background task is waited for by its own run).
TEST(SharedArena, RunsAtOnceGiveTheResultsOfRunsAlone) {
  const Mesh small = test::to_surface_mesh(test::icosphere(2)), large = test::to_surface_mesh(test::icosphere(3));
  std::vector<RunOptions> options(4);
  for (std::size_t k = 0; k < options.size(); ++k) {
    set_run_option(options[k], "frames", "20");
    set_run_option(options[k], "threads", "2");
    set_run_option(options[k], "order", k % 2 ? "coloured" : "sequential");
    set_run_option(options[k], "pressure", k < 2 ? "4" : "8");
    resolve_run_options(options[k]);
  }
  auto mesh_of = [&](std::size_t k) -> const Mesh& { return k % 2 ? large : small; };
  std::vector<Positions> alone;
  for (std::size_t k = 0; k < options.size(); ++k) alone.push_back(run_contraction(mesh_of(k), options[k]).positions);
  for (int round = 0; round < 3; ++round) {
    std::vector<Positions> together(options.size());
    std::vector<std::thread> threads;
    for (std::size_t k = 0; k < options.size(); ++k)
      threads.emplace_back([&, k] { together[k] = run_contraction(mesh_of(k), options[k]).positions; });
    for (std::thread& t : threads) t.join();
    for (std::size_t k = 0; k < options.size(); ++k) {
      ASSERT_EQ(together[k].rows(), alone[k].rows());
      EXPECT_TRUE(together[k] == alone[k]) << "run " << k << ", round " << round;
    }
  }
}

// An arena that memory ran out while it was made is not kept: the next run of that thread count
// in the process completes (tests/tools/arena_retry_run.cpp, a process of its own for each
// limit). Before: TBB's lazy initialization, left "pending" by the std::bad_alloc, made every
// later run of that count spin for ever (a Python session retrying after its MemoryError). Where
// the arena's making fails depends on the allocator (from how little address space TBB's own
// allocator is loaded at all), so the limits are stepped up from none until the arena is made.
TEST(SharedArena, ARunAfterTheArenaRanOutOfMemoryCompletes) {
#ifdef __SANITIZE_ADDRESS__
  GTEST_SKIP() << "AddressSanitizer's allocator reserves its address space its own way";
#endif
  constexpr long STEP_KIB = 256, MOST_KIB = 64 * 1024;
  int refused = 0;
  bool made_after_refusal = false;
  for (long kib = 0; kib <= MOST_KIB && !made_after_refusal; kib += STEP_KIB) {
    test::ChildSpec spec;
    spec.program = SHELLCONTRACT_ARENA_RETRY_RUN;
    spec.args = {std::string(test::MESH_DIR) + "/ico2.off", std::to_string(kib)};
    test::Child child(spec);
    // Far beyond the milliseconds the run takes; one waiting for a failed arena never ends.
    const int status = child.finish(std::chrono::seconds(60));
    SCOPED_TRACE(std::to_string(kib) + " KiB of headroom: " + test::ending(status) + ": " +
                 child.output());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    ASSERT_NE(child.output().find("run: ok"), std::string::npos);
    if (child.output().find("arena: refused") != std::string::npos)
      ++refused;
    else if (refused > 0)
      made_after_refusal = true;
  }
  std::printf("%d limits refused the arena\n", refused);
  EXPECT_GT(refused, 0) << "no limit up to " << MOST_KIB << " KiB made the arena fail";
  EXPECT_TRUE(made_after_refusal) << "the arena was not made under any limit above the failures";
}

}  // namespace
}  // namespace shellcontract
