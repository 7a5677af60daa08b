// The runs' task arenas (core/arena_threads.hpp): a pool per thread count for the whole process,
// each arena leased by one run at a time, so that a program calling the library many times does
// not grow (oneTBB 2021.8 keeps some kilobytes of every arena that ran parallel work after the
// arena is destroyed).
#include <gtest/gtest.h>
#include <malloc.h>
#include <sys/wait.h>
#include <tbb/info.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
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

std::atomic<bool> making_arena{false};

// A process forked while another thread made an arena (holding the pool's mutex) inherited the
// mutex held, and its first lease waited for ever. A thread makes an arena and sleeps in the
// pool's hook, mutex held, while this thread forks: the child's lease must return.
TEST(SharedArena, AForkWhileAnArenaIsMadeLeavesTheChildAbleToLease) {
  // Every arena of one thread leased here, so that the thread's lease makes a new one.
  std::vector<ArenaLease> held;
  while (held.size() < arenas_made(1)) held.emplace_back(1);
  set_arena_made_hook([] {
    making_arena = true;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  });
  std::thread maker([] { const ArenaLease made(1); });
  while (!making_arena) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const pid_t child = ::fork();
  if (child == 0) {
    ::alarm(20);  // a child that waits for ever is ended, and the test fails
    const ArenaLease lease(1);
    ::_exit(lease.threads() == 1 ? 0 : 3);
  }
  maker.join();
  set_arena_made_hook(nullptr);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
      << "the child's lease "
      << (WIFSIGNALED(status) && WTERMSIG(status) == SIGALRM ? "waited for ever" : "failed")
      << " (wait status " << status << ")";
}

TEST(SharedArena, ALeaseHasItsArenaToItselfAndGivesItBack) {
  const int machine = tbb::info::default_concurrency();
  EXPECT_EQ(ArenaLease(1).arena().max_concurrency(), 1);
  // A count above the machine's is the machine's (arena_threads); 0 and below are TBB's
  // automatic count.
  EXPECT_EQ(ArenaLease(machine + 5).threads(), ArenaLease(machine).threads());
  EXPECT_EQ(ArenaLease(-3).threads(), ArenaLease(0).threads());
  {
    const ArenaLease a(1), b(1);
    EXPECT_NE(&a.arena(), &b.arena());  // two runs at once: an arena each
    const ArenaLease copy = a;
    EXPECT_EQ(&copy.arena(), &a.arena());  // a copy shares the lease
  }
  // Both given back: leases one at a time make no more arenas.
  const std::size_t made = arenas_made(1);
  EXPECT_GE(made, 2u);
  for (int i = 0; i < 20; ++i) {
    const ArenaLease a(1);
    const ArenaLease b(1);
  }
  EXPECT_EQ(arenas_made(1), made);
}

TEST(SharedArena, ARunsPartsShareItsLease) {
  const ArenaLease run(2);
  {
    const RunArenaScope in_run(run);
    EXPECT_EQ(&run_arena(2).arena(), &run.arena());
    if (arena_threads(1) != arena_threads(2)) {  // another count: a lease of its own
      EXPECT_NE(&run_arena(1).arena(), &run.arena());
    }
    {
      const ArenaLease nested(2);  // a run started inside this one (a callback's)
      EXPECT_NE(&nested.arena(), &run.arena());
      const RunArenaScope in_nested(nested);
      EXPECT_EQ(&run_arena(2).arena(), &nested.arena());
    }
    EXPECT_EQ(&run_arena(2).arena(), &run.arena());  // the outer scope is back
  }
  EXPECT_NE(&run_arena(2).arena(), &run.arena());  // outside a run: a lease of its own
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
  const std::size_t arenas = arenas_made(2);
  for (int i = 0; i < 500; ++i) ASSERT_EQ(run_contraction(mesh, o).status, RunStatus::Completed);
  const long grown = resident_kib() - before;
  EXPECT_LT(grown, 2048) << "KiB grown over 500 runs";
  EXPECT_EQ(arenas_made(2), arenas) << "runs one after another reuse their arenas";
}

// Runs on several threads at once each lease an arena of their thread count; each must still
// give the bytes it gives alone, and the pool holds no more arenas than runs ran at once (the
// coloured order's results do not depend on which thread runs which chunk, and the collision step's
// background task is waited for by its own run).
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
  const std::size_t arenas = arenas_made(2);
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
  EXPECT_LE(arenas_made(2), arenas + options.size());
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
