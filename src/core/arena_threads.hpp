// The thread count of a TBB arena for a run's `threads` option, and the arena of that count.
#pragma once

#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>
#include <memory>

#include "core/usable_cpus.hpp"

namespace shellcontract {

/// 0: the CPUs this process may use (usable_cpus: its affinity held to its cgroup's CPU quota;
/// TBB's automatic count is the affinity's alone, so a container given 2 CPUs of a 64-core host
/// ran 64 threads). A count above that is held to it: more threads than a quota allows only
/// share its time, and above the affinity's TBB would run no more workers anyway, but asked for
/// more it prints a warning of its own ("TBB Warning: The number of workers is currently limited
/// ...") that no front end can keep quiet (-q). Raising TBB's limit instead (global_control)
/// starts the extra threads, and a worker that starts another cannot report a refused
/// pthread_create as an error: the process aborts when memory is short
/// (tests/cli/test_cli_out_of_memory.cpp). The results do not depend on the count.
inline int arena_threads(int requested) {
  return requested <= 0 ? usable_cpus() : std::min(requested, usable_cpus());
}

/// A run's task arena of arena_threads(requested) threads, leased from the process's pool for
/// the run alone (its planning and the Simulator's construction, its solver, its collision step,
/// its step's own work): copies share the one lease, and the arena goes back to the pool when the
/// last copy is destroyed. A lease takes a free arena of its count, and makes one only when every
/// arena of that count is leased, so the pool holds as many arenas of a count as runs of that
/// count ever ran at once. The arenas are kept, not destroyed: TBB (oneTBB 2021.8) keeps some
/// kilobytes of every arena that ran parallel work after the arena is destroyed, so a program that
/// calls the library thousands of times (a Python loop) grew without bound
/// (tests/sim/test_shared_arena.cpp).
///
/// One run per arena is what keeps a run's observer callbacks on its caller's thread. An arena
/// reserves one slot for external threads (task_arena's default reserved_for_masters = 1; TBB's
/// workers take only the others), and execute() runs the functor on the calling thread when it
/// takes a free slot; only when every slot is taken does TBB hand the functor to a thread already
/// in the arena and wait. Runs that shared an arena of their count did: while one run held the
/// reserved slot, another run's preparation (its `stage` and `cancelled` callbacks, Python's
/// Ctrl-C check) ran on a TBB worker or on the first run's thread, and waited for that run's work.
/// The only thread that enters a leased arena from outside is its run's caller, one call at a
/// time, so it always finds the reserved slot free (tests/sim/test_run_threads_at_once.cpp).
class ArenaLease {
 public:
  /// Takes a free arena of arena_threads(requested) threads from the pool, or makes one
  /// (initialized here: an arena whose initialization threw std::bad_alloc is not kept, and the
  /// next lease tries again).
  explicit ArenaLease(int requested);
  tbb::task_arena& arena() const { return *arena_; }
  /// arena_threads(requested): the arena's max_concurrency.
  int threads() const { return threads_; }

 private:
  int threads_;
  std::shared_ptr<tbb::task_arena> arena_;
};

/// For a part of a run (the Simulator, the solver, the collision Workers): the lease of the run
/// being built on this thread (a RunArenaScope's) if it has this thread count, else a lease of
/// its own (a part made alone, as tests do).
ArenaLease run_arena(int requested);

/// While it lives, run_arena on this thread shares `lease`: the run's parts, made in its
/// preparation, work in the run's arena. Scopes nest (a callback that starts a run of its own
/// gets its own lease and scope; the outer one is back when it ends).
class RunArenaScope {
 public:
  explicit RunArenaScope(const ArenaLease& lease);
  ~RunArenaScope();
  RunArenaScope(const RunArenaScope&) = delete;
  RunArenaScope& operator=(const RunArenaScope&) = delete;

 private:
  const ArenaLease* outer_;
};

/// Tests only: a function that a lease calls right after it made a new arena, with the pool's
/// mutex held (nullptr: none).
using ArenaMadeHook = void (*)();
void set_arena_made_hook(ArenaMadeHook hook);

/// How many arenas of arena_threads(requested) threads the pool has made so far (leased or free):
/// the most runs of that count at once, for tests of the bound.
std::size_t arenas_made(int requested);

}  // namespace shellcontract
