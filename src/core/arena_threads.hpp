// The thread count of a TBB arena for a run's `threads` option, and the arena of that count.
#pragma once

#include <tbb/task_arena.h>

#include <algorithm>

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

/// The process's arena of arena_threads(requested) threads, made at its first use and kept once
/// TBB has initialized it (std::bad_alloc passes, and the next call tries again): a run
/// (its planning and the Simulator's construction, its solver, its collision step, its step's own
/// work) works in it instead of arenas of its own. TBB (oneTBB 2021.8) keeps some kilobytes of
/// every arena that ran parallel work after the arena is destroyed, so a program that calls the
/// library thousands of times (a Python loop) grew without bound (tests/sim/test_shared_arena.cpp).
/// Runs on several threads at once may share one: an arena takes work from several threads, and
/// neither the results nor the colour schedule's progress depend on which thread runs which task
/// (colour_schedule.hpp).
tbb::task_arena& shared_arena(int requested);

}  // namespace shellcontract
